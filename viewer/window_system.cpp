#include "viewer/window_system.h"

#include "core/plugin_library.h"

namespace acpca {

WindowSystem& windowSystem() {
#ifdef ACPCA_WINDOW_BUILT
  const char* built = ACPCA_WINDOW_BUILT;
#else
  const char* built = nullptr;
#endif
  static WindowSystem& windows = *reinterpret_cast<WindowSystem* (*)()>(
      loadPluginEntry({"libacpca_window.so", "ACPCA_WINDOW", built, kWindowSystemEntry,
                       "the viewer's window (OpenCV highgui; scripts/setup.sh installs it)"}))();
  return windows;
}

}  // namespace acpca
