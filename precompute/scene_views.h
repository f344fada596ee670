#pragma once
// A scene's several views (docs/scenes.md, "Several views"): where each
// view's file goes, and the refusal of a view that sees nothing, before any
// view is rendered.
#include <string>

#include "precompute/scene.h"

namespace acpca {

/// "vNN": view k's name in file names (more digits past 99).
std::string viewName(size_t k);

/// View k's output beside `out`: STEM_vNN.EXT (NN = 00, 01, ...; more digits
/// past 99); `out` itself for a scene of one view.
std::string viewOutputPath(const std::string& out, size_t k, size_t views);

/// Throws UserError naming the scene file's view and its camera when a view
/// of several sees no geometry (one camera sample per pixel, traced once for
/// every view). A scene of one view is left alone: its image may be empty.
void refuseBlindViews(const Scene& scene);

}  // namespace acpca
