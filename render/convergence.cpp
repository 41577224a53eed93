#include "render/convergence.h"

#include <cmath>
#include <limits>

#include "util/error.h"

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

ImageError image_error(const Image& image, const Image& reference) {
  check_same_size(image, reference);
  double se = 0, rel = 0, ae = 0, sm = 0;
  const size_t n = image.rgb.size();
  for (size_t k = 0; k < n; ++k) {
    const double x = image.rgb[k], r = reference.rgb[k];
    const double d = x - r;
    se += d * d;
    rel += d * d / (r * r + relmse_epsilon);
    ae += std::abs(d);
    const double scale = std::abs(x) + std::abs(r);
    if (scale > 0) sm += 2 * std::abs(d) / scale;
  }
  ImageError e;
  e.rmse = std::sqrt(se / double(n));
  e.relmse = rel / double(n);
  e.mae = ae / double(n);
  e.smape = sm / double(n);
  return e;
}

double noise_from_seeds(const Image& a, const Image& b) {
  return image_error(a, b).rmse / std::sqrt(2.0);
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
