#pragma once
// The lighting vector of a file's lighting domain (docs/formats.md): the
// cube lattice's texels, or a captured light set's cells. A cell's lighting
// is the environment's integral over the cell: the map is integrated exactly
// onto a fine cube lattice and each texel's integral shared out among the
// cells by the part of its solid angle each holds, so energy is kept as the
// lattice keeps it and a rotation re-integrates.
#include <memory>
#include <optional>

#include "lighting/lighting.h"
#include "transport/light_set.h"
#include "transport/transport_file.h"

namespace acpca {

class DomainLighting {
 public:
  explicit DomainLighting(const TransportHeader& header);
  /// Columns: texels or lights.
  int size() const { return size_; }
  bool isLightSet() const { return cells_ != nullptr; }
  /// The lattice of a cube-lattice file; null for a light set.
  const CubeLattice* lattice() const { return lattice_.get(); }
  /// The cells of a light set; null for a cube-lattice file.
  const LightCells* cells() const { return cells_.get(); }

  /// The environment under the rotation, integrated onto the domain (RGB per
  /// column). RotationMode::FastLattice is refused for a light set (it
  /// resamples the lattice); `uncoveredShare`, when given, receives the
  /// share of the lighting's energy on directions no cell holds (0 for the
  /// lattice).
  /// Refuses RotationMode::FastLattice for a light set (UserError).
  static void requireRotationMode(bool isLightSet, RotationMode mode);

  LatticeLighting operator()(const Environment& env, const EnvRotation& rotation,
                             RotationMode mode = RotationMode::Exact,
                             double* uncoveredShare = nullptr) const;
  /// The same under each of `rotations`, made together where the map can
  /// (computeLightings); `uncoveredShares`, when given, receives one share
  /// per rotation.
  std::vector<LatticeLighting> lightings(const Environment& env,
                                         const std::vector<EnvRotation>& rotations,
                                         RotationMode mode = RotationMode::Exact,
                                         std::vector<double>* uncoveredShares = nullptr) const;

  /// The lighting drawn on a cube lattice, mapLattice(): a light set's on
  /// its fine lattice, each texel at the radiance of the cell holding it (0
  /// where none does); a cube-lattice file's as it is.
  LatticeLighting mapLighting(const LatticeLighting& lighting) const;
  const CubeLattice& mapLattice() const { return lattice_ ? *lattice_ : cells_->lattice(); }

 private:
  /// A light set's cells' lighting from its fine lattice's.
  LatticeLighting gatherCells(const LatticeLighting& fine, double* uncoveredShare) const;

  int size_ = 0;
  std::unique_ptr<CubeLattice> lattice_;
  std::unique_ptr<LightCells> cells_;
  /// Per cell: given solid angle / the Voronoi cell's (cells given in the file).
  std::vector<double> cellScale_;
  std::vector<double> cellSolidAngles_;
};

}  // namespace acpca
