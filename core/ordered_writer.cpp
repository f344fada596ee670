#include "core/ordered_writer.h"

#include <algorithm>

namespace acpca {

OrderedWriter::OrderedWriter(int threads, size_t capacity)
    : capacity_(std::max<size_t>(1, capacity)) {
  for (int t = 0; t < std::max(1, threads); ++t) threads_.emplace_back([this] { work(); });
}

OrderedWriter::~OrderedWriter() {
  {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return committed_ == submitted_ || error_; });
    stopping_ = true;
  }
  changed_.notify_all();
  for (auto& t : threads_) t.join();
}

void OrderedWriter::rethrowError() {
  if (error_) std::rethrow_exception(error_);
}

void OrderedWriter::submit(Job job) {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return submitted_ - committed_ < capacity_ || error_; });
  rethrowError();
  queue_.emplace_back(submitted_++, std::move(job));
  changed_.notify_all();
}

void OrderedWriter::finish() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return committed_ == submitted_ || error_; });
  rethrowError();
}

size_t OrderedWriter::committed() const {
  std::lock_guard lock(mutex_);
  return committed_;
}

void OrderedWriter::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return !queue_.empty() || stopping_; });
    if (queue_.empty()) return;  // stopping, nothing left
    auto [index, job] = std::move(queue_.front());
    queue_.erase(queue_.begin());
    Commit commit;
    if (!error_) {
      lock.unlock();
      try {
        commit = job();
      } catch (...) {
        lock.lock();
        if (!error_) error_ = std::current_exception();
        changed_.notify_all();
        continue;
      }
      lock.lock();
    }
    done_.emplace(index, std::move(commit));
    commitReady(lock);
    changed_.notify_all();
  }
}

void OrderedWriter::commitReady(std::unique_lock<std::mutex>& lock) {
  // One thread commits at a time, in order; the others leave it the items
  // they finish.
  if (committing_) return;
  committing_ = true;
  while (!error_ && !done_.empty() && done_.begin()->first == committed_) {
    Commit commit = std::move(done_.begin()->second);
    done_.erase(done_.begin());
    lock.unlock();
    try {
      if (commit) commit();
    } catch (...) {
      lock.lock();
      if (!error_) error_ = std::current_exception();
      break;
    }
    lock.lock();
    ++committed_;
    changed_.notify_all();
  }
  committing_ = false;
}

}  // namespace acpca
