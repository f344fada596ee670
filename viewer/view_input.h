#pragma once
// How the viewer's inputs change what it shows, as pure functions of the view
// state: keys, drags, mouse buttons, trackbar positions and script events. No
// window is involved, so all of it is tested without a display.
#include <string>

namespace acpca {

/// What the window shows; everything an input can change.
struct ViewState {
  int env = 0;
  double yaw = 0, pitch = 0;  ///< degrees
  double exposure = 0;        ///< stops
  int rankPercent = 100;      ///< share of each cluster's bases used
  bool clusterOverlay = false, rankHeatMap = false, lightingInset = false;
};

bool operator==(const ViewState& a, const ViewState& b);

/// What an input asks for beyond the new state.
enum class ViewAction { None, Save, Quit };

struct ViewUpdate {
  ViewState state;
  ViewAction action = ViewAction::None;
};

/// The exposure trackbar runs over -10..+10 stops in quarter stops.
inline constexpr int kExposureSteps = 80;
inline constexpr double kExposureStep = 0.25, kExposureMin = -10;

/// A key (its ASCII code): n or space / p the next / previous of `envs` maps
/// (wrapping), c / h / l the cluster, rank and lighting overlays, a / d ten
/// degrees of yaw, r the rotation reset, + or = / - half a stop (within the
/// trackbar's range), s save, q or Esc quit; any other key changes nothing.
ViewUpdate applyKey(const ViewState& state, int key, int envs);

/// A drag by (dx, dy) pixels over an image of width x height: a full width
/// turns the lighting once around, the height half a turn (pitch within
/// -90..90).
ViewState applyDrag(const ViewState& state, int dx, int dy, int width, int height);

/// The exposure trackbar's position for an exposure (clamped to the bar), and
/// the state a moved bar gives: a position that merely rounds the current
/// exposure leaves it alone.
int exposurePosition(double exposure);
ViewState applyExposurePosition(const ViewState& state, int position);

/// The left button over the window: a press over the image (above the status
/// strip, y < imageHeight) starts a drag, a release ends it, and each move
/// with the button held gives the drag since the last one.
class DragTracker {
 public:
  void press(int x, int y, int imageHeight);
  void release() { dragging_ = false; }
  /// Whether this move drags (then dx, dy are set).
  bool move(int x, int y, bool buttonHeld, int& dx, int& dy);

 private:
  bool dragging_ = false;
  int x_ = 0, y_ = 0;
};

}  // namespace acpca
