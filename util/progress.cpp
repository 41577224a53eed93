// Progress: a status line on stderr. On a terminal it is redrawn in place (at most ten times a
// second); in a log (stderr not a TTY) a full line at each 10 % step, after the first second,
// then every few seconds, and a last one when the work ends. Activity: a thread that speaks for
// a long step.
#include "dacrt/util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
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

std::string format_spp(double spp) {
  char text[32];
  if (!std::isfinite(spp) || spp < 0) return "?";
  if (spp == std::floor(spp) && spp < 1e15)
    std::snprintf(text, sizeof text, "%.0f", spp);
  else
    std::snprintf(text, sizeof text, "%.1f", spp);
  return text;
}

namespace {
double clamped_fraction(double fraction) {
  return std::isnan(fraction) ? 0.0 : std::clamp(fraction, 0.0, 1.0);
}
std::string heading(const ProgressState& s) {
  return s.position.empty() ? s.label : s.label + " " + s.position;
}
}  // namespace

std::string format_log_line(const ProgressState& s) {
  const double fraction = clamped_fraction(s.fraction);
  const int percent = fraction >= 1.0 ? 100 : std::min(99, int(fraction * 100));
  std::string line = heading(s) + ": " + std::to_string(percent) + "%";
  if (s.spp_done >= 0 && s.spp_total >= 0)
    line += ", " + format_spp(s.spp_done) + "/" + format_spp(s.spp_total) + " spp";
  if (s.rays_per_second >= 0) line += ", " + format_rate(s.rays_per_second);
  if (s.ended)
    line += ", took " + format_duration(s.elapsed);
  else if (fraction > 0)
    line += ", ETA " + format_duration(s.elapsed * (1 - fraction) / fraction);
  else
    line += ", ETA --:--";
  if (s.total_eta >= 0) line += ", total ETA " + format_duration(s.total_eta);
  return line;
}

std::string format_terminal_line(const ProgressState& s) {
  std::string line =
      format_progress_line(heading(s), s.ended ? std::max(s.fraction, 1.0) : s.fraction,
                           s.rays_per_second, s.elapsed);
  if (s.total_eta >= 0) line += "  total ETA " + format_duration(s.total_eta);
  return line;
}

ProgressOutput ProgressOutput::standard_error() {
  ProgressOutput out;
  out.write = [](const std::string& text) {
    std::fputs(text.c_str(), stderr);
    std::fflush(stderr);
  };
  out.now = [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  };
  out.terminal = isatty(STDERR_FILENO);
  return out;
}

struct Progress::Watch {
  std::mutex mutex;
  std::condition_variable wake;
  bool over = false;
  std::thread thread;
};

Progress::Progress(std::string label, uint64_t total, bool enabled, ProgressPart part,
                   uint64_t pixels, ProgressOutput output, ProgressTimes times)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled),
      part_(std::move(part)),
      pixels_(pixels),
      out_(std::move(output)),
      times_(times),
      start_(enabled ? out_.now() : 0.0),
      last_print_(start_) {
  if (!enabled_ || !times_.watch) return;
  watch_ = std::make_unique<Watch>();
  watch_->thread = std::thread([this] {
    std::unique_lock lock(watch_->mutex);
    while (!watch_->over) {
      watch_->wake.wait_for(lock, std::chrono::milliseconds(100));
      if (!watch_->over) tick();
    }
  });
}

Progress::~Progress() {
  if (!finished_) finish();
}

void Progress::tick() {
  if (finished_) return;
  const double now = out_.now(), elapsed = now - start_;
  const bool due = out_.terminal ? now - last_print_ >= 1.0
                   : drawn_      ? now - last_print_ >= times_.gap(elapsed)
                                 : elapsed >= times_.first;
  if (due) print(false);
}

double Progress::fraction(double elapsed) const {
  if (done_ >= total_) return 1.0;
  double f = double((long double)done_ / total_);
  if (time_limit_ > 0) f = std::max(f, elapsed / time_limit_);
  return std::min(f, std::nextafter(1.0, 0.0));
}

