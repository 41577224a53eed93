// Progress formatting: the pieces of Progress's status line as pure functions, so they can be
// tested.
#pragma once

#include <string>

namespace dacrt {

// "850 rays/s", "12.3 krays/s", "4.56 Mrays/s"... three significant digits; "0 rays/s" for
// zero, negative or non-finite input.
std::string format_rate(double rays_per_second);
// "0:07", "12:34", "1:02:03" (rounded to the nearest second); "--:--" for negative or non-finite
// input, ">99:59:59" past that.
std::string format_duration(double seconds);
// "[#####---------------]": `fraction` (clamped to [0, 1], NaN as 0) of `width` cells filled.
std::string format_bar(double fraction, int width = 20);
// The whole line: "label [#########-----------]  42%  12.3 Mrays/s  ETA 0:13". The percentage is
// rounded down (100% only when done); the rate is left out when negative; the ETA is "--:--" until
// fraction > 0, and once fraction >= 1 it is replaced by "took m:ss" (the elapsed time).
std::string format_progress_line(const std::string& label, double fraction, double rays_per_second,
                                 double elapsed_seconds);

// What one line of a Progress says.
struct ProgressState {
  std::string label;     // "render", "render embree"
  std::string position;  // "frame 12, 3 of 5"; empty: none
  double fraction = 0;   // of this part's work
  double rays_per_second = -1;  // < 0: left out
  double elapsed = 0;           // seconds of this part
  double spp_done = -1, spp_total = -1;  // samples per pixel; < 0: left out
  double total_eta = -1;  // seconds left of the whole; < 0: left out
  bool ended = false;     // the last line: "took m:ss" in place of the ETA
};
// A line for a log, one event: "render frame 12, 3 of 5: 42%, 27/64 spp, 12.3 Mrays/s, ETA 0:13,
// total ETA 1:05"; the last line has "took 0:31" for the ETA (whatever the percentage: a render
// stopped, or sampled adaptively, ends short of 100 %).
std::string format_log_line(const ProgressState& state);
// The terminal's bar: format_progress_line's, the label followed by the position, and
// "  total ETA m:ss" when there is one.
std::string format_terminal_line(const ProgressState& state);
// "64", "12.5": a sample count per pixel, whole numbers without decimals.
std::string format_spp(double spp);

}  // namespace dacrt
