#pragma once
// Pinhole camera of docs/design.md section 3: image row 0 is the top row, pixel
// centres at (x + 0.5, y + 0.5), vertical field of view in degrees.
#include "transport/cube_lattice.h"

namespace acpca {

/// Image size in pixels.
struct ImageSize {
  int width = 0;
  int height = 0;
  long long pixels() const { return static_cast<long long>(width) * height; }
};

/// Largest image side we accept: refuses absurd sizes before any allocation.
constexpr int kMaxImageSide = 16384;
/// Throws UserError naming `what` unless both sides are in 1..kMaxImageSide.
void validateImageSize(const ImageSize& size, const std::string& what);
/// Parses "WxH" (e.g. 256x256), validated; throws UserError naming `what`.
ImageSize parseImageSize(const std::string& text, const std::string& what);

/// Unit direction of lat-long angles (docs/design.md section 3): theta from +Y, phi
/// from -Z towards +X. Lighting, suns and framing cameras all use it.
Vec3 directionFromAngles(double thetaRadians, double phiRadians);

/// Sub-pixel position in [0, 1)^2 of a pixel's camera sample s: the centre
/// for s = 0, then the R2 low-discrepancy sequence (plastic number) from there.
Eigen::Vector2d pixelSampleOffset(int s);

struct Camera {
  Vec3 eye{0, 0, 1};
  Vec3 target{0, 0, 0};
  Vec3 up{0, 1, 0};
  double fovDegrees = 45;  ///< vertical field of view
  ImageSize size{256, 256};

  /// Throws UserError if the camera cannot form an image (eye == target, up parallel
  /// to the view direction, fov outside (0, 180), bad size).
  void validate() const;
  /// Unit direction of the ray through image point (px, py) in pixel units, where
  /// (x + 0.5, y + 0.5) is the centre of pixel (x, y).
  Vec3 rayDirection(double px, double py) const;
  /// Where a world point appears: its image position in the units
  /// rayDirection takes, and its depth along the view direction. False for a
  /// point on or behind the eye's plane (pixel and depth untouched).
  bool project(const Vec3& point, Eigen::Vector2d& pixel, double& depth) const;
  /// The world offset that moves a point at `depth` in front of the eye by
  /// (dx, dy) pixels across the image, parallel to the image plane.
  Vec3 imagePlaneOffset(double dx, double dy, double depth) const;
  /// OpenEXR's worldToCamera: camera space x right, y up, z forward (left-handed);
  /// points are row vectors, p M.
  Eigen::Matrix4d worldToCamera() const;
  /// OpenEXR's worldToNDC: p M divided by its w is (0, 0) at the image's top
  /// left corner and (1, 1) at its bottom right (pixel (x, y)'s centre at
  /// ((x + 0.5) / width, (y + 0.5) / height)); z / w is 1 / depth.
  Eigen::Matrix4d worldToNdc() const;
  /// Unit view direction, right and up of the image (up as the image shows it).
  Vec3 forward() const { return (target - eye).normalized(); }
  Vec3 right() const { return forward().cross(up).normalized(); }
  Vec3 imageUp() const { return right().cross(forward()); }

 private:
  /// World units per pixel at unit depth.
  double pixelScale() const;
};

}  // namespace acpca
