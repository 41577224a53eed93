// Progress: what long work says on stderr while it runs. On a terminal a one-line bar redrawn in
// place (percentage, rays/s, ETA); in a log (stderr not a TTY) a line at each 10 % step, after
// the first second, then every 5 seconds (every 30 after the first five minutes), and one when
// the work ends.
// A Progress may be one part of a longer whole (frame 3 of 5, backend 2 of 3): its lines say
// which, and the whole's ETA. Activity covers a step with no progress of its own (a load, a
// build). Disabled (prints nothing) with --quiet. Call update() and finish() from the driving
// thread; a thread of the Progress's own prints on time when updates do not come.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace dacrt {

// Where the lines go and what time it is: stderr (a terminal or not) and the steady clock, or
// what a test injects.
struct ProgressOutput {
  std::function<void(const std::string&)> write;  // the text as it is (with its '\r' or '\n')
  std::function<double()> now;                    // seconds, monotonic
  bool terminal = false;
  // stderr, isatty(STDERR_FILENO), std::chrono::steady_clock.
  static ProgressOutput standard_error();
};

// When a log gets a line: after `first` seconds, then every `every`, every `later` once `late`
// seconds have gone by; with `tenths`, also at each 10 % step, and always at the end (a reader
// of the lines, such as the Blender add-on, then sees short work move in tenths). With `watch`
// a thread keeps to these times while the work gives no update (a first wavefront that takes
// long); without it (a test's clock), only update() prints.
struct ProgressTimes {
  double first = 1.0, every = 5.0, later = 30.0, late = 300.0;
  bool tenths = true, watch = true;
  double gap(double elapsed) const { return elapsed >= late ? later : every; }
};

// The whole a Progress is a part of.
struct ProgressPart {
  std::string position;  // "frame 12, 3 of 5", "backend 2 of 3"; empty: the work is the whole
  double before = 0.0;   // the fraction of the whole done before this part
  double share = 1.0;    // this part's fraction of the whole
  double whole_start = -1.0;  // when the whole began (ProgressOutput::now); < 0: no total ETA
};

class Progress {
  struct Watch;  // the watching thread and what it shares with update()

 public:
  // `total` units of work (samples); `pixels` > 0 shows the samples per pixel done ("12/64 spp").
  Progress(std::string label, uint64_t total, bool enabled, ProgressPart part = {},
           uint64_t pixels = 0, ProgressOutput output = ProgressOutput::standard_error(),
           ProgressTimes times = {});
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  // `done` units of `total` are finished; `rays` is the running count of rays traced.
  void update(uint64_t done, uint64_t rays);
  // The work ended (done or stopped): the terminal's line is closed, the log gets a last line.
  void finish();
  // The work stops after about `seconds` (a time limit) if it is not done sooner: the fraction
  // done, its percentage and the ETAs are then at least the time's, and a last line after the
  // limit says 100 %.
  void limit_time(double seconds) { time_limit_ = seconds; }

 private:
  void print(bool final_line);
  // Of the work done at `elapsed` seconds: by the units, or by the time limit if further.
  double fraction(double elapsed) const;
  // Prints the line the time asks for, if any (the watching thread, under its lock).
  void tick();

  std::string label_;
  uint64_t total_;
  bool enabled_;
  ProgressPart part_;
  uint64_t pixels_;
  ProgressOutput out_;
  ProgressTimes times_;
  bool finished_ = false, drawn_ = false;
  int last_percent_ = -1, last_step_ = -1;
  uint64_t done_ = 0, rays_ = 0;
  double time_limit_ = 0.0;
  double start_, last_print_;
  std::unique_ptr<Watch> watch_;
};

// A step with no progress of its own (a scene's load, a backend's build), watched by a thread:
// nothing when it is quick; once it has taken `times.first` seconds a line "WHAT…", then
// "WHAT: m:ss so far" every few seconds (ProgressTimes), and done() adds what it took. A
// disabled Activity (or one without times.watch, which a test ticks) starts no thread; a disabled
// one prints nothing.
class Activity {
 public:
  Activity(std::string what, bool enabled,
           ProgressOutput output = ProgressOutput::standard_error(), ProgressTimes times = {});
  ~Activity();  // without done() (an error ended the step), prints nothing more
  Activity(const Activity&) = delete;
  Activity& operator=(const Activity&) = delete;
  // Ends the step: when it printed a line (it took long), prints `summary` (e.g. "loaded X in
  // 3.2 s: read 1.2 s, scene 2.0 s"), or "WHAT: done in m:ss" when `summary` is empty.
  void done(const std::string& summary);
  // The seconds since the step began.
  double seconds() const;
  // Prints what is due at this time (the watching thread calls it; a test without the thread).
  void tick();

 private:
  bool stop();  // ends the thread; false when it had ended already

  std::string what_;
  bool enabled_;
  ProgressOutput out_;
  ProgressTimes times_;
  double start_, next_;
  bool printed_ = false, over_ = false;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread watcher_;
};

}  // namespace dacrt
