#pragma once
// NumPy's .npy format (version 1.0): a short text header giving the dtype and
// shape, then the values in C order, so Python reads a label with np.load
// and nothing else.
#include <cstdint>
#include <string>
#include <vector>

namespace acpca {

/// Writes `values` (the product of `shape` of them, C order) as little-endian
/// float32 into `file` (a temporary name the caller renames; errors name `path`).
void writeNpy(const std::string& file, const std::string& path, const std::vector<size_t>& shape,
              const float* values);
/// The same as int32.
void writeNpy(const std::string& file, const std::string& path, const std::vector<size_t>& shape,
              const std::int32_t* values);

}  // namespace acpca
