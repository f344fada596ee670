#include "pipeline/kept_transport.h"

#include <algorithm>
#include <cstring>

#include "core/error.h"

namespace acpca {

KeptTransport::KeptTransport(const std::string& path, const TransportHeader& header,
                             const std::vector<Tile>& tiles)
    : writer_(path, header), tiles_(tiles), rowLength_(header.rowLength()) {}

void KeptTransport::startTileRow(size_t firstTile) {
  tileRowY0_ = tiles_[firstTile].y0;
  tileRowFirst_ = tiles_[firstTile].rows.front();
  tileRowEnd_ = tileRowFirst_;
  for (size_t t = firstTile; t < tiles_.size() && tiles_[t].y0 == tileRowY0_; ++t) {
    tileRowFirst_ = std::min(tileRowFirst_, tiles_[t].rows.front());
    tileRowEnd_ = std::max(tileRowEnd_, tiles_[t].rows.back() + 1);
  }
  tileRow_.assign(static_cast<size_t>((tileRowEnd_ - tileRowFirst_) * rowLength_), 0.0f);
}

void KeptTransport::writeTileRow() {
  if (tileRowEnd_ > tileRowFirst_)
    writer_.writeRows(tileRowFirst_, tileRowEnd_ - tileRowFirst_, tileRow_.data());
  tileRowFirst_ = tileRowEnd_ = 0;
  tileRow_.clear();
}

void KeptTransport::add(size_t tile, const float* rows) {
  ACPCA_CHECK(tile == nextTile_, "kept transport: tile ", tile, " arrived, ", nextTile_,
              " expected");
  const Tile& t = tiles_[tile];
  if (t.y0 != tileRowY0_) {
    writeTileRow();
    startTileRow(tile);
  }
  // Every occupied pixel of the tile row's image rows lies in one of its
  // tiles, so its tiles fill [tileRowFirst_, tileRowEnd_) exactly.
  for (size_t i = 0; i < t.rows.size(); ++i)
    std::memcpy(tileRow_.data() + (t.rows[i] - tileRowFirst_) * rowLength_, rows + i * rowLength_,
                sizeof(float) * rowLength_);
  ++nextTile_;
}

void KeptTransport::finish() {
  ACPCA_CHECK(nextTile_ == tiles_.size(), "kept transport: ", nextTile_, " of ", tiles_.size(),
              " tiles");
  writeTileRow();
  writer_.finish();
}

}  // namespace acpca
