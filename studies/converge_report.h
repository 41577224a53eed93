// The outputs of `dacrt converge` (apps/converge.h): the points measured, the CSV, the gnuplot
// script with its data inline and the plot gnuplot draws from it, and the table of fits and
// equal-error and equal-time comparisons on stdout.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "dacrt/render/convergence.h"

namespace dacrt {

enum class Metric { rmse, relmse, mae, smape, noise };
constexpr const char* metric_keys[] = {"rmse", "relmse", "mae", "smape", "noise"};
constexpr const char* metric_names[] = {"RMSE", "relMSE", "MAE", "SMAPE", "noise"};
// One render's measurement at a point: the seconds it took and its errors.
struct Measure {
  double seconds = 0.0;
  std::optional<ImageError> error;  // against the reference, its own error taken out when known
  std::optional<ImageError> raw;    // against the reference as it is
  std::optional<double> noise;
};

// A point of a curve: `spp` samples per pixel, one measure per repeat (--repeats).
struct Point {
  uint32_t spp = 0;
  std::vector<Measure> repeats;
};

struct Curve {
  std::string label;
  std::vector<Point> points;
};

// A measure's value of a metric (nothing when it was not measured).
std::optional<double> value_of(const Measure& m, Metric metric);
// A point's metric over its repeats: the mean and its 95 % band (NaN ends with one repeat);
// nothing when a repeat lacks it.
std::optional<Interval> summary_of(const Point& p, Metric metric);
// A point's seconds over its repeats, the same way.
Interval seconds_of(const Point& p);
// snprintf of one number.
std::string format(const char* f, double v);

// The reference's own error (nothing when unknown) fills the CSV's reference columns.
void write_csv(const std::string& path, const std::vector<Curve>& curves,
               const std::optional<ReferenceError>& reference);
// The gnuplot script, its data inline: `gnuplot convergence.gp` in OUTDIR draws the plot again.
// The outputs are the variables svg and png (set with -e), convergence.svg/png by default.
void write_script(const std::string& path, const std::vector<Curve>& curves, Metric metric,
                  const std::string& title);
// Runs gnuplot on the script, its outputs written to temporaries and renamed. Error when it fails.
void draw_plot(const std::string& gnuplot, const std::string& script, const std::string& svg,
               const std::string& png);
// The table on stdout: each curve's fit, then equal-error and equal-time comparisons (at
// `targets`, or at the lowest error every curve reached).
// The reference's line above the table: its own MSE and that it is subtracted, or that it is
// unknown.
void print_reference(std::FILE* out, const std::string& path,
                     const std::optional<ReferenceError>& error);
// A warning for each curve whose last point is too short to time (render/convergence.h: under
// 0.1 s).
std::vector<std::string> short_run_warnings(const std::vector<Curve>& curves);
void print_table(std::FILE* out, const std::vector<Curve>& curves, Metric metric,
                 std::vector<double> targets);

// OUTDIR/index.html: one self-contained page (bench/html_page.h) with the plot (the SVG gnuplot
// drew, when it did: `svg` empty otherwise), `summary` (the reference's line and the table printed
// on stdout) and every point with its band.
void write_page(const std::string& dir, const std::string& title, const std::vector<Curve>& curves,
                Metric metric, const std::string& summary, const std::string& svg);

}  // namespace dacrt
