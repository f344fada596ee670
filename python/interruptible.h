#pragma once
// Long calls from Python: the work runs on its own thread while Python's
// thread waits without the GIL, waking every 50 ms to run Python's signal
// handlers. Ctrl-C (a KeyboardInterrupt from a handler) or an exception in a
// Python callback sets the cancel flag; the work's next check throws
// Cancelled and unwinds (its outputs are written atomically, so nothing
// half-written stays), and Python sees the KeyboardInterrupt or the callback's
// own exception.
#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

namespace acpca::python {

namespace py = pybind11;

/// Thrown by a cancelled work's checks; never seen by Python.
struct Cancelled : std::exception {
  const char* what() const noexcept override { return "cancelled"; }
};

/// What the work gets: the cancel check, and a way to call Python.
class WorkContext {
 public:
  /// Throws Cancelled once the call is to stop.
  void check() const {
    if (cancel_) throw Cancelled{};
  }
  /// Calls f with the GIL held; a Python exception from it cancels the work
  /// and is raised in the caller when the work has unwound.
  void callPython(const std::function<void()>& f) {
    check();
    py::gil_scoped_acquire gil;
    try {
      f();
    } catch (py::error_already_set& e) {
      pending_ = std::make_shared<py::error_already_set>(std::move(e));
      cancel_ = true;
      throw Cancelled{};
    }
  }

 private:
  template <typename F>
  friend void runInterruptible(F&& work);
  std::atomic<bool> cancel_{false};
  std::shared_ptr<py::error_already_set> pending_;
};

/// Runs work(context) as described above; called with the GIL held.
template <typename F>
void runInterruptible(F&& work) {
  WorkContext context;
  std::exception_ptr error;
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::thread worker([&] {
    try {
      work(context);
    } catch (...) {
      error = std::current_exception();
    }
    std::lock_guard lock(mutex);
    done = true;
    finished.notify_all();
  });
  bool interrupted = false;
  for (;;) {
    {
      py::gil_scoped_release release;
      std::unique_lock lock(mutex);
      if (finished.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; })) break;
    }
    if (!interrupted && PyErr_CheckSignals() != 0) {  // the handler raised (Ctrl-C)
      interrupted = true;
      context.cancel_ = true;
    }
  }
  {
    py::gil_scoped_release release;
    worker.join();
  }
  if (interrupted) throw py::error_already_set();
  if (context.pending_) {
    context.pending_->restore();
    context.pending_.reset();
    throw py::error_already_set();
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace acpca::python
