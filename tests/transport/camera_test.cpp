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
