#pragma once
// Scanline EXR files through OpenEXR's core C API (Debian 12's 3.1): OpenEXR
// writes the header, the chunk offsets and each chunk's frame; the pixels
// are packed and compressed here, by the format's own rules (OpenEXR's byte
// reordering and predictor, then its run-length code or a zlib stream), so
// every reader of EXR reads them; PIZ by OpenEXR's own encode pipeline.
// OpenImageIO's writer took 38 ms of a core
// for a 1024x1024 half RGB frame with RLE; OpenEXR's own C++ writer 21 ms.
#include <string>
#include <utility>
#include <vector>

#include "imageio/frame_metadata.h"

namespace acpca {

/// The codecs written here: every lossless one the CLI offers.
enum class ExrCodec { None, Rle, Zips, Zip, Piz };

/// Pixels for an EXR: rows top to bottom, channels interleaved, half
/// (std::uint16_t bits) or float.
struct ExrPixels {
  int width = 0, height = 0;
  std::vector<std::string> channelNames;  ///< one per interleaved channel, unique
  bool isFloat = false;
  const void* values = nullptr;
};

/// Writes `file` (a temporary name the caller renames); `attributes` become
/// string attributes of the header, and `metadata` (if any) the frame's
/// chromaticities, colorInteropID, camera and fields (frame_metadata.h).
/// False, with OpenEXR's reason in `error`, when it cannot (the file is
/// then removed).
bool writeExr(const std::string& file, const ExrPixels& pixels, ExrCodec codec,
              const std::vector<std::pair<std::string, std::string>>& attributes,
              const FrameMetadata* metadata, std::string& error);

/// OpenEXR's run-length code of `bytes` (already reordered and predicted)
/// into `out` (room for size * 3 / 2 + 2 bytes): the very bytes OpenEXR's
/// own encoder makes, found faster. Returns the code's length.
size_t exrRunLengthCode(const unsigned char* bytes, size_t size, unsigned char* out);

}  // namespace acpca
