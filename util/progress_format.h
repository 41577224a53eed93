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

}  // namespace dacrt
