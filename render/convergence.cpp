#include "dacrt/render/convergence.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dacrt/util/error.h"

namespace dacrt {

namespace {

void check_same_size(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    throw Error("cannot compare a " + std::to_string(a.width) + " x " + std::to_string(a.height) +
                " image with a " + std::to_string(b.width) + " x " + std::to_string(b.height) +
                " one");
  if (a.rgb.empty() || a.rgb.size() != b.rgb.size()) throw Error("cannot compare empty images");
}

bool usable(double x, double y) {
  return x > 0 && y > 0 && std::isfinite(x) && std::isfinite(y);
}

// Linear interpolation of y at x between (x0, y0) and (x1, y1), all in logs.
double lerp_log(double x0, double y0, double x1, double y1, double x) {
  const double lx0 = std::log(x0), lx1 = std::log(x1);
  if (lx1 == lx0) return y0;
  const double f = (std::log(x) - lx0) / (lx1 - lx0);
  return std::exp(std::log(y0) + f * (std::log(y1) - std::log(y0)));
}

}  // namespace

ChannelErrors channel_errors(const Image& image, const Image& reference) {
  check_same_size(image, reference);
  // Sums per channel: each channel's metrics are its own sums over its pixels, and the overall
  // ones the three channels' sums over all values (every channel has the same count).
  std::array<ImageError, 3> sum{};
  const size_t n = image.rgb.size();
  for (size_t k = 0; k < n; ++k) {
    const double x = image.rgb[k], r = reference.rgb[k];
    const double d = x - r;
    ImageError& s = sum[k % 3];
    s.rmse += d * d;
    s.relmse += d * d / (r * r + relmse_epsilon);
    s.mae += std::abs(d);
    const double scale = std::abs(x) + std::abs(r);
    if (scale > 0) s.smape += 2 * std::abs(d) / scale;
    s.max_abs = std::max(s.max_abs, std::abs(d));
  }
  const auto mean = [](const ImageError& s, double count) {
    ImageError e;
    e.rmse = std::sqrt(s.rmse / count);
    e.relmse = s.relmse / count;
    e.mae = s.mae / count;
    e.smape = s.smape / count;
    e.max_abs = s.max_abs;
    return e;
  };
  ImageError total;
  for (const ImageError& s : sum) {
    total.rmse += s.rmse, total.relmse += s.relmse, total.mae += s.mae, total.smape += s.smape;
    total.max_abs = std::max(total.max_abs, s.max_abs);
  }
  ChannelErrors e;
  for (int c = 0; c < 3; ++c) e.channel[c] = mean(sum[c], double(n / 3));
  e.all = mean(total, double(n));
  return e;
}

ImageError image_error(const Image& image, const Image& reference) {
  return channel_errors(image, reference).all;
}

std::optional<std::string> first_non_finite(const Image& image) {
  for (size_t i = 0; i < image.rgb.size(); ++i)
    if (!std::isfinite(image.rgb[i])) {
      const size_t pixel = i / 3, width = size_t(image.width);
      return "pixel (" + std::to_string(pixel % width) + ", " + std::to_string(pixel / width) +
             ") channel " + "RGB"[i % 3] + " is " + (std::isnan(image.rgb[i]) ? "NaN" : "infinite");
    }
  return std::nullopt;
}

double noise_from_seeds(const Image& a, const Image& b) {
  return image_error(a, b).rmse / std::sqrt(2.0);
}

SplitReference combine_halves(const Image& a, const Image& b) {
  check_same_size(a, b);
  SplitReference r{a, {}};
  double se = 0, rel = 0;
  const size_t n = a.rgb.size();
  for (size_t k = 0; k < n; ++k) {
    const double mean = 0.5 * (double(a.rgb[k]) + double(b.rgb[k]));
    const double d = double(a.rgb[k]) - double(b.rgb[k]);
    r.image.rgb[k] = float(mean);
    se += d * d / 4;
    rel += d * d / 4 / (mean * mean + relmse_epsilon);
  }
  r.error.mse = se / double(n);
  r.error.relmse = rel / double(n);
  return r;
}

ImageError without_reference_error(const ImageError& measured, const ReferenceError& reference) {
  ImageError e = measured;
  e.rmse = std::sqrt(std::max(0.0, measured.rmse * measured.rmse - reference.mse));
  e.relmse = std::max(0.0, measured.relmse - reference.relmse);
  return e;
}

double student_t975(int dof) {
  // Exact to the digits shown up to 30 degrees of freedom; past that the Cornish-Fisher
  // expansion in 1/dof about the normal quantile z is within 1e-6 (2.042270 at 30, the table's
  // 2.042272).
  static constexpr double table[] = {12.7062047, 4.30265273, 3.18244631, 2.77644511, 2.57058184,
                                     2.44691185, 2.36462425, 2.30600414, 2.26215716, 2.22813885,
                                     2.20098516, 2.17881283, 2.16036866, 2.14478669, 2.13144955,
                                     2.11990530, 2.10981558, 2.10092204, 2.09302405, 2.08596345,
                                     2.07961384, 2.07387307, 2.06865761, 2.06389856, 2.05953855,
                                     2.05552944, 2.05183052, 2.04840714, 2.04522964, 2.04227246};
  if (dof < 1) return std::numeric_limits<double>::quiet_NaN();
  if (dof <= 30) return table[dof - 1];
  const double z = 1.959963984540054, z2 = z * z, v = dof;
  const double g1 = (z2 + 1) * z / 4, g2 = ((5 * z2 + 16) * z2 + 3) * z / 96,
               g3 = (((3 * z2 + 19) * z2 + 17) * z2 - 15) * z / 384;
  return z + g1 / v + g2 / (v * v) + g3 / (v * v * v);
}

Interval mean_interval95(const std::vector<double>& values) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  const size_t n = values.size();
  if (n == 0) return {nan, nan, nan};
  double sum = 0;
  for (double v : values) sum += v;
  const double mean = sum / double(n);
  if (n < 2) return {mean, nan, nan};
  double ss = 0;
  for (double v : values) ss += (v - mean) * (v - mean);
  const double half = student_t975(int(n - 1)) * std::sqrt(ss / double(n - 1) / double(n));
  return {mean, mean - half, mean + half};
}

