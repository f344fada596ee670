#include "lighting/sh_lighting.h"

#include <tbb/parallel_for.h>

#include <vector>

#include "core/error.h"

namespace acpca {

std::array<double, 9> realSh9(const Vec3& d) {
  const double x = d.x(), y = d.y(), z = d.z();
  // sqrt(1 / 4 pi), sqrt(3 / 4 pi), sqrt(15 / 4 pi), sqrt(5 / 16 pi), sqrt(15 / 16 pi)
  constexpr double c0 = 0.28209479177387814, c1 = 0.4886025119029199, c2 = 1.0925484305920792,
                   c3 = 0.31539156525252005, c4 = 0.5462742152960396;
  return {c0,
          c1 * y,
          c1 * z,
          c1 * x,
          c2 * x * y,
          c2 * y * z,
          c3 * (3 * z * z - 1),
          c2 * x * z,
          c4 * (x * x - y * y)};
}

ShProjector::ShProjector(const CubeLattice& lattice) : meanY_(lattice.size()) {
  constexpr int kCells = 16;
  const int r = lattice.resolution();
  const double step = 2.0 / r, cell = step / kCells;
  const auto corner = [&](int index, int sub) { return -1 + index * step + sub * cell; };
  // A cell's solid angle depends on its place on a face, not on the face:
  // found once for one face (most of the work: four atan2 a cell), and the
  // texels on all cores, each summed in the same order as before.
  std::vector<double> cellAngle(static_cast<size_t>(r) * r * kCells * kCells);
  tbb::parallel_for(0, r * r, [&](int place) {
    const int row = place / r, col = place % r;
    for (int i = 0; i < kCells; ++i)
      for (int k = 0; k < kCells; ++k) {
        const double s0 = corner(col, k), t0 = corner(row, i);
        cellAngle[(static_cast<size_t>(place) * kCells + i) * kCells + k] =
            CubeLattice::rectangleSolidAngle(s0, t0, s0 + cell, t0 + cell);
      }
  });
  tbb::parallel_for(0, lattice.size(), [&](int texel) {
    const TexelCoord t = lattice.texelCoord(texel);
    const double* angle = &cellAngle[static_cast<size_t>(t.row * r + t.col) * kCells * kCells];
    std::array<double, 9> sum{};
    double area = 0;
    for (int i = 0; i < kCells; ++i)
      for (int k = 0; k < kCells; ++k) {
        const double s0 = corner(t.col, k), t0 = corner(t.row, i);
        const double w = angle[i * kCells + k];
        const auto y = realSh9(
            CubeLattice::faceDirection(t.face, s0 + 0.5 * cell, t0 + 0.5 * cell).normalized());
        for (int b = 0; b < 9; ++b) sum[b] += w * y[b];
        area += w;
      }
    for (int b = 0; b < 9; ++b) meanY_[texel][b] = sum[b] / area;
  });
}

ShProjector::ShProjector(const DomainLighting& domain) : ShProjector(domain.mapLattice()) {
  const LightCells* cells = domain.cells();
  if (!cells) return;
  // Each cell's mean Y: its texels' means weighted by the solid angle each
  // gives the cell.
  const CubeLattice& fine = cells->lattice();
  std::vector<std::array<double, 9>> sum(cells->cells(), std::array<double, 9>{});
  std::vector<double> area(cells->cells(), 0.0);
  for (int j = 0; j < fine.size(); ++j)
    for (const LightCells::Share* s = cells->begin(j); s != cells->end(j); ++s) {
      const double w = s->fraction * fine.solidAngle(j);
      for (int b = 0; b < 9; ++b) sum[s->cell][b] += w * meanY_[j][b];
      area[s->cell] += w;
    }
  meanY_.assign(cells->cells(), std::array<double, 9>{});
  for (int k = 0; k < cells->cells(); ++k)
    if (area[k] > 0)
      for (int b = 0; b < 9; ++b) meanY_[k][b] = sum[k][b] / area[k];
}

std::array<Rgb, 9> ShProjector::project(const LatticeLighting& lighting) const {
  ACPCA_CHECK(lighting.size() == 3 * meanY_.size(), "lighting of ", lighting.size() / 3,
              " texels for a lattice of ", meanY_.size());
  std::array<Rgb, 9> out;
  out.fill(Rgb::Zero());
  for (size_t texel = 0; texel < meanY_.size(); ++texel) {
    const Rgb value(lighting[3 * texel], lighting[3 * texel + 1], lighting[3 * texel + 2]);
    for (int b = 0; b < 9; ++b) out[b] += meanY_[texel][b] * value;
  }
  return out;
}

}  // namespace acpca
