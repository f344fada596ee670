#include "relight/memory_bandwidth.h"

#include "core/stopwatch.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <vector>

namespace acpca {

namespace {

/// Sum of a[begin, end) in 32 independent lanes (the compiler vectorises them).
double laneSum(const float* a, size_t begin, size_t end) {
  constexpr size_t kLanes = 32;
  float lanes[kLanes] = {};
  size_t i = begin;
  for (; i + kLanes <= end; i += kLanes)
    for (size_t j = 0; j < kLanes; ++j) lanes[j] += a[i + j];
  double sum = 0;
  for (float v : lanes) sum += v;
  for (; i < end; ++i) sum += a[i];
  return sum;
}

}  // namespace

BandwidthMeasurement measureStreamingRead(double bytes, int passes) {
  const size_t count = static_cast<size_t>(bytes / sizeof(float));
  std::vector<float> data(count);
  // Touch every page in parallel so first-touch placement matches the readers.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1 << 20),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i) data[i] = float(i & 1023);
                    });
  BandwidthMeasurement m;
  m.bytes = double(count) * sizeof(float);
  std::vector<double> rates;
  for (int pass = -1; pass < passes; ++pass) {
    const Stopwatch watch;
    const double sum = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, count, 1 << 18), 0.0,
        [&](const tbb::blocked_range<size_t>& r, double acc) {
          return acc + laneSum(data.data(), r.begin(), r.end());
        },
        [](double a, double b) { return a + b; });
    const double seconds = watch.seconds();
    m.checksum += sum;
    if (pass >= 0) rates.push_back(m.bytes / seconds / 1e9);
  }
  std::sort(rates.begin(), rates.end());
  m.gbPerSecondMedian = rates.empty() ? 0 : rates[rates.size() / 2];
  m.gbPerSecondBest = rates.empty() ? 0 : rates.back();
  return m;
}

}  // namespace acpca
