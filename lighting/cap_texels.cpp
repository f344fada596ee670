#include "lighting/cap_texels.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace acpca {

namespace {

constexpr double kPi = std::numbers::pi;

/// The four great circles bounding a texel, as inward unit normals: a
/// direction w lies in the texel when every n . w >= 0, and a cap of angular
/// radius alpha around w lies in it when every n . w >= sin(alpha).
std::array<Vec3, 4> texelBoundaryNormals(const CubeLattice& lattice, int texel) {
  const TexelCoord t = lattice.texelCoord(texel);
  const double step = 2.0 / lattice.resolution();
  const double s0 = -1 + t.col * step, s1 = s0 + step, t0 = -1 + t.row * step, t1 = t0 + step;
  const Vec3 centre = lattice.direction(texel);
  const auto plane = [&](const Vec3& a, const Vec3& b) {
    Vec3 n = a.cross(b).normalized();
    return n.dot(centre) >= 0 ? n : Vec3(-n);
  };
  const auto at = [&](double s, double tt) { return CubeLattice::faceDirection(t.face, s, tt); };
  return {plane(at(s0, t0), at(s0, t1)), plane(at(s1, t0), at(s1, t1)),
          plane(at(s0, t0), at(s1, t0)), plane(at(s0, t1), at(s1, t1))};
}

/// Per face, the box (s min, s max, t min, t max) of face coordinates a cap
/// covers there: its rim's points, its centre and the face corners inside it
/// (a face it misses has s min > s max).
using FaceBoxes = std::array<std::array<double, 4>, 6>;
FaceBoxes capFaceBoxes(const Vec3& axis, double cosAlpha, double sinAlpha, int rimPoints) {
  FaceBoxes box;
  for (auto& b : box) b = {2, -2, 2, -2};
  const auto addPoint = [&](int face, double s, double t) {
    auto& b = box[face];
    b = {std::min(b[0], s), std::max(b[1], s), std::min(b[2], t), std::max(b[3], t)};
  };
  const auto add = [&](const Vec3& d) {
    int face;
    double s, t;
    CubeLattice::faceCoordinates(d, face, s, t);
    addPoint(face, s, t);
  };
  add(axis);
  const Vec3 helper = std::abs(axis.y()) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  const Vec3 u = axis.cross(helper).normalized(), v = axis.cross(u);
  for (int i = 0; i < rimPoints; ++i) {
    const double phi = 2 * kPi * i / rimPoints;
    add(cosAlpha * axis + sinAlpha * (std::cos(phi) * u + std::sin(phi) * v));
  }
  for (int face = 0; face < 6; ++face)
    for (double s : {-1.0, 1.0})
      for (double t : {-1.0, 1.0})
        if (CubeLattice::faceDirection(face, s, t).normalized().dot(axis) >= cosAlpha)
          addPoint(face, s, t);
  // Where the rim leaves a face between two of its points the cap runs on to
  // the edge: widen by a rim step (an angle, stretched at most 3x on a face).
  const double margin = 3 * 2 * kPi * sinAlpha / rimPoints;
  for (auto& b : box)
    if (b[0] <= b[1]) b = {b[0] - margin, b[1] + margin, b[2] - margin, b[3] + margin};
  return box;
}

/// Cells of a face's texel grid `perSide` to a side covering `box`, one cell wider.
template <typename Visit>
void cellsOver(const std::array<double, 4>& box, int perSide, Visit&& visit) {
  const double step = 2.0 / perSide;
  const auto cell = [&](double c) {
    return std::clamp(static_cast<int>(std::floor((c + 1) / step)), 0, perSide - 1);
  };
  for (int row = std::max(0, cell(box[2]) - 1); row <= std::min(perSide - 1, cell(box[3]) + 1);
       ++row)
    for (int col = std::max(0, cell(box[0]) - 1); col <= std::min(perSide - 1, cell(box[1]) + 1);
         ++col)
      visit(row, col, -1 + col * step, -1 + row * step, step);
}

/// A cap up to a couple of texels across on a grid of cells about alpha / 12
/// wide that divides every texel (so texel edges are cell edges): each cell
/// whose centre is inside adds its solid angle, area / (1 + s^2 + t^2)^(3/2),
/// to its texel.
void capByCells(const CubeLattice& lattice, const Vec3& axis, double cosAlpha, double sinAlpha,
                double alpha, double texelAngle, std::vector<LightTap>& taps) {
  const int res = lattice.resolution();
  const int perTexel = std::clamp(static_cast<int>(std::ceil(12 * texelAngle / alpha)), 3, 64);
  const FaceBoxes box = capFaceBoxes(axis, cosAlpha, sinAlpha, 128);
  const double cos2 = cosAlpha * cosAlpha;
  const size_t start = taps.size();
  for (int face = 0; face < 6; ++face) {
    if (box[face][0] > box[face][1]) continue;
    cellsOver(box[face], res * perTexel, [&](int row, int col, double s0, double t0, double step) {
      const double s = s0 + 0.5 * step, t = t0 + 0.5 * step, r2 = 1 + s * s + t * t;
      const double along = CubeLattice::faceDirection(face, s, t).dot(axis);
      if (along <= 0 || along * along < cos2 * r2) return;
      const int texel = lattice.texelIndex({face, row / perTexel, col / perTexel});
      const double solidAngle = step * step / (r2 * std::sqrt(r2));
      auto tap = std::find_if(taps.begin() + start, taps.end(),
                              [&](const LightTap& x) { return x.texel == texel; });
      if (tap == taps.end())
        taps.push_back({texel, solidAngle});
      else
        tap->weight += solidAngle;
    });
  }
}

/// A large cap texel by texel: texels whose corners are all inside take their
/// exact solid angle, texels on its rim the solid angle of the 8x8 sub-cells
/// whose centres are inside.
void capByTexels(const CubeLattice& lattice, const Vec3& axis, double cosAlpha, double sinAlpha,
                 std::vector<LightTap>& taps) {
  const auto inside = [&](const Vec3& d) { return d.normalized().dot(axis) >= cosAlpha; };
  const FaceBoxes box = capFaceBoxes(axis, cosAlpha, sinAlpha, 256);
  constexpr int kSub = 8;
  for (int face = 0; face < 6; ++face) {
    if (box[face][0] > box[face][1]) continue;
    cellsOver(box[face], lattice.resolution(),
              [&](int row, int col, double s0, double t0, double step) {
                const int texel = lattice.texelIndex({face, row, col});
                int cornersInside = 0;
                for (int corner = 0; corner < 4; ++corner)
                  cornersInside += inside(CubeLattice::faceDirection(face, s0 + (corner & 1) * step,
                                                                     t0 + (corner >> 1) * step));
                if (cornersInside == 4) {  // a cap under 90 degrees is convex: all inside
                  taps.push_back({texel, lattice.solidAngle(texel)});
                  return;
                }
                double covered = 0;
                const double sub = step / kSub;
                for (int a = 0; a < kSub; ++a)
                  for (int c = 0; c < kSub; ++c) {
                    const double s = s0 + (c + 0.5) * sub, t = t0 + (a + 0.5) * sub;
                    if (!inside(CubeLattice::faceDirection(face, s, t))) continue;
                    covered += CubeLattice::rectangleSolidAngle(s - 0.5 * sub, t - 0.5 * sub,
                                                                s + 0.5 * sub, t + 0.5 * sub);
                  }
                if (covered > 0) taps.push_back({texel, covered});
              });
  }
}

}  // namespace

