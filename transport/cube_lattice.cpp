#include "transport/cube_lattice.h"

#include <cmath>
#include <limits>

#include "core/error.h"

namespace acpca {

namespace {
// Solid angle subtended by [0, x] x [0, y] on the plane at distance 1.
double cornerArea(double x, double y) {
  return std::atan2(x * y, std::sqrt(x * x + y * y + 1));
}
}  // namespace

CubeLattice::CubeLattice(int resolution) : resolution_(resolution) {
  if (resolution < 1 || resolution > kMaxResolution)
    throw UserError(
        concat("cube-map resolution ", resolution, " is out of range 1..", kMaxResolution));
  const int n = size();
  directions_.resize(n);
  solidAngles_.resize(n);
  const double step = 2.0 / resolution;
  for (int face = 0; face < kFaces; ++face)
    for (int row = 0; row < resolution; ++row)
      for (int col = 0; col < resolution; ++col) {
        const double s0 = -1 + col * step, t0 = -1 + row * step;
        const int j = texelIndex({face, row, col});
        directions_[j] = faceDirection(face, s0 + 0.5 * step, t0 + 0.5 * step).normalized();
        solidAngles_[j] = rectangleSolidAngle(s0, t0, s0 + step, t0 + step);
      }
}

double CubeLattice::rectangleSolidAngle(double x0, double y0, double x1, double y1) {
  return cornerArea(x1, y1) - cornerArea(x0, y1) - cornerArea(x1, y0) + cornerArea(x0, y0);
}

TexelCoord CubeLattice::texelCoord(int texel) const {
  ACPCA_CHECK(texel >= 0 && texel < size(), "texel ", texel, " of ", size());
  const int r2 = resolution_ * resolution_;
  return {texel / r2, (texel % r2) / resolution_, texel % resolution_};
}

Vec3 CubeLattice::faceDirection(int face, double sc, double tc) {
  switch (face) {
    case 0:
      return {1, -tc, -sc};  // +X: sc = -z, tc = -y
    case 1:
      return {-1, -tc, sc};  // -X: sc = +z, tc = -y
    case 2:
      return {sc, 1, tc};  // +Y: sc = +x, tc = +z
    case 3:
      return {sc, -1, -tc};  // -Y: sc = +x, tc = -z
    case 4:
      return {sc, -tc, 1};  // +Z: sc = +x, tc = -y
    default:
      return {-sc, -tc, -1};  // -Z: sc = -x, tc = -y
  }
}

void CubeLattice::refuseDirection(const Vec3& d) {
  failCheck("ma > 0 && std::isfinite(ma)", __FILE__, __LINE__,
            concat("direction has no major axis: ", d.transpose()));
}

void CubeLattice::texelsOf(const double* __restrict x, const double* __restrict y,
                           const double* __restrict z, int count, int* __restrict texels) const {
  // faceCoordinates and texelOf's cell, written as selects: each value is made
  // by the same IEEE operations, so every texel equals texelOf's.
  const double r = resolution_, last = resolution_ - 1;
  bool allFinite = true;
  for (int i = 0; i < count; ++i) {
    const double ax = std::abs(x[i]), ay = std::abs(y[i]), az = std::abs(z[i]);
    const bool xMajor = ax >= ay && ax >= az, yMajor = !xMajor && ay >= az;
    const double ma = xMajor ? ax : yMajor ? ay : az;
    const double face = xMajor   ? (x[i] >= 0 ? 0 : 1)
                        : yMajor ? (y[i] >= 0 ? 2 : 3)
                                 : (z[i] >= 0 ? 4 : 5);
    const double sc = xMajor   ? (x[i] >= 0 ? -z[i] : z[i])
                      : yMajor ? x[i]
                               : (z[i] >= 0 ? x[i] : -x[i]);
    const double tc = yMajor ? (y[i] >= 0 ? z[i] : -z[i]) : -y[i];
    allFinite &= ma > 0 && ma <= std::numeric_limits<double>::max();
    // Small integers are exact in doubles: the index is formed there and
    // converted once.
    const double row = std::clamp(std::floor((tc / ma + 1) * 0.5 * r), 0.0, last);
    const double col = std::clamp(std::floor((sc / ma + 1) * 0.5 * r), 0.0, last);
    texels[i] = static_cast<int>((face * r + row) * r + col);
  }
  if (!allFinite)
    for (int i = 0; i < count; ++i) texels[i] = texelOf(Vec3(x[i], y[i], z[i]));  // throws
}

std::array<BilinearTap, 4> CubeLattice::bilinearTaps(const Vec3& d) const {
  int face;
  double sc, tc;
  faceCoordinates(d, face, sc, tc);
  // Continuous texel coordinates with texel centres at integers.
  const double u = (sc + 1) * 0.5 * resolution_ - 0.5;
  const double v = (tc + 1) * 0.5 * resolution_ - 0.5;
  const int c0 = static_cast<int>(std::floor(u)), r0 = static_cast<int>(std::floor(v));
  const double fu = u - c0, fv = v - r0;
  std::array<BilinearTap, 4> taps;
  const auto inside = [&](int i) { return i >= 0 && i < resolution_; };
  int k = 0, corner = -1;
  for (int dr = 0; dr <= 1; ++dr)
    for (int dc = 0; dc <= 1; ++dc) {
      const int row = r0 + dr, col = c0 + dc;
      const double w = (dc ? fu : 1 - fu) * (dr ? fv : 1 - fv);
      if (inside(row) && inside(col)) {
        taps[k++] = {texelIndex({face, row, col}), w};
      } else if (inside(row) || inside(col)) {
        // Off the face: take the texel just across the seam, in the same row (or
        // column) as the tap, so both sides of a seam blend the same texels.
        const double step = 2.0 / resolution_, beyond = 1 + 1e-6;
        const auto across = [&](int i) {
          return i < 0 ? -beyond : i >= resolution_ ? beyond : -1 + (i + 0.5) * step;
        };
        taps[k++] = {texelOf(faceDirection(face, across(col), across(row))), w};
      } else {
        corner = k;  // off both edges: no texel there, three meet at a cube corner
        taps[k++] = {0, w};
      }
    }
  if (corner >= 0) {
    // The missing fourth value is the mean of the three texels that meet at the
    // corner, as seamless cube-map filtering does; it is the same seen from any face.
    const double share = taps[corner].weight / 3;
    for (int i = 0; i < 4; ++i)
      if (i != corner) taps[i].weight += share;
    taps[corner] = {taps[corner == 0 ? 1 : 0].texel, 0.0};
  }
  return taps;
}

double CubeLattice::bilinear(const std::vector<double>& values, const Vec3& d) const {
  ACPCA_CHECK(static_cast<int>(values.size()) == size(), "values ", values.size(), " vs ", size());
  double sum = 0;
  for (const auto& tap : bilinearTaps(d)) sum += tap.weight * values[tap.texel];
  return sum;
}

}  // namespace acpca
