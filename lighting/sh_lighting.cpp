#include "lighting/sh_lighting.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/error.h"

namespace acpca {

namespace {

/// The nine real SH bands summed over weighted directions, from their
/// moments: w the weights' sum, first the sum of w d, second of w d d^T.
/// Each band is a polynomial of degree at most 2 in d.
std::array<double, 9> sh9OfMoments(double w, const Vec3& first, const Eigen::Matrix3d& second) {
  const auto [c0, c1, c2, c3, c4] = kSh9Normalisations;
  return {c0 * w,
          c1 * first.y(),
          c1 * first.z(),
          c1 * first.x(),
          c2 * second(0, 1),
          c2 * second(1, 2),
          c3 * (3 * second(2, 2) - w),
          c2 * second(0, 2),
          c4 * (second(0, 0) - second(1, 1))};
}

}  // namespace

std::array<double, 9> realSh9(const Vec3& d) {
  return sh9OfMoments(1, d, d * d.transpose());
}

std::vector<std::array<double, 9>> texelSh9Means(const CubeLattice& lattice, bool threads) {
  std::vector<std::array<double, 9>> meanY(lattice.size());
  constexpr int kCells = 16;
  const int r = lattice.resolution();
  const double step = 2.0 / r, cell = step / kCells;
  const auto corner = [&](int index, int sub) { return -1 + index * step + sub * cell; };
  // Every Y is a polynomial of degree 2 in the direction, and each face is
  // the same square turned by a signed permutation A (faceDirection): so a
  // place on a face needs only its cells' weighted moments of n = (s, t, 1)
  // / |(s, t, 1)|, found once for all six faces: the sum of w, of w n and of
  // w n n^T (16 x 16 cells of exact solid angle w), then each face's sums
  // of w Y through d = A n.
  struct Moments {
    double w = 0;
    Vec3 first = Vec3::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  };
  std::vector<Moments> places(static_cast<size_t>(r) * r);
  const auto addPlace = [&](int place) {
    const int row = place / r, col = place % r;
    Moments& m = places[place];
    for (int i = 0; i < kCells; ++i)
      for (int k = 0; k < kCells; ++k) {
        const double s0 = corner(col, k), t0 = corner(row, i);
        const double w = CubeLattice::rectangleSolidAngle(s0, t0, s0 + cell, t0 + cell);
        const Vec3 n = Vec3(s0 + 0.5 * cell, t0 + 0.5 * cell, 1).normalized();
        m.w += w;
        m.first += w * n;
        m.second += w * n * n.transpose();
      }
  };
  if (threads)
    tbb::parallel_for(0, r * r, addPlace);
  else
    for (int place = 0; place < r * r; ++place) addPlace(place);
  for (int texel = 0; texel < lattice.size(); ++texel) {
    const TexelCoord t = lattice.texelCoord(texel);
    const Vec3 origin = CubeLattice::faceDirection(t.face, 0, 0);
    Eigen::Matrix3d a;
    a << CubeLattice::faceDirection(t.face, 1, 0) - origin,
        CubeLattice::faceDirection(t.face, 0, 1) - origin, origin;
    const Moments& m = places[static_cast<size_t>(t.row) * r + t.col];
    const std::array<double, 9> sum = sh9OfMoments(m.w, a * m.first, a * m.second * a.transpose());
    for (int b = 0; b < 9; ++b) meanY[texel][b] = sum[b] / m.w;
  }
  return meanY;
}

ShProjector::ShProjector(const CubeLattice& lattice) : meanY_(texelSh9Means(lattice)) {}

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

std::array<Rgb, 9> projectDisc(const MapSource& disc) {
  const double a = disc.radius, sin2 = std::sin(a) * std::sin(a);
  const double band[3] = {disc.solidAngle(), std::numbers::pi * sin2,
                          std::numbers::pi * std::cos(a) * sin2};
  const std::array<double, 9> y = realSh9(disc.direction.normalized());
  std::array<Rgb, 9> c;
  for (int k = 0; k < 9; ++k) c[k] = disc.radiance * (y[k] * band[k == 0 ? 0 : k < 4 ? 1 : 2]);
  return c;
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
