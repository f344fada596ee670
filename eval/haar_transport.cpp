#include "eval/haar_transport.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.h"
#include "core/half.h"
#include "transport/row_stream.h"

namespace acpca {

namespace {

constexpr int kBlockRows = 1 << 16;  // row indices fit 16 bits
constexpr float kInvSqrt2 = 0.70710678118654752f;

/// One level along rows then columns of the top-left n x n corner.
void forwardLevel(float* face, int stride, int n, std::vector<float>& tmp) {
  const int h = n / 2;
  for (int y = 0; y < n; ++y) {
    float* row = face + y * stride;
    for (int i = 0; i < h; ++i) {
      tmp[i] = (row[2 * i] + row[2 * i + 1]) * kInvSqrt2;
      tmp[h + i] = (row[2 * i] - row[2 * i + 1]) * kInvSqrt2;
    }
    std::copy_n(tmp.data(), n, row);
  }
  for (int x = 0; x < n; ++x) {
    for (int i = 0; i < h; ++i) {
      const float a = face[2 * i * stride + x], b = face[(2 * i + 1) * stride + x];
      tmp[i] = (a + b) * kInvSqrt2;
      tmp[h + i] = (a - b) * kInvSqrt2;
    }
    for (int i = 0; i < n; ++i) face[i * stride + x] = tmp[i];
  }
}

void inverseLevel(float* face, int stride, int n, std::vector<float>& tmp) {
  const int h = n / 2;
  for (int x = 0; x < n; ++x) {
    for (int i = 0; i < h; ++i) {
      const float s = face[i * stride + x], d = face[(h + i) * stride + x];
      tmp[2 * i] = (s + d) * kInvSqrt2;
      tmp[2 * i + 1] = (s - d) * kInvSqrt2;
    }
    for (int i = 0; i < n; ++i) face[i * stride + x] = tmp[i];
  }
  for (int y = 0; y < n; ++y) {
    float* row = face + y * stride;
    for (int i = 0; i < h; ++i) {
      tmp[2 * i] = (row[i] + row[h + i]) * kInvSqrt2;
      tmp[2 * i + 1] = (row[i] - row[h + i]) * kInvSqrt2;
    }
    std::copy_n(tmp.data(), n, row);
  }
}

}  // namespace

void haarForward2d(float* face, int resolution) {
  std::vector<float> tmp(resolution);
  for (int n = resolution; n >= 2; n /= 2) forwardLevel(face, resolution, n, tmp);
}

void haarInverse2d(float* face, int resolution) {
  std::vector<float> tmp(resolution);
  for (int n = 2; n <= resolution; n *= 2) inverseLevel(face, resolution, n, tmp);
}

HaarTransport::HaarTransport(const TransportReader& transport, int bits)
    : resolution_(transport.header().cubemapResolution),
      latticeSize_(transport.latticeSize()),
      rowLength_(transport.rowLength()),
      channels_(transport.header().channels),
      rows_(transport.rows()),
      albedo_(transport.header().albedo) {
  if (resolution_ & (resolution_ - 1))
    throw UserError(concat(transport.path(),
                           ": the Haar baseline needs a power-of-two cube map, not ", resolution_));
  const int faceSize = resolution_ * resolution_;
  const float keep = bits > 0 ? std::exp2(float(-bits)) : 0.0f;
  const long long chunk = rowsPerBlock(transport);
  std::vector<float> buffer(static_cast<size_t>(chunk) * rowLength_);
  for (long long first = 0; first < rows_; first += kBlockRows) {
    RowBlock block;
    block.firstRow = first;
    const long long count = std::min<long long>(kBlockRows, rows_ - first);
    // Entries in row order, then bucketed by column (a counting sort).
    std::vector<std::uint32_t> entryColumn;
    std::vector<std::uint16_t> entryRow;
    std::vector<float> entryValue;
    for (long long r0 = 0; r0 < count; r0 += chunk) {
      const long long n = std::min(chunk, count - r0);
      transport.readRows(first + r0, n, buffer.data());
      tbb::parallel_for(0LL, n, [&](long long r) {
        float* row = buffer.data() + r * rowLength_;
        for (int f = 0; f * faceSize < rowLength_; ++f)  // every face of every channel
          haarForward2d(row + f * faceSize, resolution_);
      });
      for (long long r = 0; r < n; ++r) {
        const float* row = buffer.data() + r * rowLength_;
        float largest = 0;
        for (int j = 0; j < rowLength_; ++j) largest = std::max(largest, std::abs(row[j]));
        const float threshold = std::max(largest * keep, std::numeric_limits<float>::min());
        for (int j = 0; j < rowLength_; ++j)
          if (std::abs(row[j]) >= threshold) {
            entryColumn.push_back(static_cast<std::uint32_t>(j));
            entryRow.push_back(static_cast<std::uint16_t>(r0 + r));
            entryValue.push_back(std::clamp(row[j], -kHalfMax, kHalfMax));
          }
      }
    }
    block.columnStart.assign(rowLength_ + 1, 0);
    for (auto j : entryColumn) ++block.columnStart[j + 1];
    std::partial_sum(block.columnStart.begin(), block.columnStart.end(), block.columnStart.begin());
    std::vector<std::int64_t> next(block.columnStart.begin(), block.columnStart.end() - 1);
    std::vector<std::uint16_t> halves(entryValue.size());
    floatToHalf(entryValue.data(), halves.data(), halves.size());
    block.row.resize(entryColumn.size());
    block.value.resize(entryColumn.size());
    for (size_t e = 0; e < entryColumn.size(); ++e) {
      const auto at = next[entryColumn[e]]++;
      block.row[at] = entryRow[e];
      block.value[at] = halves[e];
    }
    blocks_.push_back(std::move(block));
  }
  light_.assign(3 * static_cast<size_t>(latticeSize_), 0.0f);
}

double HaarTransport::fillRatio() const {
  double kept = 0;
  for (const auto& b : blocks_) kept += b.row.size();
  const double all = double(rows_) * rowLength_;
  return all > 0 ? kept / all : 0;
}

long long HaarTransport::bytes() const {
  long long total = static_cast<long long>(albedo_.size()) * 4;
  for (const auto& b : blocks_)
    total +=
        static_cast<long long>(b.row.size()) * 4 + static_cast<long long>(b.columnStart.size()) * 8;
  return total;
}

void HaarTransport::relight(const LatticeLighting& lighting, int terms, float* rgb) {
  ACPCA_CHECK(static_cast<long long>(lighting.size()) == 3LL * latticeSize_, "lighting has ",
              lighting.size(), " values for a lattice of ", latticeSize_);
  const int faceSize = resolution_ * resolution_;
  for (int c = 0; c < 3; ++c) {
    float* channel = light_.data() + c * latticeSize_;
    for (int j = 0; j < latticeSize_; ++j) channel[j] = static_cast<float>(lighting[3 * j + c]);
    for (int f = 0; f * faceSize < latticeSize_; ++f)
      haarForward2d(channel + f * faceSize, resolution_);
  }
  // The k largest coefficients by RGB magnitude; ties broken by index, so the
  // choice is deterministic.
  std::vector<int> order(latticeSize_);
  std::iota(order.begin(), order.end(), 0);
  const auto magnitude = [&](int j) {
    double m = 0;
    for (int c = 0; c < 3; ++c)
      m += double(light_[c * latticeSize_ + j]) * light_[c * latticeSize_ + j];
    return m;
  };
  const int k = std::clamp(terms, 0, latticeSize_);
  std::vector<double> mag(latticeSize_);
  for (int j = 0; j < latticeSize_; ++j) mag[j] = magnitude(j);
  std::partial_sort(order.begin(), order.begin() + k, order.end(),
                    [&](int a, int b) { return mag[a] != mag[b] ? mag[a] > mag[b] : a < b; });
  order.resize(k);
  std::sort(order.begin(), order.end());
  // With R, G and B rows, term j is column j of each channel's part, lit by
  // that channel alone.
  double entries = 0;
  for (const auto& b : blocks_)
    for (int j : order)
      for (int part = 0; part < channels_; ++part)
        entries += double(b.columnStart[part * latticeSize_ + j + 1] -
                          b.columnStart[part * latticeSize_ + j]);
  lastCost_ = rows_ ? entries / rows_ / channels_ : 0;  // in RGB triples

  tbb::parallel_for(0, static_cast<int>(blocks_.size()), [&](int bi) {
    const RowBlock& b = blocks_[bi];
    const long long count = std::min<long long>(kBlockRows, rows_ - b.firstRow);
    float* out = rgb + 3 * b.firstRow;
    std::fill(out, out + 3 * count, 0.0f);
    constexpr int kBatch = 256;
    float values[kBatch];
    for (int term : order)
      for (int part = 0; part < channels_; ++part) {
        const int j = part * latticeSize_ + term;
        float l[3];
        for (int c = 0; c < 3; ++c)
          l[c] = channels_ == 1 || c == part ? light_[c * latticeSize_ + term] : 0.0f;
        for (auto e0 = b.columnStart[j]; e0 < b.columnStart[j + 1]; e0 += kBatch) {
          const int n = static_cast<int>(std::min<std::int64_t>(kBatch, b.columnStart[j + 1] - e0));
          halfToFloat(b.value.data() + e0, values, n);
          for (int e = 0; e < n; ++e) {
            float* o = out + 3 * b.row[e0 + e];
            o[0] += values[e] * l[0];
            o[1] += values[e] * l[1];
            o[2] += values[e] * l[2];
          }
        }
      }
    for (long long r = 0; r < 3 * count; ++r) out[r] *= albedo_[3 * b.firstRow + r];
  });
}

std::vector<float> HaarTransport::relight(const LatticeLighting& lighting, int terms) {
  std::vector<float> rgb(3 * rows_);
  relight(lighting, terms, rgb.data());
  return rgb;
}

}  // namespace acpca
