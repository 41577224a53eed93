#include "studies/converge_report.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "bench/html_page.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"

extern char** environ;

namespace dacrt {

namespace fs = std::filesystem;

std::optional<double> value_of(const Measure& measure, Metric metric) {
  if (metric == Metric::noise) return measure.noise;
  if (!measure.error) return std::nullopt;
  const ImageError& e = *measure.error;
  return metric == Metric::rmse     ? e.rmse
         : metric == Metric::relmse ? e.relmse
         : metric == Metric::mae    ? e.mae
                                    : e.smape;
}

namespace {

// A point's values of `get` (a Measure to an optional number) over its repeats: their mean and
// band, or nothing when one repeat lacks the value.
template <class Get>
std::optional<Interval> summarize(const Point& p, Get get) {
  std::vector<double> values;
  for (const Measure& m : p.repeats) {
    const std::optional<double> v = get(m);
    if (!v) return std::nullopt;
    values.push_back(*v);
  }
  if (values.empty()) return std::nullopt;
  return mean_interval95(values);
}

}  // namespace

std::optional<Interval> summary_of(const Point& p, Metric metric) {
  return summarize(p, [&](const Measure& m) { return value_of(m, metric); });
}

Interval seconds_of(const Point& p) {
  return *summarize(p, [](const Measure& m) { return std::optional<double>(m.seconds); });
}

std::string format(const char* f, double v) {
  char text[64];
  std::snprintf(text, sizeof text, f, v);
  return text;
}

namespace {

std::string csv_quote(const std::string& text) {
  std::string q = "\"";
  for (char ch : text) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

// A gnuplot string in single quotes, where only '' is special: a line break (or any other control
// character, from a scene's file name say) would end the command, so each becomes a space.
std::string gnuplot_quote(const std::string& text) {
  std::string q = "'";
  for (char ch : text)
    q += ch == '\'' ? std::string("''")
                    : std::string(1, (unsigned char)ch < 0x20 || ch == 0x7f ? ' ' : ch);
  return q + "'";
}

std::vector<double> costs(const Curve& c) {
  std::vector<double> v;
  for (const Point& p : c.points) v.push_back(seconds_of(p).mean);
  return v;
}
std::vector<double> samples(const Curve& c) {
  std::vector<double> v;
  for (const Point& p : c.points) v.push_back(p.spp);
  return v;
}
// The curve's mean errors, or one end of their bands (NaN without one).
std::vector<double> errors(const Curve& c, Metric m, double Interval::*end = &Interval::mean) {
  std::vector<double> v;
  for (const Point& p : c.points) {
    const std::optional<Interval> e = summary_of(p, m);
    v.push_back(e ? (*e).*end : NAN);
  }
  return v;
}
bool has_band(const Curve& c) {
  for (const Point& p : c.points)
    if (p.repeats.size() > 1) return true;
  return false;
}

// A number, or nothing (an empty CSV cell) when it is not one.
std::string cell(std::optional<double> v) {
  return v && std::isfinite(*v) ? format("%.9g", *v) : std::string();
}
// "  [low, high]" of a band, or nothing without one.
std::string band_text(double low, double high) {
  return std::isfinite(low) && std::isfinite(high)
             ? "  [" + format("%.3g", low) + ", " + format("%.3g", high) + "]"
             : std::string();
}

std::string slope_text(double slope) {
  return std::isfinite(slope) ? format("%.2f", slope) : std::string("n/a");
}

}  // namespace

void write_csv(const std::string& path, const std::vector<Curve>& curves,
               const std::optional<ReferenceError>& reference) {
  // One field of a band, or of the reference's error, that may not exist: an empty cell then.
  auto field = [](const auto& maybe, double std::decay_t<decltype(*maybe)>::*member) {
    return cell(maybe ? std::optional((*maybe).*member) : std::nullopt);
  };
  write_atomically(path, "CSV", [&](std::ostream& out) {
    out << "config,spp,seconds,rmse,relmse,mae,smape,noise,repeats,seconds_low,seconds_high";
    for (const char* key : metric_keys) out << ',' << key << "_low," << key << "_high";
    out << ",rmse_raw,relmse_raw,reference_mse,reference_relmse\n";
    for (const Curve& c : curves)
      for (const Point& p : c.points) {
        const Interval seconds = seconds_of(p);
        out << csv_quote(c.label) << ',' << p.spp << ',' << format("%.6g", seconds.mean);
        std::vector<std::optional<Interval>> bands;
        for (int m = 0; m < 5; ++m) {
          bands.push_back(summary_of(p, Metric(m)));
          out << ',' << field(bands.back(), &Interval::mean);
        }
        out << ',' << p.repeats.size() << ',' << cell(seconds.low) << ',' << cell(seconds.high);
        for (const std::optional<Interval>& b : bands)
          out << ',' << field(b, &Interval::low) << ',' << field(b, &Interval::high);
        for (double ImageError::*raw : {&ImageError::rmse, &ImageError::relmse})
          out << ','
              << field(summarize(p,
                                 [&](const Measure& m) {
                                   return m.raw ? std::optional((*m.raw).*raw) : std::nullopt;
                                 }),
                       &Interval::mean);
        out << ',' << field(reference, &ReferenceError::mse) << ','
            << field(reference, &ReferenceError::relmse) << '\n';
      }
  });
}

void write_script(const std::string& path, const std::vector<Curve>& curves, Metric metric,
                  const std::string& title) {
  std::ostringstream plot;
  plot << "plot ";
  int drawn = 0;
  std::ostringstream data;
  for (size_t k = 0; k < curves.size(); ++k) {
    const Curve& c = curves[k];
    data << "$config" << k << " << EOD\n# seconds " << metric_keys[int(metric)]
         << " spp low high (the 95 % band; the value itself without repeats)\n";
    int rows = 0;
    for (const Point& p : c.points) {
      const std::optional<Interval> v = summary_of(p, metric);
      const double seconds = seconds_of(p).mean;
      if (!v || !(v->mean > 0) || !(seconds > 0)) continue;
      // A band that reaches 0 would leave the log plot: its low end is drawn at a tenth of the
      // mean (the CSV and the tables keep the interval as computed).
      const double low = std::isfinite(v->low) ? std::max(v->low, v->mean / 10) : v->mean;
      const double high = std::isfinite(v->high) ? v->high : v->mean;
      data << format("%.6g", seconds) << ' ' << format("%.9g", v->mean) << ' ' << p.spp << ' '
           << format("%.9g", low) << ' ' << format("%.9g", high) << '\n';
      ++rows;
    }
    data << "EOD\n";
    if (rows == 0) continue;
    const LogLogFit by_time = fit_log_log(costs(c), errors(c, metric));
    const LogLogFit by_spp = fit_log_log(samples(c), errors(c, metric));
    const std::string legend = c.label + ": slope " + slope_text(by_time.slope) + " vs time, " +
                               slope_text(by_spp.slope) + " vs spp";
    const std::string colour = " linecolor " + std::to_string(k % 8 + 1);
    plot << (drawn++ ? ", \\\n     " : "");
    if (has_band(c))
      plot << "$config" << k << " using 1:4:5 with filledcurves" << colour
           << " fillstyle transparent solid 0.2 noborder notitle, \\\n     ";
    plot << "$config" << k << " using 1:2 with linespoints linewidth 2" << colour << " pointtype "
         << 5 + 2 * (k % 4) << " title " << gnuplot_quote(legend);
  }
  if (drawn == 0) plot << "NaN notitle";
  const bool banded = std::any_of(curves.begin(), curves.end(), has_band);
  write_atomically(path, "gnuplot script", [&](std::ostream& out) {
    out << "# dacrt converge: " << metric_names[int(metric)]
        << " against render time, one curve per configuration.\n"
        << "# Draw it with `gnuplot convergence.gp` (writes convergence.svg and convergence.png).\n"
        << "if (!exists(\"svg\")) svg = 'convergence.svg'\n"
        << "if (!exists(\"png\")) png = 'convergence.png'\n"
        << data.str() << "set logscale xy\nset grid xtics ytics mxtics mytics\n"
        << "set format x '%g'\nset format y '%g'\n"
        << "set xlabel 'seconds (cumulative: build and every sample so far)'\n"
        << "set ylabel "
        << gnuplot_quote(std::string(metric_names[int(metric)]) + " (linear radiance" +
                         (banded ? "; the mean of the repeats, their 95 % band shaded)" : ")"))
        << "\nset title " << gnuplot_quote(title) << "\nset key top right box opaque\n"
        << "set terminal svg size 820,560 dynamic noenhanced font 'sans,12' background '#ffffff'\n"
        << "set output svg\n"
        << plot.str() << "\nset terminal pngcairo size 820,560 noenhanced font 'sans,10'\n"
        << "set output png\n"
        << plot.str() << "\nset output\n";
  });
}

void draw_plot(const std::string& gnuplot, const std::string& script, const std::string& svg,
               const std::string& png) {
  // gnuplot writes into a directory of our own, made with an unpredictable name beside the
  // outputs (a link planted at a guessable temporary name is never followed), and is given
  // plain names there: the directory's path need not survive gnuplot's quoting. The plots are
  // then renamed into place.
  std::string pattern =
      (fs::absolute(fs::path(svg)).parent_path() / ".convergence-XXXXXX").string();
  if (!::mkdtemp(pattern.data()))
    throw Error("cannot draw the plot beside " + svg + ": " + std::strerror(errno));
  const fs::path dir = pattern;
  const fs::path svg_tmp = dir / "plot.svg", png_tmp = dir / "plot.png", err = dir / "gnuplot.err";
  const std::string vars = "svg='plot.svg'; png='plot.png'";
  std::vector<std::string> argv_s = {gnuplot, "-e", vars, script};
  std::vector<char*> argv;
  for (std::string& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
  pid_t pid = -1;
  const int spawned = posix_spawn(&pid, gnuplot.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  if (spawned == 0) waitpid(pid, &status, 0);
  std::string message;
  {
    std::ifstream in(err);
    std::getline(in, message);
    std::string line;
    while (message.find_first_not_of(" \t^") == std::string::npos && std::getline(in, line))
      message = line;
  }
  std::error_code ec;
  const bool ok = spawned == 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0 &&
                  fs::exists(svg_tmp) && fs::exists(png_tmp);
  if (ok) {
    fs::rename(svg_tmp, svg, ec);
    if (!ec) fs::rename(png_tmp, png, ec);
  }
  std::error_code ignored;
  fs::remove_all(dir, ignored);
  if (!ok || ec)
    throw Error("gnuplot could not draw " + script +
                (message.empty() ? "" : ": " + one_line(message)));
}

void print_reference(std::FILE* out, const std::string& path,
                     const std::optional<ReferenceError>& error) {
  if (error)
    std::fprintf(out, 
        "reference %s: its own MSE %.3g (RMSE %.3g, relMSE %.3g), from its two halves, is "
        "subtracted from each configuration's MSE against it (RMSE and relMSE; MAE and "
        "SMAPE as measured)\n\n",
        path.c_str(), error->mse, std::sqrt(error->mse), error->relmse);
  else
    std::fprintf(out, 
        "reference %s: its own error is unknown (no referenceMse attribute): not "
        "subtracted\n\n",
        path.c_str());
}

std::vector<std::string> short_run_warnings(const std::vector<Curve>& curves) {
  std::vector<std::string> warnings;
  for (const Curve& c : curves) {
    const double seconds = seconds_of(c.points.back()).mean;
    if (too_short_to_time(seconds))
      warnings.push_back("--config \"" + c.label + "\" ran " + format("%.3g", seconds) +
                         " s in all: times under 0.1 s are noisy (a larger --time-budget, "
                         "--max-spp or image runs longer)");
  }
  return warnings;
}

void print_table(std::FILE* out, const std::vector<Curve>& curves, Metric metric,
                 std::vector<double> targets) {
  const char* name = metric_names[int(metric)];
  size_t width = 6;
  for (const Curve& c : curves) width = std::max(width, c.label.size());
  const int w = int(width);
  const bool banded = std::any_of(curves.begin(), curves.end(), has_band);
  if (banded)
    std::fprintf(out, 
        "(each number the mean of the repeats, [low, high] its 95 %% confidence interval, "
        "Student t)\n");
  std::fprintf(out, "%-*s  points  last spp  seconds  %8s  slope/spp  slope/time%s\n", w, "config", name,
              banded ? "  95 % band" : "");
  double common_error = 0, common_time = INFINITY;
  for (const Curve& c : curves) {
    const std::vector<double> e = errors(c, metric);
    const LogLogFit by_spp = fit_log_log(samples(c), e), by_time = fit_log_log(costs(c), e);
    const Point& last = c.points.back();
    std::fprintf(out, "%-*s  %6zu  %8u  %7.3g  %8.3g  %9s  %10s%s\n", w, c.label.c_str(), c.points.size(),
                last.spp, seconds_of(last).mean, e.back(), slope_text(by_spp.slope).c_str(),
                slope_text(by_time.slope).c_str(),
                band_text(errors(c, metric, &Interval::low).back(),
                          errors(c, metric, &Interval::high).back())
                    .c_str());
    double lowest = INFINITY;
    for (double v : e)
      if (v > 0) lowest = std::min(lowest, v);
    common_error = std::max(common_error, lowest);
    common_time = std::min(common_time, seconds_of(last).mean);
  }
  const bool automatic = targets.empty();
  if (automatic && std::isfinite(common_error)) targets.push_back(common_error);
  for (double target : targets) {
    std::fprintf(out, "\nequal error: %s %.3g%s\n", name, target,
                automatic ? " (the lowest every configuration reached)" : "");
    if (banded)
      std::fprintf(out, 
          "  ([low, high]: when the band's low and high ends reach it; > the last "
          "point's seconds when the high end never does)\n");
    std::optional<double> first;
    std::string sentence;
    for (size_t k = 0; k < curves.size(); ++k) {
      const Curve& c = curves[k];
      const std::vector<double> e = errors(c, metric), t = costs(c);
      const std::optional<double> at = cost_to_reach(t, e, target);
      if (k == 0) first = at;
      std::string text;
      if (!at) {
        double lowest = INFINITY;
        for (double v : e)
          if (v > 0) lowest = std::min(lowest, v);
        text =
            "never (lowest " + format("%.3g", lowest) + " in " + format("%.3g", t.back()) + " s)";
      } else {
        text = format("%.3g s", *at);
        if (has_band(c)) {
          // A low end at or below 0 has reached every level: it counts as the least positive.
          std::vector<double> lows = errors(c, metric, &Interval::low);
          for (double& v : lows) v = std::max(v, std::numeric_limits<double>::min());
          const std::optional<double> low = cost_to_reach(t, lows, target),
                                      high = cost_to_reach(t, errors(c, metric, &Interval::high),
                                                           target);
          text += " [" + (low ? format("%.3g", *low) : std::string("?")) + ", " +
                  (high ? format("%.3g", *high) : format("> %.3g", t.back())) + "]";
        }
        if (first && *first > 0) text += format("  %.2fx", *at / *first);
        if (!e.empty() && e[0] <= target) text += "  (at its first point: perhaps sooner)";
      }
      std::fprintf(out, "  %-*s  %s\n", w, c.label.c_str(), text.c_str());
      sentence += (k ? (k + 1 == curves.size() ? " and " : ", ") : "") + c.label +
                  (at ? " in " + format("%.3g s", *at) : " never");
    }
    std::fprintf(out, "  (%s reach %s %.3g)\n", sentence.c_str(), name, target);
  }
  if (std::isfinite(common_time)) {
    std::fprintf(out, "\nequal time: %.3g s (the longest every configuration ran)\n", common_time);
    std::optional<double> first;
    for (size_t k = 0; k < curves.size(); ++k) {
      const Curve& c = curves[k];
      const std::vector<double> t = costs(c);
      const std::optional<double> e = error_at(t, errors(c, metric), common_time);
      if (k == 0) first = e;
      std::string text = e ? format("%.3g", *e) : std::string("n/a (its first point is later)");
      if (e && has_band(c)) {
        // The band's half width, interpolated as the mean is (a low end may be 0 or below,
        // which a log-log interpolation cannot take).
        std::vector<double> half = errors(c, metric, &Interval::high), mean = errors(c, metric);
        for (size_t i = 0; i < half.size(); ++i) half[i] -= mean[i];
        const double h = error_at(t, half, common_time).value_or(NAN);
        text += band_text(*e - h, *e + h);
      }
      if (e && first && *first > 0) text += format("  %.2fx", *e / *first);
      std::fprintf(out, "  %-*s  %s %s\n", w, c.label.c_str(), name, text.c_str());
    }
  }
}

void write_page(const std::string& dir, const std::string& title, const std::vector<Curve>& curves,
                Metric metric, const std::string& summary, const std::string& svg) {
  HtmlPage page("dacrt converge: " + title);
  if (!svg.empty()) {
    std::ifstream in(svg);
    std::stringstream text;
    text << in.rdbuf();
    if (!in) throw Error("cannot read the plot " + svg + " for the report");
    page.figure(text.str(), std::string(metric_names[int(metric)]) +
                                " against render seconds, log-log; with --repeats, each point is "
                                "the mean over the seeds and the band its 95 % interval.");
  } else {
    page.paragraph("No plot: gnuplot was not found (install gnuplot-nox).");
  }
  page.heading("Fits and comparisons");
  page.preformatted(summary);
  page.heading("Points");
  std::vector<std::vector<std::string>> rows;
  for (const Curve& c : curves)
    for (const Point& p : c.points) {
      const Interval t = seconds_of(p);
      const std::optional<Interval> e = summary_of(p, metric);
      rows.push_back({c.label, std::to_string(p.spp), std::to_string(p.repeats.size()),
                      format("%.3g", t.mean) + band_text(t.low, t.high),
                      e ? format("%.4g", e->mean) + band_text(e->low, e->high) : "-"});
    }
  page.table({"config", "spp", "repeats", "seconds [95 % band]",
              std::string(metric_names[int(metric)]) + " [95 % band]"},
             rows);
  page.write(dir);
}

}  // namespace dacrt
