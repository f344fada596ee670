// The viewer's input handling without a window: keys, drags, the mouse and
// the exposure trackbar change the view state as the help line says.
#include <gtest/gtest.h>

#include "viewer/view_input.h"

namespace acpca {
namespace {

TEST(ViewInput, MapKeysWrapAroundTheMaps) {
  ViewState s;
  s.env = 2;
  EXPECT_EQ(applyKey(s, 'n', 3).state.env, 0);
  EXPECT_EQ(applyKey(s, ' ', 3).state.env, 0);
  s.env = 0;
  EXPECT_EQ(applyKey(s, 'p', 3).state.env, 2);
  EXPECT_EQ(applyKey(s, 'n', 1).state.env, 0) << "one map: n stays on it";
}

TEST(ViewInput, OverlayKeysToggleAndResetKeepsEverythingButTheRotation) {
  ViewState s;
  s.yaw = 40, s.pitch = -20, s.exposure = 1.5, s.env = 1;
  const ViewState c = applyKey(s, 'c', 2).state;
  EXPECT_TRUE(c.clusterOverlay);
  EXPECT_FALSE(applyKey(c, 'c', 2).state.clusterOverlay);
  EXPECT_TRUE(applyKey(s, 'h', 2).state.rankHeatMap);
  EXPECT_TRUE(applyKey(s, 'l', 2).state.lightingInset);
  const ViewState r = applyKey(c, 'r', 2).state;
  EXPECT_EQ(r.yaw, 0);
  EXPECT_EQ(r.pitch, 0);
  EXPECT_EQ(r.exposure, 1.5);
  EXPECT_EQ(r.env, 1);
  EXPECT_TRUE(r.clusterOverlay);
  EXPECT_EQ(applyKey(s, 'a', 2).state.yaw, 30);
  EXPECT_EQ(applyKey(s, 'd', 2).state.yaw, 50);
}

TEST(ViewInput, ExposureKeysStayWithinTheTrackbar) {
  ViewState s;
  EXPECT_EQ(applyKey(s, '+', 1).state.exposure, 0.5);
  EXPECT_EQ(applyKey(s, '=', 1).state.exposure, 0.5);
  EXPECT_EQ(applyKey(s, '-', 1).state.exposure, -0.5);
  s.exposure = 9.75;
  EXPECT_EQ(applyKey(s, '+', 1).state.exposure, 10);
  s.exposure = -9.9;
  EXPECT_EQ(applyKey(s, '-', 1).state.exposure, kExposureMin);
}

TEST(ViewInput, QuitSaveAndUnknownKeysLeaveTheStateAlone) {
  ViewState s;
  s.yaw = 12;
  for (int key : {int('q'), 27}) {
    const ViewUpdate u = applyKey(s, key, 2);
    EXPECT_EQ(u.action, ViewAction::Quit);
    EXPECT_TRUE(u.state == s);
  }
  EXPECT_EQ(applyKey(s, 's', 2).action, ViewAction::Save);
  EXPECT_TRUE(applyKey(s, 's', 2).state == s);
  for (int key : {int('x'), int('Z'), int('0'), 200}) {
    const ViewUpdate u = applyKey(s, key, 2);
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

}  // namespace
}  // namespace acpca
