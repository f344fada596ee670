#include "lighting/domain_lighting.h"

#include "core/error.h"

namespace acpca {

DomainLighting::DomainLighting(const TransportHeader& header) : size_(header.latticeSize()) {
  if (!header.isLightSet()) {
    lattice_ = std::make_unique<CubeLattice>(header.cubemapResolution);
    return;
  }
  const LightSet& lights = header.lights;
  // Given cells are integrated over the Voronoi cells of the directions,
  // then scaled to the given solid angles (the mean radiance of the nearest
  // directions times the cell the file names).
  const bool given = lights.cells == CellSource::Given;
  cells_ = std::make_unique<LightCells>(lights.directions, given ? 180.0 : lights.capDegrees);
  const std::vector<double> voronoi = cells_->solidAngles();
  cellSolidAngles_ = given ? lights.solidAngles : voronoi;
  cellScale_.assign(lights.size(), 1.0);
  if (given)
    for (int k = 0; k < lights.size(); ++k)
      cellScale_[k] = voronoi[k] > 0 ? lights.solidAngles[k] / voronoi[k] : 0.0;
}

void DomainLighting::requireRotationMode(bool isLightSet, RotationMode mode) {
  if (isLightSet && mode == RotationMode::FastLattice)
    throw UserError(
        "the fast rotation resamples the cube lattice: a captured light set's lighting is "
        "integrated over its cells again for every rotation (leave --fast-rotation out)");
}

LatticeLighting DomainLighting::operator()(const Environment& env, const EnvRotation& rotation,
                                           RotationMode mode, double* uncoveredShare) const {
  if (uncoveredShare) *uncoveredShare = 0;
  if (lattice_) return computeLighting(env, *lattice_, rotation, mode);
  if (!rotation.isIdentity()) requireRotationMode(true, mode);
  return gatherCells(computeLighting(env, cells_->lattice(), rotation), uncoveredShare);
}

std::vector<LatticeLighting> DomainLighting::lightings(const Environment& env,
                                                       const std::vector<EnvRotation>& rotations,
                                                       RotationMode mode,
                                                       std::vector<double>* uncoveredShares) const {
  if (uncoveredShares) uncoveredShares->assign(rotations.size(), 0.0);
  if (lattice_) return computeLightings(env, *lattice_, rotations, mode);
  for (const EnvRotation& rotation : rotations)
    if (!rotation.isIdentity()) requireRotationMode(true, mode);
  std::vector<LatticeLighting> made = computeLightings(env, cells_->lattice(), rotations);
  for (size_t k = 0; k < made.size(); ++k)
    made[k] = gatherCells(made[k], uncoveredShares ? &(*uncoveredShares)[k] : nullptr);
  return made;
}

LatticeLighting DomainLighting::gatherCells(const LatticeLighting& fine,
                                            double* uncoveredShare) const {
  LatticeLighting lighting(3 * static_cast<size_t>(size_), 0.0);
  cells_->gather(fine, 3, lighting);
  for (int k = 0; k < size_; ++k)
    for (int c = 0; c < 3; ++c) lighting[3 * k + c] *= cellScale_[k];
  if (uncoveredShare) {
    double all = 0, held = 0;
    for (double v : fine) all += std::abs(v);
    for (double v : lighting) held += std::abs(v);
    // Cells given in the file may hold more than their Voronoi cells did.
    *uncoveredShare = all > 0 ? std::max(0.0, 1 - held / all) : 0.0;
  }
  return lighting;
}

LatticeLighting DomainLighting::mapLighting(const LatticeLighting& lighting) const {
  ACPCA_CHECK(lighting.size() == 3 * static_cast<size_t>(size_), "lighting of ",
              lighting.size() / 3, " columns for ", size_);
  if (lattice_) return lighting;
  const CubeLattice& fine = cells_->lattice();
  LatticeLighting mapped(3 * static_cast<size_t>(fine.size()), 0.0);
  for (int j = 0; j < fine.size(); ++j)
    for (const LightCells::Share* s = cells_->begin(j); s != cells_->end(j); ++s) {
      const double area = cellSolidAngles_[s->cell];
      if (area <= 0) continue;
      for (int c = 0; c < 3; ++c)
        mapped[3 * j + c] += s->fraction * fine.solidAngle(j) * lighting[3 * s->cell + c] / area;
    }
  return mapped;
}

}  // namespace acpca
