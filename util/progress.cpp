// Progress: a status line on stderr. On a terminal it is redrawn in place (at most ten times a
// second); in a log (stderr not a TTY) a full line is printed at each 10 % step only.
#include "dacrt/util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "dacrt/util/progress_format.h"

namespace dacrt {

std::string format_rate(double rays_per_second) {
  if (!std::isfinite(rays_per_second) || rays_per_second <= 0) return "0 rays/s";
  static const char* const units[] = {"rays/s", "krays/s", "Mrays/s"};
  double value = rays_per_second;
  int unit = 0;
  while (unit < 2 && value >= 999.5) {  // 999.5 would print as "1000"
    value /= 1000;
    ++unit;
  }
  const char* format = unit == 0       ? "%.0f %s"
                       : value < 9.995 ? "%.2f %s"
                       : value < 99.95 ? "%.1f %s"
                                       : "%.0f %s";
  char text[64];
  std::snprintf(text, sizeof text, format, value, units[unit]);
  return text;
}

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  if (seconds >= 359999.5) return ">99:59:59";
  const long long total = std::llround(seconds);
  const long long h = total / 3600, m = total / 60 % 60, s = total % 60;
  char text[32];
  if (h > 0)
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", h, m, s);
  else
    std::snprintf(text, sizeof text, "%lld:%02lld", m, s);
  return text;
}

std::string format_bar(double fraction, int width) {
  width = std::max(width, 0);
  if (std::isnan(fraction)) fraction = 0;
  fraction = std::clamp(fraction, 0.0, 1.0);
  const int filled = std::min(width, int(fraction * width));
  std::string bar;
  bar.reserve(size_t(width) + 2);
  bar += '[';
  bar.append(size_t(filled), '#');
  bar.append(size_t(width - filled), '-');
  bar += ']';
  return bar;
}

std::string format_progress_line(const std::string& label, double fraction, double rays_per_second,
                                 double elapsed_seconds) {
  if (std::isnan(fraction)) fraction = 0;
  fraction = std::clamp(fraction, 0.0, 1.0);
  const bool done = fraction >= 1.0;
  const int percent = done ? 100 : std::min(99, int(fraction * 100));
  char pct[16];
  std::snprintf(pct, sizeof pct, "%3d%%", percent);
  std::string line = label + " " + format_bar(fraction) + " " + pct;
  if (rays_per_second >= 0) line += "  " + format_rate(rays_per_second);
  if (done)
    line += "  took " + format_duration(elapsed_seconds);
  else if (fraction > 0)
    line += "  ETA " + format_duration(elapsed_seconds * (1 - fraction) / fraction);
  else
    line += "  ETA --:--";
  return line;
}

Progress::Progress(std::string label, uint64_t total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled),
      tty_(enabled && isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

Progress::~Progress() {
  if (!finished_) finish();
}

void Progress::update(uint64_t done, uint64_t rays) {
  if (!enabled_ || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  // Integer percentage so that 100 % means done, however large total is.
  const bool complete = done >= total_;
  const int percent = complete ? 100 : std::min(99, int((long double)done * 100 / total_));
  bool draw;
  if (tty_) {
    draw = last_percent_ < 0 || (percent == 100 && last_percent_ != 100) ||
           now - last_print_ >= std::chrono::milliseconds(100);
  } else {
    draw = percent >= 10 && percent / 10 > std::max(last_percent_, 0) / 10;
  }
  if (!draw) return;

  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = (rays > 0 && elapsed > 0) ? double(rays) / elapsed : -1.0;
  double fraction = complete ? 1.0 : double((long double)done / total_);
  if (!complete) fraction = std::min(fraction, std::nextafter(1.0, 0.0));
  const std::string line = format_progress_line(label_, fraction, rate, elapsed);
  if (tty_)
    std::fprintf(stderr, "\r%s\033[K", line.c_str());  // \033[K clears what a longer line left
  else
    std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
  last_print_ = now;
  last_percent_ = percent;
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled_) return;
  if (total_ == 0 && last_percent_ != 100) {  // nothing to do: report it as done
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const std::string line = format_progress_line(label_, 1.0, -1.0, elapsed);
    std::fprintf(stderr, tty_ ? "\r%s\033[K\n" : "%s\n", line.c_str());
  } else if (tty_ && last_percent_ >= 0) {
    std::fputc('\n', stderr);
  }
  std::fflush(stderr);
}

}  // namespace dacrt
