#pragma once
// `build --keep-transport FILE`: the dense transport a streamed build renders
// anyway, written as `precompute` writes it, for users who want the model and
// T and have the disk. Tiles finish in tile order (row-major); the rows of a
// tile row (one row of tiles across the image) are one contiguous run of
// transport rows, so a tile row is held until its last tile arrives and then
// written in row order: memory is one tile row (about 1 GB of floats at
// 1024x1024 with 64-pixel tiles), not the transport.
#include <string>
#include <vector>

#include "pipeline/tile_plan.h"
#include "transport/transport_file.h"

namespace acpca {

class KeptTransport {
 public:
  KeptTransport(const std::string& path, const TransportHeader& header,
                const std::vector<Tile>& tiles);
  /// The rendered rows of tile `tile` (its rows x rowLength floats); every
  /// tile, in increasing order.
  void add(size_t tile, const float* rows);
  /// Writes the last tile row and moves the file into place.
  void finish();

 private:
  void startTileRow(size_t firstTile);
  void writeTileRow();

  TransportWriter writer_;
  const std::vector<Tile>& tiles_;
  long long rowLength_ = 0;
  size_t nextTile_ = 0;
  int tileRowY0_ = -1;
  long long tileRowFirst_ = 0, tileRowEnd_ = 0;  ///< transport rows of the tile row being filled
  std::vector<float> tileRow_;
};

}  // namespace acpca
