#pragma once
// An encoded image written to its file in one call: the kernel then fills
// whole pages, where many small writes at offsets made it zero each page's
// unwritten part first (an EXR's 1,024 RLE scanline chunks, a tenth of a
// 1024x1024 batch's CPU by perf).
#include <string>

namespace acpca {

/// Writes `size` bytes to `file` (created or truncated); false with the
/// system's words in `error` when it cannot, the partial file removed.
bool writeWholeFile(const std::string& file, const void* bytes, size_t size, std::string& error);

}  // namespace acpca
