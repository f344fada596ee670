#pragma once
// The machine's streaming-read bandwidth, measured the way the relighter reads:
// a plain loop summing a large array with every thread TBB has. The relighter's
// figures are reported as a fraction of it.
#include <vector>

#include "core/huge_pages.h"

namespace acpca {

struct BandwidthMeasurement {
  double bytes = 0;              ///< size of the array read per pass
  double gbPerSecondMedian = 0;  ///< over the passes
  double gbPerSecondBest = 0;
  double checksum = 0;  ///< the sum, so the reads cannot be optimised away
};

/// An array far larger than the caches (use >= 256 MiB), read a pass at a time.
/// On a shared host the bandwidth drifts within seconds, so a benchmark reads
/// one pass right before each frame it times and sets the two side by side.
class StreamingRead {
 public:
  explicit StreamingRead(double bytes);
  /// One pass with every thread TBB has: GB/s.
  double pass();
  double bytes() const { return static_cast<double>(data_.size() * sizeof(float)); }
  double checksum() const { return checksum_; }

 private:
  HugePageVector<float> data_;  ///< on huge pages, as the relighter's arrays
  double checksum_ = 0;
};

/// Reads an array of `bytes` (far larger than the caches: use >= 1 GiB) `passes`
/// times after one warm-up pass.
BandwidthMeasurement measureStreamingRead(double bytes, int passes);

}  // namespace acpca
