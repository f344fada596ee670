// The relighter's shadow rays: a triangle and a sphere block the segments
// that cross them and only those, whichever way a segment runs, and a
// segment stopped short of a surface passes.
#include <gtest/gtest.h>

#include "occlusion/scene_occluder.h"

namespace acpca {
namespace {

/// A unit square in the plane y = 1 (two triangles) and a sphere of radius
/// 0.5 around (5, 0, 0).
LampGeometry squareAndSphere() {
  LampGeometry g;
  g.vertices = {-0.5f, 1, -0.5f, 0.5f, 1, -0.5f, 0.5f, 1, 0.5f, -0.5f, 1, 0.5f};
  g.triangles = {0, 1, 2, 0, 2, 3};
  g.spheres = {5, 0, 0, 0.5f};
  return g;
}

/// One segment traced as the relighter traces them, in a packet of its own.
struct OneRay {
  const SceneOccluder& occluder;
  bool blocked(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float nearest,
               float farthest) const {
    SceneOccluder::Packet p;
    p.count = 1;
    p.ox[0] = o.x(), p.oy[0] = o.y(), p.oz[0] = o.z();
    p.dx[0] = d.x(), p.dy[0] = d.y(), p.dz[0] = d.z();
    p.nearest[0] = nearest, p.farthest[0] = farthest;
    occluder.trace(p);
    return p.blocked[0];
  }
};

TEST(SceneOccluder, SurfacesBlockTheSegmentsThatCrossThemAndNoOthers) {
  const SceneOccluder scene(squareAndSphere());
  const OneRay occluder{scene};
  const Eigen::Vector3f up(0, 1, 0), down(0, -1, 0), x(1, 0, 0);
  EXPECT_TRUE(occluder.blocked({0.1f, 0, 0.2f}, up, 0, 5));
  EXPECT_TRUE(occluder.blocked({0.1f, 3, 0.2f}, down, 0, 5));     // from the other side
  EXPECT_FALSE(occluder.blocked({0.1f, 0, 0.2f}, up, 0, 0.99f));  // stopped short
  EXPECT_FALSE(occluder.blocked({0.1f, 0, 0.2f}, up, 1.01f, 5));  // starting past it
  EXPECT_FALSE(occluder.blocked({0.7f, 0, 0}, up, 0, 5));         // beside the square
  // On the shared diagonal: robust intersection lets nothing through.
  EXPECT_TRUE(occluder.blocked({0.25f, 0, 0.25f}, up, 0, 5));
  EXPECT_TRUE(occluder.blocked({0, 0, 0}, x, 0, 10));  // the sphere
  EXPECT_FALSE(occluder.blocked({0, 0, 0}, x, 0, 4.4f));
  EXPECT_FALSE(occluder.blocked({0, 0.6f, 0}, x, 0, 10));  // above it
}

TEST(SceneOccluder, NoSurfacesBlockNothing) {
  const SceneOccluder scene{LampGeometry{}};
  const OneRay occluder{scene};
  EXPECT_FALSE(occluder.blocked({0, 0, 0}, {0, 1, 0}, 0, 1e30f));
}

}  // namespace
}  // namespace acpca
