#pragma once
// The 6 x R x R cube-map lattice of lighting directions (docs/design.md section 3).
// Face order +X, -X, +Y, -Y, +Z, -Z; within a face the OpenGL major-axis (s, t)
// table, used literally; texel j = face*R*R + row*R + col.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/vectors.h"

namespace acpca {

/// A texel's address on the cube.
struct TexelCoord {
  int face = 0;
  int row = 0;
  int col = 0;
};

/// One of the (up to) four texels a bilinear lookup blends, with its weight.
struct BilinearTap {
  int texel = 0;
  double weight = 0.0;
};

class CubeLattice {
 public:
  static constexpr int kFaces = 6;
  static constexpr int kMaxResolution = 1024;

  /// Throws UserError unless 1 <= resolution <= kMaxResolution.
  explicit CubeLattice(int resolution);

  int resolution() const { return resolution_; }
  /// Number of texels, 6 R^2 (the l of the paper).
  int size() const { return kFaces * resolution_ * resolution_; }

  int texelIndex(const TexelCoord& c) const {
    return (c.face * resolution_ + c.row) * resolution_ + c.col;
  }
  TexelCoord texelCoord(int texel) const;

  /// Normalised direction through the texel's centre.
  const Vec3& direction(int texel) const { return directions_[texel]; }
  /// Exact solid angle of the texel (not 4 pi / l).
  double solidAngle(int texel) const { return solidAngles_[texel]; }
  const std::vector<double>& solidAngles() const { return solidAngles_; }

  /// The texel whose footprint contains direction d (d need not be normalised).
  /// Inline: the lighting of every map pixel of every frame goes through it.
  int texelOf(const Vec3& d) const {
    int face;
    double sc, tc;
    faceCoordinates(d, face, sc, tc);
    const auto cell = [&](double c) {
      const int i = static_cast<int>(std::floor((c + 1) * 0.5 * resolution_));
      return std::clamp(i, 0, resolution_ - 1);  // c = +1 exactly belongs to the last texel
    };
    return texelIndex({face, cell(tc), cell(sc)});
  }

  /// texelOf for `count` directions given as coordinate arrays, into texels:
  /// the same operations without branches, so the loop runs in SIMD lanes (a
  /// lat-long map integrated under a rotation sends every map cell through it).
  void texelsOf(const double* x, const double* y, const double* z, int count, int* texels) const;

  /// Bilinear interpolation weights between texel centres, continuous across face
  /// seams: taps that fall off the face are moved to the neighbouring face.
  std::array<BilinearTap, 4> bilinearTaps(const Vec3& d) const;
  /// Bilinear lookup of one value per texel.
  double bilinear(const std::vector<double>& values, const Vec3& d) const;

  /// Unnormalised direction for face coordinates sc, tc in [-1, 1] (inverse of the
  /// OpenGL table; values outside [-1, 1] extend the face plane).
  static Vec3 faceDirection(int face, double sc, double tc);
  /// Face and face coordinates (sc, tc in [-1, 1]) of a direction.
  static void faceCoordinates(const Vec3& d, int& face, double& sc, double& tc) {
    const double ax = std::abs(d.x()), ay = std::abs(d.y()), az = std::abs(d.z());
    double ma;
    if (ax >= ay && ax >= az) {
      ma = ax;
      face = d.x() >= 0 ? 0 : 1;
      sc = d.x() >= 0 ? -d.z() : d.z();
      tc = -d.y();
    } else if (ay >= az) {
      ma = ay;
      face = d.y() >= 0 ? 2 : 3;
      sc = d.x();
      tc = d.y() >= 0 ? d.z() : -d.z();
    } else {
      ma = az;
      face = d.z() >= 0 ? 4 : 5;
      sc = d.z() >= 0 ? d.x() : -d.x();
      tc = -d.y();
    }
    if (!(ma > 0 && std::isfinite(ma))) refuseDirection(d);
    sc /= ma;
    tc /= ma;
  }
  /// Exact solid angle of the face-plane rectangle [x0, x1] x [y0, y1] (unit cube).
  static double rectangleSolidAngle(double x0, double y0, double x1, double y1);

 private:
  [[noreturn]] static void refuseDirection(const Vec3& d);  ///< one without a major axis

  int resolution_;
  std::vector<Vec3> directions_;
  std::vector<double> solidAngles_;
};

}  // namespace acpca
