#pragma once
// Writing that overlaps computing: jobs (encode a frame, write it under a
// temporary name) run on a few threads of their own while the caller computes
// the next item, and each job's commit (rename into place, a manifest row)
// runs in submission order, so what appears on disk is always a prefix of the
// items and never depends on which job finished first. The queue is bounded:
// memory holds at most `capacity` items however many are submitted.
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

namespace acpca {

class OrderedWriter {
 public:
  /// What a job hands back: run, in submission order, once every earlier
  /// job's commit has run.
  using Commit = std::function<void()>;
  using Job = std::function<Commit()>;

  /// `threads` writing threads (at least 1), at most `capacity` jobs queued,
  /// running or waiting for their turn to commit.
  OrderedWriter(int threads, size_t capacity);
  /// Waits for the jobs submitted; an error is dropped (finish() reports it).
  ~OrderedWriter();
  OrderedWriter(const OrderedWriter&) = delete;
  OrderedWriter& operator=(const OrderedWriter&) = delete;

  /// Queues the next job; blocks while `capacity` are in flight. Rethrows the
  /// first error of an earlier job or commit (after which nothing more commits).
  void submit(Job job);
  /// Waits until every job has committed; rethrows the first error.
  void finish();
  /// Jobs committed so far.
  size_t committed() const;

 private:
  void work();
  void commitReady(std::unique_lock<std::mutex>& lock);
  void rethrowError();

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::pair<size_t, Job>> queue_;  ///< waiting to run, oldest first
  std::map<size_t, Commit> done_;              ///< run, waiting for their turn
  size_t submitted_ = 0, committed_ = 0, capacity_;
  bool committing_ = false, stopping_ = false;
  std::exception_ptr error_;
  std::vector<std::thread> threads_;
};

}  // namespace acpca
