#pragma once
// Whether a window can be opened at all: OpenCV's Qt back end aborts the
// process when it cannot reach the X server, so the viewer asks first.
#include <string>

namespace acpca {

/// Why no window can be opened, or "" when an X server answers at $DISPLAY
/// (or Qt is told to draw off screen).
std::string displayProblem();

}  // namespace acpca