bool too_short_to_time(double seconds) {
  return seconds < 0.1;
}

LogLogFit fit_log_log(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (size_t k = 0; k < x.size() && k < y.size(); ++k) {
    if (!usable(x[k], y[k])) continue;
    const double lx = std::log(x[k]), ly = std::log(y[k]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
    ++n;
  }
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  LogLogFit fit{nan, nan, n};
  const double denominator = n * sxx - sx * sx;
  if (n < 2 || !(std::abs(denominator) > 1e-12 * std::max(1.0, n * sxx))) return fit;
  fit.slope = (n * sxy - sx * sy) / denominator;
  fit.intercept = (sy - fit.slope * sx) / n;
  return fit;
}

std::optional<double> cost_to_reach(const std::vector<double>& cost,
                                    const std::vector<double>& error, double target) {
  if (!(target > 0)) return std::nullopt;
  const size_t n = std::min(cost.size(), error.size());
  for (size_t k = 0; k < n; ++k) {
    if (!usable(cost[k], error[k])) continue;
    if (error[k] > target) continue;
    if (k == 0 || !usable(cost[k - 1], error[k - 1])) return cost[k];
    // error[k − 1] > target ≥ error[k]: interpolate log cost against log error.
    return lerp_log(error[k - 1], cost[k - 1], error[k], cost[k], target);
  }
  return std::nullopt;
}

std::optional<double> error_at(const std::vector<double>& cost, const std::vector<double>& error,
                               double at) {
  const size_t n = std::min(cost.size(), error.size());
  for (size_t k = 0; k < n; ++k) {
    if (!usable(cost[k], error[k])) continue;
    if (cost[k] == at) return error[k];
    if (cost[k] < at) continue;
    if (k == 0 || !usable(cost[k - 1], error[k - 1])) return std::nullopt;  // before the first
    return lerp_log(cost[k - 1], error[k - 1], cost[k], error[k], at);
  }
  return std::nullopt;
}

}  // namespace dacrt
