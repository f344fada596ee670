#include "eval/sparse_transport.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/half.h"
#include "relight/relight_kernels.h"
#include "transport/row_layout.h"
#include "transport/row_stream.h"

namespace acpca {

using kernels::kChunkRows;

SparseTransport::SparseTransport(const TransportReader& transport)
    : latticeSize_(transport.latticeSize()),
      rowLength_(transport.rowLength()),
      channels_(transport.header().channels),
      paddedSize_((transport.rowLength() + kChunkRows - 1) / kChunkRows * kChunkRows),
      albedo_(transport.header().albedo) {
  ACPCA_CHECK(paddedSize_ / kChunkRows <= 65536, "rows of ", rowLength_,
              " values need more segments than 16-bit indices hold");
  const long long rows = transport.rows();
  const long long block = rowsPerBlock(transport);
  std::vector<float> buffer(static_cast<size_t>(block) * rowLength_);
  std::vector<float> padded(paddedSize_, 0.0f);
  std::uint16_t segment[kChunkRows];
  rowStart_.push_back(0);
  for (long long first = 0; first < rows; first += block) {
    const long long count = std::min(block, rows - first);
    transport.readRows(first, count, buffer.data());
    for (long long r = 0; r < count; ++r) {
      std::copy_n(buffer.data() + r * rowLength_, rowLength_, padded.data());
      for (int s = 0; s * kChunkRows < paddedSize_; ++s) {
        const float* v = padded.data() + s * kChunkRows;
        if (std::all_of(v, v + kChunkRows, [](float x) { return x == 0.0f; })) continue;
        floatToHalf(v, segment, kChunkRows);
        segments_.push_back(static_cast<std::uint16_t>(s));
        values_.insert(values_.end(), segment, segment + kChunkRows);
      }
      rowStart_.push_back(static_cast<long long>(segments_.size()));
    }
  }
  segments_.shrink_to_fit();
  values_.shrink_to_fit();
  light_.assign(3 * static_cast<size_t>(paddedSize_), 0.0f);
}

long long SparseTransport::bytesPerFrame() const {
  return static_cast<long long>(values_.size()) * 2 + static_cast<long long>(segments_.size()) * 2 +
         static_cast<long long>(albedo_.size()) * 4;
}

double SparseTransport::keptFraction() const {
  const double all = double(rows()) * rowLength_;
  return all > 0 ? double(values_.size()) / all : 0;
}

void SparseTransport::relight(const LatticeLighting& lighting, float* rgb) {
  const auto onRows = lightingOnRows(lighting, latticeSize_, channels_);
  for (int e = 0; e < rowLength_; ++e)
    for (int c = 0; c < 3; ++c) light_[c * paddedSize_ + e] = onRows(e, c);
  const float* light[3] = {light_.data(), light_.data() + paddedSize_,
                           light_.data() + 2 * paddedSize_};
  tbb::parallel_for(tbb::blocked_range<long long>(0, rows(), 256),
                    [&](const tbb::blocked_range<long long>& range) {
                      for (long long r = range.begin(); r != range.end(); ++r) {
                        const long long first = rowStart_[r];
                        float b[3];
                        kernels::dotSegmentsRgb(
                            values_.data() + first * kChunkRows, segments_.data() + first,
                            static_cast<int>(rowStart_[r + 1] - first), light, b);
                        for (int c = 0; c < 3; ++c) rgb[3 * r + c] = albedo_[3 * r + c] * b[c];
                      }
                    });
}

std::vector<float> SparseTransport::relight(const LatticeLighting& lighting) {
  std::vector<float> rgb(3 * rows());
  relight(lighting, rgb.data());
  return rgb;
}

}  // namespace acpca
