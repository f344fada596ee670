#pragma once
// EXR files read through OpenEXR's C++ library, without OpenImageIO: an
// environment map or a frame opens without loading the plugin and the
// hundreds of libraries OpenImageIO pulls (0.3 s of a batch's start, most
// of it in the dynamic loader). The files read here are the common ones:
// the data window is the display window from (0, 0), and the channels are
// R, G, B, A (any of them) or Y (and A), half or float, unsampled; any
// compression, scanlines or tiles (part 0, as OpenImageIO reads it).
// Anything else is left to OpenImageIO.
#include <memory>
#include <string>

#include "imageio/image_file.h"

namespace acpca {

/// Opens `path` when it is such an EXR; null otherwise (not one, or not
/// readable here: OpenImageIO should try). Channels come R, G, B, A (Y, A)
/// as OpenImageIO orders them.
std::unique_ptr<ImageReader> openExrDirectly(const std::string& path);

}  // namespace acpca
