#pragma once
// A cap on TBB's worker threads for as long as it lives (--threads).
#include <tbb/global_control.h>

#include <memory>

namespace acpca {

/// Caps TBB at `threads` worker threads (0: all cores) while it lives.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  int threads() const { return threads_; }

 private:
  std::unique_ptr<tbb::global_control> control_;
  int threads_;
};

}  // namespace acpca
