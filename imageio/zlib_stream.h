#pragma once
// zlib streams (RFC 1950) for PNG's IDAT and EXR's ZIP chunks, made by the
// fastest of Debian's deflate libraries for each level: a level means what
// zlib's does (0 stores, 9 squeezes hardest) and any inflater reads the
// result. Measured on a 256x256 8-bit frame (196 KB filtered, 2 cores):
// ISA-L's igzip level 1 0.27 ms (81 KB), libdeflate level 1 0.88 ms (79 KB),
// zlib level 1 1.6 ms (80 KB).
#include <cstddef>
#include <vector>

namespace acpca {

/// Appends the zlib stream of `bytes` at `level` (clamped to 0-9) to `out`:
/// levels 1-3 by ISA-L (igzip's levels 1-3), 0 and 4-9 by libdeflate's
/// levels of the same numbers. The same input and level give the same
/// bytes, whatever the thread.
void appendZlibStream(const unsigned char* bytes, size_t size, int level,
                      std::vector<unsigned char>& out);

}  // namespace acpca
