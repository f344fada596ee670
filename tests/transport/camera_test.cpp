#include "transport/camera.h"

#include <gtest/gtest.h>

namespace acpca {
namespace {

Camera tiltedCamera() {
  Camera c;
  c.eye = {1, 2, 5};
  c.target = {0, 0.5, 0};
  c.up = {0.1, 1, 0};
  c.fovDegrees = 40;
  c.size = {320, 200};  // not square: the aspect must not skew the projection
  return c;
}

// A point on the ray through (px, py) projects back to (px, py) at the
// depth it lies along the view direction.
TEST(Camera, ProjectInvertsRayDirection) {
  const Camera c = tiltedCamera();
  for (const auto& [px, py] : {std::pair{0.0, 0.0}, {160.0, 100.0}, {319.5, 3.25}, {12.0, 199.0}})
    for (double distance : {0.5, 3.0, 40.0}) {
      const Vec3 ray = c.rayDirection(px, py);
      Eigen::Vector2d pixel;
      double depth = 0;
      ASSERT_TRUE(c.project(c.eye + distance * ray, pixel, depth));
      EXPECT_NEAR(pixel.x(), px, 1e-9);
      EXPECT_NEAR(pixel.y(), py, 1e-9);
      EXPECT_NEAR(depth, distance * ray.dot(c.forward()), 1e-12);
    }
}

// OpenEXR's conventions: a point on the ray through pixel (px, py) is, in
// camera space, in front (+z) at its depth, right of the axis for px past the
// middle and above it for py above the middle (left-handed); through
// worldToNDC and the divide it lands at (px / width, py / height), with z / w
// one over its depth.
TEST(Camera, WorldToCameraAndNdcFollowOpenExr) {
  const Camera c = tiltedCamera();
  const Eigen::Matrix4d toCamera = c.worldToCamera(), toNdc = c.worldToNdc();
  for (const auto& [px, py] : {std::pair{0.0, 0.0}, {160.0, 100.0}, {319.5, 3.25}, {12.0, 199.0}})
    for (double distance : {0.5, 3.0, 40.0}) {
      const Vec3 point = c.eye + distance * c.rayDirection(px, py);
      const Eigen::RowVector4d p(point.x(), point.y(), point.z(), 1);
      const Eigen::RowVector4d camera = p * toCamera, ndc = p * toNdc;
      const double depth = distance * c.rayDirection(px, py).dot(c.forward());
      EXPECT_NEAR(camera(2), depth, 1e-9);
      if (px != 160) {
        EXPECT_EQ(camera(0) > 0, px > 160) << px;
        EXPECT_EQ(camera(1) > 0, py < 100) << py;
      }
      EXPECT_NEAR(camera(3), 1, 1e-12);
      EXPECT_NEAR(ndc(0) / ndc(3), px / 320, 1e-9);
      EXPECT_NEAR(ndc(1) / ndc(3), py / 200, 1e-9);
      EXPECT_NEAR(ndc(2) / ndc(3), 1 / depth, 1e-9);
    }
  // Rows 0 to 2 of worldToCamera are a rotation: the camera keeps lengths.
  const Eigen::Matrix3d rotation = toCamera.topLeftCorner<3, 3>();
  EXPECT_TRUE((rotation * rotation.transpose()).isIdentity(1e-12));
  EXPECT_NEAR(rotation.determinant(), -1, 1e-12) << "left-handed from right-handed world";
}

TEST(Camera, PointsBehindTheEyeDoNotProject) {
  const Camera c = tiltedCamera();
  Eigen::Vector2d pixel(-1, -1);
  double depth = -1;
  EXPECT_FALSE(c.project(c.eye - c.forward(), pixel, depth));
  EXPECT_FALSE(c.project(c.eye + c.right(), pixel, depth));  // on the eye's plane
  EXPECT_EQ(pixel, Eigen::Vector2d(-1, -1));
  EXPECT_EQ(depth, -1);
}

// Moving a point by imagePlaneOffset moves its image by exactly (dx, dy)
// pixels and leaves its depth alone; row 0 is the top, so +dy goes down.
TEST(Camera, ImagePlaneOffsetMovesTheImageByPixels) {
  const Camera c = tiltedCamera();
  const Vec3 point = c.eye + 7 * c.rayDirection(100, 60);
  Eigen::Vector2d before, after;
  double depth = 0, depthAfter = 0;
  ASSERT_TRUE(c.project(point, before, depth));
  const Vec3 moved = point + c.imagePlaneOffset(25, -40, depth);
  ASSERT_TRUE(c.project(moved, after, depthAfter));
  EXPECT_NEAR(after.x() - before.x(), 25, 1e-9);
  EXPECT_NEAR(after.y() - before.y(), -40, 1e-9);
  EXPECT_NEAR(depthAfter, depth, 1e-12);
  EXPECT_GT(c.imageUp().dot(moved - point), 0);  // up the image
}

}  // namespace
}  // namespace acpca
