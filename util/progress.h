// Progress: a one-line bar on stderr with percentage, rays/s and ETA for long work.
// Disabled (prints nothing) with --quiet. Not thread-safe: call it from the driving thread.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace dacrt {

class Progress {
 public:
  Progress(std::string label, uint64_t total, bool enabled);
  ~Progress();
  // `done` units of `total` are finished; `rays` is the running count of rays traced.
  void update(uint64_t done, uint64_t rays);
  void finish();

 private:
  std::string label_;
  uint64_t total_;
  bool enabled_;
  bool tty_;
  bool finished_ = false;
  int last_percent_ = -1;
  std::chrono::steady_clock::time_point start_, last_print_;
};

}  // namespace dacrt
