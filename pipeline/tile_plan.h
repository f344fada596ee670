#pragma once
// How the streamed build cuts the image: square tiles in row-major order, and
// the transport rows (occupied pixels) each tile holds.
#include <cstdint>
#include <vector>

#include "transport/camera.h"

namespace acpca {

struct Tile {
  int x0 = 0, y0 = 0, width = 0, height = 0;  ///< pixels; edge tiles are cut by the image
  std::vector<long long> rows;                ///< transport rows inside, increasing
};

/// Tiles of `side` pixels over the image, row-major (the order adaptive-quad
/// visits its root blocks); tiles without an occupied pixel are left out.
std::vector<Tile> planTiles(ImageSize size, const std::vector<std::int32_t>& pixels, int side);

/// Each of the tile's rows as a pixel index of the tile alone (y * width + x,
/// from its corner): a tile's rows cluster the same wherever it sits.
std::vector<std::int32_t> tilePixels(const Tile& tile, ImageSize size,
                                     const std::vector<std::int32_t>& pixels);

}  // namespace acpca
