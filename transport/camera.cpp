#include "transport/camera.h"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/error.h"

namespace acpca {

void validateImageSize(const ImageSize& size, const std::string& what) {
  if (size.width < 1 || size.height < 1 || size.width > kMaxImageSide ||
      size.height > kMaxImageSide)
    throw UserError(concat(what, ": image size ", size.width, "x", size.height,
                           " is out of range (each side 1..", kMaxImageSide, ")"));
}

void Camera::validate() const {
  validateImageSize(size, "camera");
  if (!eye.allFinite() || !target.allFinite() || !up.allFinite())
    throw UserError("camera: eye, target and up must be finite");
  const Vec3 forward = target - eye;
  if (forward.norm() <= 0) throw UserError("camera: eye and target coincide");
  if (up.cross(forward).norm() <= 1e-9 * up.norm() * forward.norm())
    throw UserError("camera: up is zero or parallel to the view direction");
  if (!(fovDegrees > 0 && fovDegrees < 180))
    throw UserError(concat("camera: fov ", fovDegrees, " is outside (0, 180) degrees"));
}

double Camera::pixelScale() const {
  return 2 * std::tan(0.5 * fovDegrees * std::numbers::pi / 180.0) / size.height;
}

Vec3 Camera::rayDirection(double px, double py) const {
  const Vec3 forward = (target - eye).normalized();
  const Vec3 right = forward.cross(up).normalized();
  const Vec3 trueUp = right.cross(forward);
  const double tanHalf = std::tan(0.5 * fovDegrees * std::numbers::pi / 180.0);
  const double aspect = static_cast<double>(size.width) / size.height;
  const double x = (2 * px / size.width - 1) * tanHalf * aspect;
  const double y = (1 - 2 * py / size.height) * tanHalf;  // row 0 is the top
  return (forward + x * right + y * trueUp).normalized();
}

// Square pixels: rayDirection's x and y step by pixelScale() per pixel.
bool Camera::project(const Vec3& point, Eigen::Vector2d& pixel, double& depth) const {
  const Vec3 d = point - eye;
  const double z = d.dot(forward());
  if (!(z > 0)) return false;
  const double s = pixelScale();
  pixel = {0.5 * size.width + d.dot(right()) / (z * s),
           0.5 * size.height - d.dot(imageUp()) / (z * s)};
  depth = z;
  return true;
}

Eigen::Matrix4d Camera::worldToCamera() const {
  const Vec3 axes[3] = {right(), imageUp(), forward()};
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  for (int j = 0; j < 3; ++j) {
    m.block<3, 1>(0, j) = axes[j];
    m(3, j) = -eye.dot(axes[j]);
  }
  m(3, 3) = 1;
  return m;
}

Eigen::Matrix4d Camera::worldToNdc() const {
  // From camera space (x, y, z, 1): X = z / 2 + x / (s W), Y = z / 2 - y / (s H),
  // Z = 1, W = z, with s the world units a pixel at unit depth (as project()).
  const double s = pixelScale();
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = 1 / (s * size.width);
  p(1, 1) = -1 / (s * size.height);
  p(2, 0) = p(2, 1) = 0.5;
  p(2, 3) = 1;
  p(3, 2) = 1;
  return worldToCamera() * p;
}

Vec3 Camera::imagePlaneOffset(double dx, double dy, double depth) const {
  const double s = pixelScale() * depth;
  return dx * s * right() - dy * s * imageUp();
}

Eigen::Vector2d pixelSampleOffset(int s) {
  constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;
  return {std::fmod(0.5 + s * a1, 1.0), std::fmod(0.5 + s * a2, 1.0)};
}

Vec3 directionFromAngles(double theta, double phi) {
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

ImageSize parseImageSize(const std::string& text, const std::string& what) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
    throw UserError(concat(what, " '", text, "': expected WxH, e.g. 256x256"));
  const ImageSize size{w, h};
  validateImageSize(size, what + " " + text);
  return size;
}

}  // namespace acpca
