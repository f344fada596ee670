#pragma once
// The lighting vector of one frame: an environment, rotated, integrated onto the
// lattice (radiance x solid angle per texel, RGB).
#include "lighting/environment.h"
#include "lighting/rotation.h"

namespace acpca {

enum class RotationMode {
  /// Resample the source map under the rotation: energy kept at every angle.
  Exact,
  /// [Nowrouzezahrai07]'s fast path: rotate the lattice and look up the unrotated lattice
  /// bilinearly. Cheap, but loses or gains energy of small bright features.
  FastLattice,
};

LatticeLighting computeLighting(const Environment& env, const CubeLattice& lattice,
                                const EnvRotation& rotation,
                                RotationMode mode = RotationMode::Exact);
/// computeLighting under each rotation, the same values, made together
/// where the map can (Environment::integrateMany).
std::vector<LatticeLighting> computeLightings(const Environment& env, const CubeLattice& lattice,
                                              const std::vector<EnvRotation>& rotations,
                                              RotationMode mode = RotationMode::Exact);

/// Radiance of each texel (lighting / solid angle), RGB.
std::vector<double> latticeRadiance(const LatticeLighting& lighting, const CubeLattice& lattice);
/// Sum of the lighting over all texels, per channel (the map's energy).
Rgb totalEnergy(const LatticeLighting& lighting);

}  // namespace acpca