void Progress::print(bool final_line) {
  const double now = out_.now();
  const double elapsed = now - start_;
  ProgressState s;
  s.label = label_;
  s.position = part_.position;
  s.fraction = fraction(elapsed);
  if (final_line && time_limit_ > 0 && elapsed >= time_limit_) s.fraction = 1.0;  // its end
  s.rays_per_second = (rays_ > 0 && elapsed > 0) ? double(rays_) / elapsed : -1.0;
  s.elapsed = elapsed;
  s.ended = final_line;
  if (pixels_ > 0)
    s.spp_done = double(done_) / double(pixels_), s.spp_total = double(total_) / double(pixels_);
  if (part_.whole_start >= 0) {
    const double whole = part_.before + part_.share * s.fraction;
    if (whole > 0) s.total_eta = (now - part_.whole_start) * (1 - std::min(whole, 1.0)) / whole;
  }
  std::string line = out_.terminal ? "\r" : "";
  line += out_.terminal ? format_terminal_line(s) : format_log_line(s);
  line += out_.terminal ? "\033[K" : "\n";  // \033[K clears what a longer line left
  out_.write(line);
  drawn_ = true;
  last_print_ = now;
}

void Progress::update(uint64_t done, uint64_t rays) {
  if (!enabled_ || finished_) return;
  std::unique_lock<std::mutex> lock;
  if (watch_) lock = std::unique_lock(watch_->mutex);
  done_ = done, rays_ = rays;
  const double now = out_.now();
  // Integer percentage so that 100 % means done, however large total is.
  const bool complete = done >= total_;
  const int percent = complete ? 100 : std::min(99, int(fraction(now - start_) * 100));
  bool draw;
  if (out_.terminal) {
    draw = !drawn_ || (percent == 100 && last_percent_ != 100) || now - last_print_ >= 0.1;
  } else if (complete) {
    draw = false;  // finish() says it
  } else {
    const double elapsed = now - start_;
    draw = drawn_ ? now - last_print_ >= times_.gap(elapsed) : elapsed >= times_.first;
    if (times_.tenths && percent >= 10 && percent / 10 > std::max(last_step_, 0) / 10) {
      draw = true;
      last_step_ = percent;
    }
  }
  if (!draw) return;
  print(false);
  last_percent_ = percent;
}

void Progress::finish() {
  if (finished_) return;
  if (watch_) {
    {
      std::lock_guard lock(watch_->mutex);
      watch_->over = true;
    }
    watch_->wake.notify_all();
    watch_->thread.join();
  }
  finished_ = true;
  if (!enabled_) return;
  if (total_ == 0 && last_percent_ != 100) {  // nothing to do: report it as done
    print(true);
    if (out_.terminal) out_.write("\n");
  } else if (out_.terminal) {
    if (drawn_) out_.write("\n");
  } else if (drawn_ || times_.tenths) {
    print(true);  // how the work ended
  }
}

Activity::Activity(std::string what, bool enabled, ProgressOutput output, ProgressTimes times)
    : what_(std::move(what)),
      enabled_(enabled),
      out_(std::move(output)),
      times_(times),
      start_(enabled ? out_.now() : 0.0),
      next_(start_ + times.first) {
  if (enabled_ && times_.watch)
    watcher_ = std::thread([this] {
      std::unique_lock lock(mutex_);
      while (!over_) {
        wake_.wait_for(lock, std::chrono::milliseconds(100));
        if (!over_) {
          lock.unlock();
          tick();
          lock.lock();
        }
      }
    });
}

Activity::~Activity() {
  stop();  // an error ended the step: its message says what happened
}

bool Activity::stop() {
  {
    std::lock_guard lock(mutex_);
    if (over_) return false;
    over_ = true;
  }
  wake_.notify_all();
  if (watcher_.joinable()) watcher_.join();
  return true;
}

double Activity::seconds() const {
  return enabled_ ? out_.now() - start_ : 0.0;
}

void Activity::tick() {
  std::lock_guard lock(mutex_);
  if (!enabled_ || over_) return;
  const double now = out_.now();
  if (now < next_) return;
  out_.write(printed_ ? what_ + ": " + format_duration(now - start_) + " so far\n" : what_ + "\n");
  printed_ = true;
  next_ = now + times_.gap(now - start_);
}

void Activity::done(const std::string& summary) {
  if (!stop() || !enabled_ || !printed_) return;
  out_.write((summary.empty() ? what_ + ": done in " + format_duration(seconds()) : summary) +
             "\n");
}

}  // namespace dacrt
