#pragma once
// The machine's streaming-read bandwidth, measured the way the relighter reads:
// a plain loop summing a large array with every thread TBB has. The relighter's
// figures are reported as a fraction of it.

namespace acpca {

struct BandwidthMeasurement {
  double bytes = 0;              ///< size of the array read per pass
  double gbPerSecondMedian = 0;  ///< over the passes
  double gbPerSecondBest = 0;
  double checksum = 0;  ///< the sum, so the reads cannot be optimised away
};

/// Reads an array of `bytes` (far larger than the caches: use >= 1 GiB) `passes`
/// times after one warm-up pass.
BandwidthMeasurement measureStreamingRead(double bytes, int passes);

}  // namespace acpca
