// The window plugin: OpenCV's highgui behind WindowSystem (window_system.h).
// Built as a module of its own, loaded when the viewer opens its window.
#include <opencv2/highgui.hpp>

#include "viewer/window_system.h"

namespace acpca {

namespace {

class HighguiWindows final : public WindowSystem {
 public:
  void open(const std::string& window) override {
    cv::namedWindow(window, cv::WINDOW_AUTOSIZE | cv::WINDOW_GUI_NORMAL);
  }
  void show(const std::string& window, const cv::Mat& canvas) override {
    cv::imshow(window, canvas);
  }
  int waitKey(int ms) override { return cv::waitKey(ms); }
  void addTrackbar(const std::string& bar, const std::string& window, int last,
                   TrackbarCallback onChange, void* user) override {
    cv::createTrackbar(bar, window, nullptr, last, onChange, user);
  }
  void setTrackbar(const std::string& bar, const std::string& window, int position) override {
    cv::setTrackbarPos(bar, window, position);
  }
  int trackbar(const std::string& bar, const std::string& window) override {
    return cv::getTrackbarPos(bar, window);
  }
  void onMouse(const std::string& window, MouseCallback callback, void* user) override {
    cv::setMouseCallback(window, callback, user);
  }
  int wheelDelta(int flags) override { return cv::getMouseWheelDelta(flags); }
  bool visible(const std::string& window) override {
    return cv::getWindowProperty(window, cv::WND_PROP_VISIBLE) >= 1;
  }
  void closeAll() override { cv::destroyAllWindows(); }
};

}  // namespace

}  // namespace acpca

extern "C" __attribute__((visibility("default"))) acpca::WindowSystem* acpca_window_system() {
  static acpca::HighguiWindows windows;
  return &windows;
}
