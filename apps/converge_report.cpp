#include "apps/converge_report.h"

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
#include <sstream>

#include "util/atomic_file.h"
#include "util/error.h"

extern char** environ;

namespace dacrt {

namespace fs = std::filesystem;

std::optional<double> value_of(const Point& p, Metric m) {
  if (m == Metric::noise) return p.noise;
  if (!p.error) return std::nullopt;
  const ImageError& e = *p.error;
  return m == Metric::rmse     ? e.rmse
         : m == Metric::relmse ? e.relmse
         : m == Metric::mae    ? e.mae
                               : e.smape;
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
  for (const Point& p : c.points) v.push_back(p.seconds);
  return v;
}
std::vector<double> samples(const Curve& c) {
  std::vector<double> v;
  for (const Point& p : c.points) v.push_back(p.spp);
  return v;
}
std::vector<double> errors(const Curve& c, Metric m) {
  std::vector<double> v;
  for (const Point& p : c.points) v.push_back(value_of(p, m).value_or(NAN));
  return v;
}

std::string slope_text(double slope) {
  return std::isfinite(slope) ? format("%.2f", slope) : std::string("n/a");
}

}  // namespace

void write_csv(const std::string& path, const std::vector<Curve>& curves) {
  write_atomically(path, "CSV", [&](std::ostream& out) {
    out << "config,spp,seconds,rmse,relmse,mae,smape,noise\n";
    for (const Curve& c : curves)
      for (const Point& p : c.points) {
        out << csv_quote(c.label) << ',' << p.spp << ',' << format("%.6g", p.seconds);
        for (int m = 0; m < 5; ++m) {
          const std::optional<double> v = value_of(p, Metric(m));
          out << ',' << (v ? format("%.9g", *v) : std::string());
        }
        out << '\n';
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
    data << "$config" << k << " << EOD\n# seconds " << metric_keys[int(metric)] << " spp\n";
    int rows = 0;
    for (const Point& p : c.points)
      if (const auto v = value_of(p, metric); v && *v > 0 && p.seconds > 0)
        data << format("%.6g", p.seconds) << ' ' << format("%.9g", *v) << ' ' << p.spp << '\n',
            ++rows;
    data << "EOD\n";
    if (rows == 0) continue;
    const LogLogFit by_time = fit_log_log(costs(c), errors(c, metric));
    const LogLogFit by_spp = fit_log_log(samples(c), errors(c, metric));
    const std::string legend = c.label + ": slope " + slope_text(by_time.slope) + " vs time, " +
                               slope_text(by_spp.slope) + " vs spp";
    plot << (drawn++ ? ", \\\n     " : "") << "$config" << k
         << " using 1:2 with linespoints linewidth 2 pointtype " << 5 + 2 * (k % 4) << " title "
         << gnuplot_quote(legend);
  }
  if (drawn == 0) plot << "NaN notitle";
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
        << gnuplot_quote(std::string(metric_names[int(metric)]) + " (linear radiance)")
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

void print_table(const std::vector<Curve>& curves, Metric metric, std::vector<double> targets) {
  const char* name = metric_names[int(metric)];
  size_t width = 6;
  for (const Curve& c : curves) width = std::max(width, c.label.size());
  const int w = int(width);
  std::printf("%-*s  points  last spp  seconds  %8s  slope/spp  slope/time\n", w, "config", name);
  double common_error = 0, common_time = INFINITY;
  for (const Curve& c : curves) {
    const std::vector<double> e = errors(c, metric);
    const LogLogFit by_spp = fit_log_log(samples(c), e), by_time = fit_log_log(costs(c), e);
    const Point& last = c.points.back();
    std::printf("%-*s  %6zu  %8u  %7.3g  %8.3g  %9s  %10s\n", w, c.label.c_str(), c.points.size(),
                last.spp, last.seconds, e.back(), slope_text(by_spp.slope).c_str(),
                slope_text(by_time.slope).c_str());
    double lowest = INFINITY;
    for (double v : e)
      if (v > 0) lowest = std::min(lowest, v);
    common_error = std::max(common_error, lowest);
    common_time = std::min(common_time, last.seconds);
  }
  const bool automatic = targets.empty();
  if (automatic && std::isfinite(common_error)) targets.push_back(common_error);
  for (double target : targets) {
    std::printf("\nequal error: %s %.3g%s\n", name, target,
                automatic ? " (the lowest every configuration reached)" : "");
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
        if (first && *first > 0) text += format("  %.2fx", *at / *first);
        if (!e.empty() && e[0] <= target) text += "  (at its first point: perhaps sooner)";
      }
      std::printf("  %-*s  %s\n", w, c.label.c_str(), text.c_str());
      sentence += (k ? (k + 1 == curves.size() ? " and " : ", ") : "") + c.label +
                  (at ? " in " + format("%.3g s", *at) : " never");
    }
    std::printf("  (%s reach %s %.3g)\n", sentence.c_str(), name, target);
  }
  if (std::isfinite(common_time)) {
    std::printf("\nequal time: %.3g s (the longest every configuration ran)\n", common_time);
    std::optional<double> first;
    for (size_t k = 0; k < curves.size(); ++k) {
      const Curve& c = curves[k];
      const std::optional<double> e = error_at(costs(c), errors(c, metric), common_time);
      if (k == 0) first = e;
      std::string text = e ? format("%.3g", *e) : std::string("n/a (its first point is later)");
      if (e && first && *first > 0) text += format("  %.2fx", *e / *first);
      std::printf("  %-*s  %s %s\n", w, c.label.c_str(), name, text.c_str());
    }
  }
}

}  // namespace dacrt
