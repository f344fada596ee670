#pragma once
// The viewer's window: OpenCV's highgui (Qt on Debian) behind an interface,
// in a plugin of its own (highgui_window.cpp, libacpca_window.so) loaded
// when a window opens, so that no other command loads Qt
// (core/plugin_library.h). The event codes are highgui's (cv::EVENT_*).
#include <opencv2/core.hpp>
#include <string>

namespace acpca {

/// One window with trackbars, mouse and keys; the calls highgui has.
class WindowSystem {
 public:
  using MouseCallback = void (*)(int event, int x, int y, int flags, void* user);
  using TrackbarCallback = void (*)(int position, void* user);

  /// Opens `window`, sized to what it shows, without highgui's toolbar.
  virtual void open(const std::string& window) = 0;
  virtual void show(const std::string& window, const cv::Mat& canvas) = 0;
  /// The key pressed within `ms` milliseconds, or -1; lets the window draw.
  virtual int waitKey(int ms) = 0;
  virtual void addTrackbar(const std::string& bar, const std::string& window, int last,
                           TrackbarCallback onChange, void* user) = 0;
  virtual void setTrackbar(const std::string& bar, const std::string& window, int position) = 0;
  virtual int trackbar(const std::string& bar, const std::string& window) = 0;
  virtual void onMouse(const std::string& window, MouseCallback callback, void* user) = 0;
  /// The wheel's turn in a mouse event's flags (120 a notch).
  virtual int wheelDelta(int flags) = 0;
  /// False once the user has closed the window.
  virtual bool visible(const std::string& window) = 0;
  virtual void closeAll() = 0;

 protected:
  ~WindowSystem() = default;
};

/// The plugin's exported function: `extern "C" WindowSystem* NAME()`.
inline constexpr const char* kWindowSystemEntry = "acpca_window_system";

/// The window plugin, loaded on the first call ($ACPCA_WINDOW names its
/// file). Throws UserError naming the files tried when it cannot be loaded.
WindowSystem& windowSystem();

}  // namespace acpca
