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

StreamingRead::StreamingRead(double bytes) : data_(static_cast<size_t>(bytes / sizeof(float))) {
  // Touch every page in parallel so first-touch placement matches the readers.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, data_.size(), 1 << 20),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i) data_[i] = float(i & 1023);
                    });
}

double StreamingRead::pass() {
  const Stopwatch watch;
  checksum_ += tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, data_.size(), 1 << 18), 0.0,
      [&](const tbb::blocked_range<size_t>& r, double acc) {
        return acc + laneSum(data_.data(), r.begin(), r.end());
      },
      [](double a, double b) { return a + b; });
  return bytes() / watch.seconds() / 1e9;
}

BandwidthMeasurement measureStreamingRead(double bytes, int passes) {
  StreamingRead array(bytes);
  BandwidthMeasurement m;
  m.bytes = array.bytes();
  array.pass();  // warm-up
  std::vector<double> rates;
  for (int pass = 0; pass < passes; ++pass) rates.push_back(array.pass());
  m.checksum = array.checksum();
  std::sort(rates.begin(), rates.end());
  m.gbPerSecondMedian = rates.empty() ? 0 : rates[rates.size() / 2];
  m.gbPerSecondBest = rates.empty() ? 0 : rates.back();
  return m;
}

}  // namespace acpca
