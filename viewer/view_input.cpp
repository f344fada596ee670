#include "viewer/view_input.h"

#include <algorithm>
#include <cmath>

namespace acpca {

bool operator==(const ViewState& a, const ViewState& b) {
  return a.env == b.env && a.yaw == b.yaw && a.pitch == b.pitch && a.exposure == b.exposure &&
         a.rankPercent == b.rankPercent && a.clusterOverlay == b.clusterOverlay &&
         a.rankHeatMap == b.rankHeatMap && a.lightingInset == b.lightingInset;
}

ViewUpdate applyKey(const ViewState& state, int key, int envs) {
  ViewUpdate u{state};
  ViewState& s = u.state;
  switch (key) {
    case 27:
    case 'q':
      u.action = ViewAction::Quit;
      break;
    case 'n':
    case ' ':
      s.env = (s.env + 1) % envs;
      break;
    case 'p':
      s.env = (s.env + envs - 1) % envs;
      break;
    case 'c':
      s.clusterOverlay = !s.clusterOverlay;
      break;
    case 'h':
      s.rankHeatMap = !s.rankHeatMap;
      break;
    case 'l':
      s.lightingInset = !s.lightingInset;
      break;
    case 'a':
    case 'd':
      s.yaw += key == 'a' ? -10 : 10;
      break;
    case 'r':
      s.yaw = s.pitch = 0;
      break;
    case '+':
    case '=':
      s.exposure = std::min(s.exposure + 0.5, -kExposureMin);
      break;
    case '-':
      s.exposure = std::max(s.exposure - 0.5, kExposureMin);
      break;
    case 's':
      u.action = ViewAction::Save;
      break;
    default:
      break;
  }
  return u;
}

ViewState applyDrag(const ViewState& state, int dx, int dy, int width, int height) {
  ViewState s = state;
  s.yaw += dx * 360.0 / width;
  s.pitch = std::clamp(s.pitch + dy * 180.0 / height, -90.0, 90.0);
  return s;
}

int exposurePosition(double exposure) {
  const int position = static_cast<int>(std::lround((exposure - kExposureMin) / kExposureStep));
  return std::clamp(position, 0, kExposureSteps);
}

ViewState applyExposurePosition(const ViewState& state, int position) {
  ViewState s = state;
  if (position >= 0 && position != exposurePosition(s.exposure))
    s.exposure = kExposureMin + std::min(position, kExposureSteps) * kExposureStep;
  return s;
}

void DragTracker::press(int x, int y, int imageHeight) {
  if (y >= imageHeight) return;  // the status strip
  dragging_ = true;
  x_ = x, y_ = y;
}

bool DragTracker::move(int x, int y, bool buttonHeld, int& dx, int& dy) {
  if (!dragging_ || !buttonHeld) return false;
  dx = x - x_, dy = y - y_;
  x_ = x, y_ = y;
  return true;
}

}  // namespace acpca
