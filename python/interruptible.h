// Long calls from Python: the work runs on a thread of its own while the calling thread, the GIL
// released, waits for it. Every 50 ms the caller takes the GIL back to run Python's signal
// handlers (PyErr_CheckSignals), so Ctrl-C raises KeyboardInterrupt as it does in pure Python
// code: the stop token is set, the work ends at its next wavefront, and the exception is raised
// once it has (nothing is left running behind Python's back). Other Python threads run while
// the work does.
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

namespace dacrt::python {

// Runs work() (which must end soon after `stop` turns true) and returns its result; rethrows its
// exception; throws pybind11::error_already_set (KeyboardInterrupt, or whatever a signal handler
// raised) when a handler raised while it ran. Called with the GIL held.
template <class Work>
auto run_interruptible(std::atomic<bool>& stop, Work work) -> decltype(work()) {
  using Result = decltype(work());
  std::optional<Result> result;
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable done_cv;
  bool done = false;
  bool interrupted = false;
  {
    pybind11::gil_scoped_release unlocked;
    std::thread worker([&] {
      try {
        result.emplace(work());
      } catch (...) {
        failure = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(mutex);
      done = true;
      done_cv.notify_one();
    });
    std::unique_lock<std::mutex> lock(mutex);
    while (!done_cv.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; })) {
      if (interrupted) continue;  // asked to stop already: wait for the work to end
      lock.unlock();
      {
        pybind11::gil_scoped_acquire locked;
        // -1: a handler raised; the exception stays set until the work has ended.
        interrupted = PyErr_CheckSignals() != 0;
      }
      if (interrupted) stop = true;
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (interrupted) throw pybind11::error_already_set();
  if (failure) std::rethrow_exception(failure);
  return std::move(*result);
}

}  // namespace dacrt::python
