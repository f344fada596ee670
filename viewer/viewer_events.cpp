// A viewer script's events applied as a user's would be (viewer_script.h),
// and the frame times the script run reports.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/stopwatch.h"
#include "pictures/pictures.h"
#include "viewer/viewer.h"
#include "viewer/window_system.h"

namespace acpca {

void Viewer::applyEvent(const ScriptEvent& e) {
  using Kind = ScriptEvent::Kind;
  switch (e.kind) {
    case Kind::Key:
      applyKey(static_cast<int>(e.a));
      break;
    case Kind::Drag:
      if (heldLight_ >= 0)
        applyLightDrag(heldLight_, static_cast<int>(e.a), static_cast<int>(e.b));
      else  // after a press, the map stays held until the release
        applyDrag(static_cast<int>(e.a), static_cast<int>(e.b), scriptPressed_);
      break;
    case Kind::Press:
      scriptPressed_ = true;
      heldLight_ = lightUnder(ui_, e.a, e.b, context_.camera);
      holdLamp(heldLight_ >= 0);
      break;
    case Kind::Release:
      scriptPressed_ = false;
      heldLight_ = -1;
      holdLamp(false);
      releaseMap();
      break;
    case Kind::DragFrom:
      if (const int light = lightUnder(ui_, e.a, e.b, context_.camera); light >= 0)
        applyLightDrag(light, static_cast<int>(e.c), static_cast<int>(e.d));
      else
        applyDrag(static_cast<int>(e.c), static_cast<int>(e.d), false);
      break;
    case Kind::Wheel:
      applyWheel(e.a);
      break;
    case Kind::Light: {
      ViewContext context = context_;
      context.newLight = *e.light;
      ui_ = acpca::applyKey(ui_, 'i', context).state;
      request();
      break;
    }
    case Kind::Rotate:  // as a drag: held while a press is
      ui_.yaw = e.a;
      ui_.pitch = e.b;
      ui_.mapHeld = scriptPressed_ && heldLight_ < 0;
      request();
      break;
    case Kind::Exposure:
      ui_.exposure = e.a;
      request();
      break;
    case Kind::Rank:
      ui_.rankPercent = static_cast<int>(std::lround(e.a));
      request();
      break;
    case Kind::Env:
      if (e.a < 0 || e.a >= envs_.size())
        throw ParameterError("viewer script", concat("env ", e.a),
                             concat("is not one of the ", envs_.size(), " maps (0-based)"));
      ui_.env = static_cast<int>(e.a);
      request();
      break;
    case Kind::Save:
      waitForLatestRequest();
      savePictures(e.path);
      break;
    case Kind::Screenshot:
      waitForLatestRequest();
      writeScreenshot(e.path);
      break;
    case Kind::Wait: {
      const Stopwatch waiting;
      while (waiting.milliseconds() < e.a) {
        showLatest();
        windowSystem().waitKey(10);
      }
      break;
    }
  }
  syncTrackbars();
  waitForLatestRequest();
}

std::string Viewer::frameSummary() {
  std::lock_guard lock(mutex_);  // the worker is idle: every request is drawn
  if (frameMs_.empty()) return "no frames";
  std::vector<double> ms = frameMs_;
  // The first frame relights everything; the rest relight what changed.
  const double first = ms.front();
  ms.erase(ms.begin());
  if (ms.empty()) return concat("1 frame: ", first, " ms");
  std::sort(ms.begin(), ms.end());
  const double median = ms[ms.size() / 2];
  char text[160];
  std::snprintf(text, sizeof text,
                "%zu frames after the first (%.1f ms): median %.1f ms (%.1f fps)", ms.size(), first,
                median, 1000.0 / median);
  return text;
}

}  // namespace acpca
