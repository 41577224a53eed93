// StopOnSignals: while one is alive, the first SIGINT or SIGTERM asks long work to stop (a
// render finishes its paths in flight and writes what it has) instead of ending the process; a
// second one ends it at once, as the default action would, removing any temporary file being
// written (util/atomic_file.h).
#pragma once

#include <atomic>

namespace dacrt {

class StopOnSignals {
 public:
  StopOnSignals();
  ~StopOnSignals();
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;

  const std::atomic<bool>& token() const;
  int signal() const;  // the signal received, 0 if none
};

}  // namespace dacrt
