#pragma once
// Relit images written in any of the formats of image_formats.h (always to a
// temporary name, then renamed).
#include <string>

#include "imageio/image.h"
#include "imageio/image_formats.h"
#include "imageio/srgb_encoders.h"

namespace acpca {

/// Writes EXR (linear, half by default) or PNG (x 2^exposure, sRGB, 8-bit).
/// EXR output is also scaled by 2^exposure. Throws UserError naming the path.
void writeImage(const Image& image, const std::string& path, ImageFormat format, double exposureEv,
                bool exrFloat = false);
/// The same into `file` (a temporary name the caller renames; errors name
/// `path`), encoded as told.
void encodeImage(const Image& image, const std::string& file, const std::string& path,
                 ImageFormat format, double exposureEv, const ImageEncoding& encoding);

/// 8-bit values (rows top to bottom, channels interleaved) as PNG into
/// `file` (a temporary name the caller renames; errors name `path`), with a
/// frame's chunks when `metadata` is given.
void encodePng8(int width, int height, int channels, const unsigned char* values,
                const std::string& file, const std::string& path, int level,
                const FrameMetadata* metadata = nullptr);
/// Writes 8-bit values as PNG, atomically; throws UserError naming the path.
void writePng8(int width, int height, int channels, const unsigned char* values,
               const std::string& path);

}  // namespace acpca