void appendCapShares(const CubeLattice& lattice, const Vec3& axis, double sinAlpha,
                     std::vector<LightTap>& taps) {
  const double cosAlpha = std::sqrt(std::max(0.0, 1 - sinAlpha * sinAlpha));
  const double alpha = std::asin(sinAlpha);
  const double texelAngle = 0.5 * kPi / lattice.resolution();

  const int centreTexel = lattice.texelOf(axis);
  // A disc under a microradian (fuzzing found one at 1e-10) is a point: the
  // cell grid cannot resolve it, and its texel holds it to 1e-6 of a texel.
  if (!(alpha > 1e-6)) {
    taps.push_back({centreTexel, 1.0});
    return;
  }
  if (alpha < texelAngle) {
    const auto normals = texelBoundaryNormals(lattice, centreTexel);
    if (std::all_of(normals.begin(), normals.end(),
                    [&](const Vec3& n) { return n.dot(axis) >= sinAlpha; })) {
      taps.push_back({centreTexel, 1.0});  // the whole disc in one texel: exact
      return;
    }
  }
  const size_t start = taps.size();
  if (alpha <= 2 * texelAngle)
    capByCells(lattice, axis, cosAlpha, sinAlpha, alpha, texelAngle, taps);
  else
    capByTexels(lattice, axis, cosAlpha, sinAlpha, taps);
  double sum = 0;
  for (size_t i = start; i < taps.size(); ++i) sum += taps[i].weight;
  if (!(sum > 0)) {
    taps.resize(start);
    taps.push_back({centreTexel, 1.0});
    return;
  }
  for (size_t i = start; i < taps.size(); ++i) taps[i].weight /= sum;
}

}  // namespace acpca
