#pragma once
// A picture in memory: float values, rows from the top, channels interleaved
// (3: RGB; 4: RGB and alpha, coverage in [0, 1]).
#include <cstddef>
#include <vector>

namespace acpca {

struct Image {
  int width = 0, height = 0, channels = 3;
  std::vector<float> pixels;  ///< row-major, row 0 at the top
  float* at(int x, int y) { return &pixels[(static_cast<size_t>(y) * width + x) * channels]; }
  const float* at(int x, int y) const {
    return &pixels[(static_cast<size_t>(y) * width + x) * channels];
  }
};

}  // namespace acpca
