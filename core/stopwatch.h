#pragma once
// Wall-clock timing for progress lines, reports and benchmarks: one steady
// clock, read as seconds or milliseconds since the stopwatch started.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <vector>

namespace acpca {

class Stopwatch {
 public:
  Stopwatch() : start_(Clock::now()) {}
  void restart() { start_ = Clock::now(); }
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  double milliseconds() const { return 1e3 * seconds(); }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_;
};

/// Median ms of `frames` calls of `work` after one untimed warm-up; NAN for none.
inline double medianMilliseconds(const std::function<void()>& work, int frames) {
  if (frames <= 0) return NAN;
  work();  // warm-up: caches, page faults, thread start
  std::vector<double> ms;
  for (int k = 0; k < frames; ++k) {
    const Stopwatch watch;
    work();
    ms.push_back(watch.milliseconds());
  }
  std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
  return ms[ms.size() / 2];
}

}  // namespace acpca
