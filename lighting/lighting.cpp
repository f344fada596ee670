#include "lighting/lighting.h"

#include "core/error.h"

namespace acpca {

std::vector<double> latticeRadiance(const LatticeLighting& lighting, const CubeLattice& lattice) {
  std::vector<double> radiance(lighting.size());
  for (int j = 0; j < lattice.size(); ++j)
    for (int c = 0; c < 3; ++c) radiance[3 * j + c] = lighting[3 * j + c] / lattice.solidAngle(j);
  return radiance;
}

Rgb totalEnergy(const LatticeLighting& lighting) {
  Rgb sum = Rgb::Zero();
  for (size_t k = 0; k < lighting.size(); ++k) sum[k % 3] += lighting[k];
  return sum;
}

LatticeLighting computeLighting(const Environment& env, const CubeLattice& lattice,
                                const EnvRotation& rotation, RotationMode mode) {
  LatticeLighting lighting(3 * static_cast<size_t>(lattice.size()), 0.0);
  if (mode == RotationMode::Exact || rotation.isIdentity()) {
    env.integrate(lattice, rotationMatrix(rotation), lighting);
    return lighting;
  }
  // Fast path: texel j of the rotated map shows the unrotated lattice at R^T d_j.
  LatticeLighting unrotated(lighting.size(), 0.0);
  env.integrate(lattice, Eigen::Matrix3d::Identity(), unrotated);
  const std::vector<double> radiance = latticeRadiance(unrotated, lattice);
  const Eigen::Matrix3d inverse = rotationMatrix(rotation).transpose();
  for (int j = 0; j < lattice.size(); ++j) {
    Rgb value = Rgb::Zero();
    for (const auto& tap : lattice.bilinearTaps(inverse * lattice.direction(j)))
      value += tap.weight * Rgb(radiance[3 * tap.texel], radiance[3 * tap.texel + 1],
                                radiance[3 * tap.texel + 2]);
    for (int c = 0; c < 3; ++c) lighting[3 * j + c] = value[c] * lattice.solidAngle(j);
  }
  return lighting;
}

std::vector<LatticeLighting> computeLightings(const Environment& env, const CubeLattice& lattice,
                                              const std::vector<EnvRotation>& rotations,
                                              RotationMode mode) {
  std::vector<LatticeLighting> lightings(rotations.size());
  std::vector<Eigen::Matrix3d> exact;
  std::vector<LatticeLighting*> onto;
  for (size_t k = 0; k < rotations.size(); ++k)
    if (mode == RotationMode::Exact || rotations[k].isIdentity()) {
      lightings[k].assign(3 * static_cast<size_t>(lattice.size()), 0.0);
      exact.push_back(rotationMatrix(rotations[k]));
      onto.push_back(&lightings[k]);
    } else {
      lightings[k] = computeLighting(env, lattice, rotations[k], mode);
    }
  env.integrateMany(lattice, exact, onto);
  return lightings;
}

}  // namespace acpca
