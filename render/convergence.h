// Convergence: how far a render is from a reference, and how fast that distance shrinks. The
// image metrics compare linear radiance (every channel of every pixel, as rendered: no tone
// mapping); the fits and interpolations work on log-log curves of error against samples or time,
// which is where Monte Carlo error is a straight line (slope −1/2 for RMSE with independent
// samples). `dacrt converge` is built on these.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "util/image.h"

namespace dacrt {

// relMSE's epsilon: (x − r)² / (r² + ε) keeps black reference pixels from dividing by zero.
inline constexpr double relmse_epsilon = 1e-2;

struct ImageError {
  double rmse = 0.0;    // √(mean (x − r)²)
  double relmse = 0.0;  // mean (x − r)² / (r² + relmse_epsilon)
  double mae = 0.0;     // mean |x − r|
  double smape = 0.0;   // mean 2|x − r| / (|x| + |r|), a term 0 where both are 0; in [0, 2]
};

// The error of `image` against `reference`, over every channel of every pixel. Throws Error when
// the sizes differ (naming both) or the images are empty.
ImageError image_error(const Image& image, const Image& reference);

// The noise of one render measured from two of the same configuration with different seeds:
// RMSE(a, b) / √2, the RMSE either has against the converged image (their errors are
// independent, so the squared difference holds two variances).
double noise_from_seeds(const Image& a, const Image& b);

// The least-squares line y = intercept + slope·x through the points (log x, log y) for which both
// are positive and finite; `points` says how many. With fewer than two usable points (or all at
// one x) the slope and intercept are NaN.
struct LogLogFit {
  double slope, intercept;
  int points;
};
LogLogFit fit_log_log(const std::vector<double>& x, const std::vector<double>& y);

// A curve of error against cost (time or samples), cost increasing: where it first reaches
// `error` (interpolated linearly in log-log between the two points around the crossing), or
// nothing when it never does. A curve that starts at or below `error` reaches it at its first
// point.
std::optional<double> cost_to_reach(const std::vector<double>& cost,
                                    const std::vector<double>& error, double target);

// The same curve's error at `cost`, interpolated in log-log; nothing outside [first, last] cost.
std::optional<double> error_at(const std::vector<double>& cost, const std::vector<double>& error,
                               double at);

}  // namespace dacrt
