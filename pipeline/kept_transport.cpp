#include "pipeline/kept_transport.h"

#include <algorithm>
#include <cstring>

#include "core/error.h"

namespace acpca {

KeptTransport::KeptTransport(const std::string& path, const TransportHeader& header,
                             const std::vector<Tile>& tiles)
    : writer_(path, header), tiles_(tiles), rowLength_(header.rowLength()) {}

void KeptTransport::startBand(size_t firstTile) {
  bandY0_ = tiles_[firstTile].y0;
  bandFirst_ = tiles_[firstTile].rows.front();
  bandEnd_ = bandFirst_;
  for (size_t t = firstTile; t < tiles_.size() && tiles_[t].y0 == bandY0_; ++t) {
    bandFirst_ = std::min(bandFirst_, tiles_[t].rows.front());
    bandEnd_ = std::max(bandEnd_, tiles_[t].rows.back() + 1);
  }
  band_.assign(static_cast<size_t>((bandEnd_ - bandFirst_) * rowLength_), 0.0f);
}

void KeptTransport::writeBand() {
  if (bandEnd_ > bandFirst_) writer_.writeRows(bandFirst_, bandEnd_ - bandFirst_, band_.data());
  bandFirst_ = bandEnd_ = 0;
  band_.clear();
}

void KeptTransport::add(size_t tile, const float* rows) {
  ACPCA_CHECK(tile == nextTile_, "kept transport: tile ", tile, " arrived, ", nextTile_,
              " expected");
  const Tile& t = tiles_[tile];
  if (t.y0 != bandY0_) {
    writeBand();
    startBand(tile);
  }
  // Every occupied pixel of the band's image rows lies in one of its tiles,
  // so the band's tiles fill [bandFirst_, bandEnd_) exactly.
  for (size_t i = 0; i < t.rows.size(); ++i)
    std::memcpy(band_.data() + (t.rows[i] - bandFirst_) * rowLength_, rows + i * rowLength_,
                sizeof(float) * rowLength_);
  ++nextTile_;
}

void KeptTransport::finish() {
  ACPCA_CHECK(nextTile_ == tiles_.size(), "kept transport: ", nextTile_, " of ", tiles_.size(),
              " tiles");
  writeBand();
  writer_.finish();
}

}  // namespace acpca
