#pragma once
// The dense relight B = albedo (T L) from memory, as fast as dense can be: T in
// half precision, each row kept only where it is non-zero (in segments of 16
// texels), so directions below a pixel's horizon or blocked for it cost nothing.
// The yardstick the model relighter is measured against.
#include <cstdint>
#include <vector>

#include "lighting/environment.h"
#include "transport/transport_file.h"

namespace acpca {

class SparseTransport {
 public:
  /// Reads the whole transport (one pass over the file).
  explicit SparseTransport(const TransportReader& transport);

  /// rgb: 3 floats per row, albedo applied, in the file's row order.
  void relight(const LatticeLighting& lighting, float* rgb);
  std::vector<float> relight(const LatticeLighting& lighting);

  long long rows() const { return static_cast<long long>(rowStart_.size()) - 1; }
  /// Bytes one frame reads: kept values, segment indices and albedo.
  long long bytesPerFrame() const;
  /// Fraction of T's entries inside kept segments.
  double keptFraction() const;

 private:
  int latticeSize_ = 0, rowLength_ = 0, channels_ = 1, paddedSize_ = 0;
  std::vector<long long> rowStart_;      ///< rows + 1, into segments_
  std::vector<std::uint16_t> segments_;  ///< index of each kept segment
  std::vector<std::uint16_t> values_;    ///< 16 halves per kept segment
  std::vector<float> albedo_;
  std::vector<float> light_;  ///< per frame: 3 x paddedSize_, channel-major
};

}  // namespace acpca
