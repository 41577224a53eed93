// The outputs of `dacrt converge` (apps/converge.h): the points measured, the CSV, the gnuplot
// script with its data inline and the plot gnuplot draws from it, and the table of fits and
// equal-error and equal-time comparisons on stdout.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "render/convergence.h"

namespace dacrt {

enum class Metric { rmse, relmse, mae, smape, noise };
constexpr const char* metric_keys[] = {"rmse", "relmse", "mae", "smape", "noise"};
constexpr const char* metric_names[] = {"RMSE", "relMSE", "MAE", "SMAPE", "noise"};
struct Point {
  uint32_t spp = 0;
  double seconds = 0.0;
  std::optional<ImageError> error;
  std::optional<double> noise;
};

struct Curve {
  std::string label;
  std::vector<Point> points;
};

// A point's value of a metric (nothing when it was not measured).
std::optional<double> value_of(const Point& p, Metric m);
// snprintf of one number.
std::string format(const char* f, double v);

void write_csv(const std::string& path, const std::vector<Curve>& curves);
// The gnuplot script, its data inline: `gnuplot convergence.gp` in OUTDIR draws the plot again.
// The outputs are the variables svg and png (set with -e), convergence.svg/png by default.
void write_script(const std::string& path, const std::vector<Curve>& curves, Metric metric,
                  const std::string& title);
// Runs gnuplot on the script, its outputs written to temporaries and renamed. Error when it fails.
void draw_plot(const std::string& gnuplot, const std::string& script, const std::string& svg,
               const std::string& png);
// The table on stdout: each curve's fit, then equal-error and equal-time comparisons (at
// `targets`, or at the lowest error every curve reached).
void print_table(const std::vector<Curve>& curves, Metric metric, std::vector<double> targets);

}  // namespace dacrt
