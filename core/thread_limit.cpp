#include "core/thread_limit.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

namespace acpca {

ThreadLimit::ThreadLimit(int threads)
    : threads_(threads > 0 ? threads : tbb::info::default_concurrency()) {
  control_ =
      std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads_);
}

ThreadLimit::~ThreadLimit() = default;

}  // namespace acpca
