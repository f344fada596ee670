#include "pipeline/tile_plan.h"

#include "core/error.h"

namespace acpca {

std::vector<Tile> planTiles(ImageSize size, const std::vector<std::int32_t>& pixels, int side) {
  if (side < 1) throw ParameterError("tile side", side, "must be >= 1");
  const int across = (size.width + side - 1) / side, down = (size.height + side - 1) / side;
  std::vector<Tile> all(static_cast<size_t>(across) * down);
  for (int ty = 0; ty < down; ++ty)
    for (int tx = 0; tx < across; ++tx) {
      Tile& t = all[static_cast<size_t>(ty) * across + tx];
      t.x0 = tx * side, t.y0 = ty * side;
      t.width = std::min(side, size.width - t.x0), t.height = std::min(side, size.height - t.y0);
    }
  for (size_t r = 0; r < pixels.size(); ++r) {  // rows are in pixel order: each list sorted
    const int x = pixels[r] % size.width, y = pixels[r] / size.width;
    all[static_cast<size_t>(y / side) * across + x / side].rows.push_back(
        static_cast<long long>(r));
  }
  std::vector<Tile> tiles;
  for (auto& t : all)
    if (!t.rows.empty()) tiles.push_back(std::move(t));
  return tiles;
}

std::vector<std::int32_t> tilePixels(const Tile& tile, ImageSize size,
                                     const std::vector<std::int32_t>& pixels) {
  std::vector<std::int32_t> local;
  local.reserve(tile.rows.size());
  for (long long r : tile.rows) {
    const int x = pixels[r] % size.width - tile.x0, y = pixels[r] / size.width - tile.y0;
    local.push_back(y * tile.width + x);
  }
  return local;
}

}  // namespace acpca
