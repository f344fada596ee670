#pragma once
// The image codecs plugin (image_codecs.h), loaded once per process on the
// first image read or written (core/plugin_library.h).
#include "core/plugin_library.h"
#include "imageio/image_codecs.h"

namespace acpca {

/// Where the image codecs are found: $ACPCA_IMAGE_CODECS names the file.
PluginSpec imageCodecsPlugin();

/// The plugin's codecs, loaded on the first call. Throws UserError naming
/// the files tried and why when it is missing or broken (and again at each
/// later call).
ImageCodecs& imageCodecs();

}  // namespace acpca
