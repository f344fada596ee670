// The viewer's input handling without a window: keys, drags, the mouse, the
// wheel and the exposure trackbar change the view state as the help line says.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "viewer/view_input.h"

namespace acpca {
namespace {

ViewContext maps(int envs) {
  ViewContext c;
  c.envs = envs;
  return c;
}

TEST(ViewInput, MapKeysWrapAroundTheMaps) {
  ViewState s;
  s.env = 2;
  EXPECT_EQ(applyKey(s, 'n', maps(3)).state.env, 0);
  EXPECT_EQ(applyKey(s, ' ', maps(3)).state.env, 0);
  s.env = 0;
  EXPECT_EQ(applyKey(s, 'p', maps(3)).state.env, 2);
  EXPECT_EQ(applyKey(s, 'n', maps(1)).state.env, 0) << "one map: n stays on it";
}

TEST(ViewInput, OverlayKeysToggleAndResetKeepsEverythingButTheRotation) {
  ViewState s;
  s.yaw = 40, s.pitch = -20, s.exposure = 1.5, s.env = 1;
  const ViewState c = applyKey(s, 'c', maps(2)).state;
  EXPECT_TRUE(c.clusterOverlay);
  EXPECT_FALSE(applyKey(c, 'c', maps(2)).state.clusterOverlay);
  EXPECT_TRUE(applyKey(s, 'h', maps(2)).state.rankHeatMap);
  EXPECT_TRUE(applyKey(s, 'l', maps(2)).state.lightingInset);
  const ViewState r = applyKey(c, 'r', maps(2)).state;
  EXPECT_EQ(r.yaw, 0);
  EXPECT_EQ(r.pitch, 0);
  EXPECT_EQ(r.exposure, 1.5);
  EXPECT_EQ(r.env, 1);
  EXPECT_TRUE(r.clusterOverlay);
  EXPECT_EQ(applyKey(s, 'a', maps(2)).state.yaw, 30);
  EXPECT_EQ(applyKey(s, 'd', maps(2)).state.yaw, 50);
}

TEST(ViewInput, ExposureKeysStayWithinTheTrackbar) {
  ViewState s;
  EXPECT_EQ(applyKey(s, '+', maps(1)).state.exposure, 0.5);
  EXPECT_EQ(applyKey(s, '=', maps(1)).state.exposure, 0.5);
  EXPECT_EQ(applyKey(s, '-', maps(1)).state.exposure, -0.5);
  s.exposure = 9.75;
  EXPECT_EQ(applyKey(s, '+', maps(1)).state.exposure, 10);
  s.exposure = -9.9;
  EXPECT_EQ(applyKey(s, '-', maps(1)).state.exposure, kExposureMin);
}

TEST(ViewInput, QuitSaveAndUnknownKeysLeaveTheStateAlone) {
  ViewState s;
  s.yaw = 12;
  for (int key : {int('q'), 27}) {
    const ViewUpdate u = applyKey(s, key, maps(2));
    EXPECT_EQ(u.action, ViewAction::Quit);
    EXPECT_TRUE(u.state == s);
  }
  EXPECT_EQ(applyKey(s, 's', maps(2)).action, ViewAction::Save);
  EXPECT_TRUE(applyKey(s, 's', maps(2)).state == s);
  for (int key : {int('x'), int('Z'), int('0'), 200}) {
    const ViewUpdate u = applyKey(s, key, maps(2));
    EXPECT_EQ(u.action, ViewAction::None);
    EXPECT_TRUE(u.state == s) << key;
  }
}

TEST(ViewInput, AFullWidthDragTurnsOnceAroundAndPitchStopsAtThePoles) {
  ViewState s;
  EXPECT_DOUBLE_EQ(applyDrag(s, 640, 0, 640, 480).yaw, 360);
  EXPECT_DOUBLE_EQ(applyDrag(s, -160, 0, 640, 480).yaw, -90);
  EXPECT_DOUBLE_EQ(applyDrag(s, 0, 240, 640, 480).pitch, 90);
  EXPECT_DOUBLE_EQ(applyDrag(s, 0, 1000, 640, 480).pitch, 90);
  EXPECT_DOUBLE_EQ(applyDrag(s, 0, -1000, 640, 480).pitch, -90);
}

TEST(ViewInput, DragsStartOnTheImageOnlyAndFollowTheButton) {
  DragTracker t;
  int dx = 0, dy = 0;
  EXPECT_FALSE(t.move(10, 10, true, dx, dy)) << "no press yet";
  t.press(5, 500, 480);  // on the status strip below the image
  EXPECT_FALSE(t.move(10, 10, true, dx, dy));
  t.press(100, 100, 480);
  ASSERT_TRUE(t.move(130, 90, true, dx, dy));
  EXPECT_EQ(dx, 30);
  EXPECT_EQ(dy, -10);
  ASSERT_TRUE(t.move(131, 95, true, dx, dy));  // since the last move
  EXPECT_EQ(dx, 1);
  EXPECT_EQ(dy, 5);
  EXPECT_FALSE(t.move(140, 95, false, dx, dy)) << "the button is up";
  t.release();
  EXPECT_FALSE(t.move(150, 95, true, dx, dy));
}

TEST(ViewInput, TheExposureTrackbarRoundTripsAndIgnoresItsOwnRounding) {
  for (int position : {0, 1, 40, 79, 80}) {
    const ViewState s = applyExposurePosition(ViewState{}, position);
    EXPECT_EQ(exposurePosition(s.exposure), position);
  }
  EXPECT_EQ(exposurePosition(-50), 0);
  EXPECT_EQ(exposurePosition(50), kExposureSteps);
  ViewState s;
  s.exposure = 0.3;  // position 41 rounds it; the bar at 41 must not move it
  EXPECT_EQ(applyExposurePosition(s, exposurePosition(0.3)).exposure, 0.3);
  EXPECT_EQ(applyExposurePosition(s, 44).exposure, 1.0);
  EXPECT_EQ(applyExposurePosition(s, -1).exposure, 0.3) << "no bar (OpenCV gives -1)";
}

// Lights: a camera looking down -Z from z = 5 at a 64 x 48 image.
ViewContext lightContext() {
  ViewContext c = maps(1);
  c.camera.eye = {0, 0, 5};
  c.camera.target = {0, 0, 0};
  c.camera.fovDegrees = 50;
  c.camera.size = {64, 48};
  c.newLight = parseLocalLight("point:0.5,1,0,20");
  return c;
}

Eigen::Vector2d drawnAt(const LocalLight& light, const Camera& camera) {
  Eigen::Vector2d pixel(-1, -1);
  double depth = 0;
  EXPECT_TRUE(camera.project(light.position, pixel, depth));
  return pixel;
}

TEST(ViewInput, TheAddKeyPlacesALightAndSelectsItRemoveAndTabCycle) {
  const ViewContext c = lightContext();
  ViewState s = applyKey(ViewState{}, 'i', c).state;
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.selectedLight, 0);
  EXPECT_EQ(s.lights[0].position, Vec3(0.5, 1, 0));
  s = applyKey(s, 'i', c).state;
  EXPECT_EQ(s.selectedLight, 1);
  EXPECT_EQ(applyKey(s, '\t', c).state.selectedLight, 0) << "Tab wraps";
  const ViewState one = applyKey(s, 'o', c).state;
  EXPECT_EQ(one.lights.size(), 1u);
  EXPECT_EQ(one.selectedLight, 0);
  const ViewState none = applyKey(one, 'o', c).state;
  EXPECT_TRUE(none.lights.empty());
  EXPECT_EQ(none.selectedLight, -1);
  EXPECT_TRUE(applyKey(none, 'o', c).state == none) << "nothing to remove";
  EXPECT_TRUE(applyKey(none, '\t', c).state == none);
}

// A dragged light follows the cursor pixel for pixel and keeps its depth;
// its spec says where it went.
TEST(ViewInput, ADraggedLightFollowsTheCursorAtItsDepth) {
  const ViewContext c = lightContext();
  ViewState s = applyKey(ViewState{}, 'i', c).state;
  const Eigen::Vector2d before = drawnAt(s.lights[0], c.camera);
  const ViewState moved = moveLightAcross(s, 0, 10, -6, c.camera);
  const Eigen::Vector2d after = drawnAt(moved.lights[0], c.camera);
  EXPECT_NEAR(after.x() - before.x(), 10, 1e-9);
  EXPECT_NEAR(after.y() - before.y(), -6, 1e-9);
  EXPECT_NEAR(moved.lights[0].position.z(), 0, 1e-12) << "this camera's depth is -z";
  EXPECT_EQ(parseLocalLight(moved.lights[0].spec).position, moved.lights[0].position);
  EXPECT_EQ(moved.lights[0].emission, s.lights[0].emission);
  EXPECT_FALSE(moved == s);
  EXPECT_TRUE(moveLightAcross(s, 3, 10, 0, c.camera) == s) << "no light 3";
}

// The wheel (and [ / ]) slides the light along its pixel's ray: the image of
// the light stays put while its distance to the eye shrinks by a tenth.
TEST(ViewInput, TheWheelMovesTheSelectedLightInDepthAlongItsRay) {
  const ViewContext c = lightContext();
  const ViewState s = applyKey(ViewState{}, 'i', c).state;
  const double distance = (s.lights[0].position - c.camera.eye).norm();
  const ViewState nearer = moveLightInDepth(s, 1, c.camera);
  EXPECT_NEAR((nearer.lights[0].position - c.camera.eye).norm(), 0.9 * distance, 1e-12);
  EXPECT_NEAR((drawnAt(nearer.lights[0], c.camera) - drawnAt(s.lights[0], c.camera)).norm(), 0,
              1e-9);
  const ViewState back = moveLightInDepth(nearer, -1, c.camera);
  EXPECT_NEAR((back.lights[0].position - s.lights[0].position).norm(), 0, 1e-12);
  EXPECT_TRUE(applyKey(s, '[', c).state.lights[0].position == nearer.lights[0].position);
  EXPECT_NEAR((applyKey(s, ']', c).state.lights[0].position - c.camera.eye).norm(), distance / 0.9,
              1e-12);
  ViewState unselected = s;
  unselected.selectedLight = -1;
  EXPECT_TRUE(moveLightInDepth(unselected, 2, c.camera) == unselected);
}

TEST(ViewInput, APressOnADrawnLightPicksItAndElsewhereTheRotation) {
  const ViewContext c = lightContext();
  // Two lights, the second dragged 30 pixels right of the first.
  const ViewState s = moveLightAcross(applyKey(applyKey(ViewState{}, 'i', c).state, 'i', c).state,
                                      1, 30, 0, c.camera);
  const Eigen::Vector2d at = drawnAt(s.lights[0], c.camera);
  EXPECT_EQ(lightUnder(s, std::floor(at.x()) + 30, std::floor(at.y()), c.camera), 1);
  // Pixel (x, y) is centred on (x + 0.5, y + 0.5).
  EXPECT_EQ(lightUnder(s, std::floor(at.x()), std::floor(at.y()), c.camera), 0);
  EXPECT_EQ(lightUnder(s, at.x() + kLightPickPixels + 1, at.y(), c.camera), -1);
  DragTracker t;
  t.press(int(at.x()), int(at.y()), 48, lightUnder(s, int(at.x()), int(at.y()), c.camera));
  EXPECT_EQ(t.light(), 0);
  t.press(0, 0, 48, lightUnder(s, 0, 0, c.camera));
  EXPECT_EQ(t.light(), -1);
}

TEST(ViewInput, TheAddedLightIsAKeyLightDrawnHighInTheView) {
  TransportHeader g;
  g.camera = lightContext().camera;  // eye (0, 0, 5) looking down -z, 64 x 48
  g.pixels = {0, 1, 2, 3, 4};
  // Depths 1, 3, 5, 100 and 2: median 3 (the far one, a backdrop, does not count).
  g.positions = {0, 0, 4, 1, 0, 2, 0, 1, 0, 50, 0, -95, 0, -1, 3};
  const LocalLight light = keyLightFor(g);
  const Eigen::Vector2d at = drawnAt(light, g.camera);
  EXPECT_NEAR(at.x(), 32, 1e-9);
  EXPECT_NEAR(at.y(), 0.2 * 48, 1e-9);
  EXPECT_NEAR(5 - light.position.z(), 0.6 * 3, 1e-12);
  EXPECT_NEAR(light.emission[0] * lightIrradiance(light, Vec3(0, 0, 2)), std::numbers::pi, 1e-12);
}

TEST(ViewInput, AHeldLampLightsSpheresAsPointsOfTheSamePower) {
  // A sphere of radiance L and radius r gives what a point of intensity
  // L pi r^2 gives, from afar; points and spots are lit as they are.
  ViewState s;
  s.lights = {parseLocalLight("sphere:0.5,2,1,0.1,30,20,10"), parseLocalLight("point:0,1,0,3"),
              parseLocalLight("spot:0,1,0,0,-1,0,30,2")};
  EXPECT_EQ(litLights(s)[0].canonicalSpec(), s.lights[0].canonicalSpec());
  const ViewState released = s;
  s.lampHeld = true;
  EXPECT_FALSE(s == released);
  const std::vector<LocalLight> lit = litLights(s);
  ASSERT_EQ(lit.size(), 3u);
  ASSERT_STREQ(lit[0].kindName(), "point");
  EXPECT_EQ(lit[0].position, s.lights[0].position);
  EXPECT_EQ(parseLocalLight(lit[0].spec).canonicalSpec(), lit[0].canonicalSpec());
  const Vec3 far = s.lights[0].position + Vec3(0, -1000, 0);  // 10^4 radii below
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(lit[0].emission[c] * lightIrradiance(lit[0], far) /
                    (s.lights[0].emission[c] * lightIrradiance(s.lights[0], far)),
                1, 1e-8);
  EXPECT_EQ(lit[1].canonicalSpec(), s.lights[1].canonicalSpec());
  EXPECT_EQ(lit[2].canonicalSpec(), s.lights[2].canonicalSpec());
}

TEST(ViewInput, AHeldMapLightsItsSourcesAsPointsOfTheSameEnergy) {
  // A 0.53-degree sun and a 10-degree lamp: each shrunk to kHeldDiscRadius,
  // its direction kept and its energy (radiance x solid angle) to rounding.
  MapSource sun, lamp;
  sun.direction = Vec3(0.3, 0.8, -0.2).normalized();
  sun.radius = 0.53 / 2 * std::numbers::pi / 180;
  sun.radiance = Rgb(4e4, 3.8e4, 3.4e4);
  lamp.direction = Vec3(0, -1, 0);
  lamp.radius = 5 * std::numbers::pi / 180;
  lamp.radiance = Rgb(2, 2, 2);
  const std::vector<MapSource> held = previewSources({sun, lamp});
  ASSERT_EQ(held.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    const MapSource& before = k == 0 ? sun : lamp;
    EXPECT_EQ(held[k].direction, before.direction);
    EXPECT_EQ(held[k].radius, kHeldDiscRadius);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(held[k].energy()[c] / before.energy()[c], 1, 1e-9) << k;
  }
  ViewState s;
  const ViewState released = s;
  s.mapHeld = true;
  EXPECT_FALSE(s == released);
}

}  // namespace
}  // namespace acpca
