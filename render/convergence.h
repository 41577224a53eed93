// Convergence: how far a render is from a reference, and how fast that distance shrinks. The
// image metrics compare linear radiance (every channel of every pixel, as rendered: no tone
// mapping); the fits and interpolations work on log-log curves of error against samples or time,
// which is where Monte Carlo error is a straight line (slope −1/2 for RMSE with independent
// samples). `dacrt converge` is built on these.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "dacrt/util/image.h"

namespace dacrt {

// relMSE's epsilon: (x − r)² / (r² + ε) keeps black reference pixels from dividing by zero.
inline constexpr double relmse_epsilon = 1e-2;

struct ImageError {
  double rmse = 0.0;     // √(mean (x − r)²)
  double relmse = 0.0;   // mean (x − r)² / (r² + relmse_epsilon)
  double mae = 0.0;      // mean |x − r|
  double smape = 0.0;    // mean 2|x − r| / (|x| + |r|), a term 0 where both are 0; in [0, 2]
  double max_abs = 0.0;  // max |x − r|
};

// The error of `image` against `reference`, over every channel of every pixel. Throws Error when
// the sizes differ (naming both) or the images are empty.
ImageError image_error(const Image& image, const Image& reference);

// The same for each channel alone (R, G, B) and over all three (what image_error gives).
struct ChannelErrors {
  std::array<ImageError, 3> channel;
  ImageError all;
};
ChannelErrors channel_errors(const Image& image, const Image& reference);

// Where `image` first holds a NaN or an infinite value, scanning pixels row by row from the
// top-left: "pixel (x, y) channel G is NaN" (or "is infinite"); nothing when every value is
// finite. The metrics of an image with one are NaN or infinite, so callers refuse it.
std::optional<std::string> first_non_finite(const Image& image);

// The noise of one render measured from two of the same configuration with different seeds:
// RMSE(a, b) / √2, the RMSE either has against the converged image (their errors are
// independent, so the squared difference holds two variances).
double noise_from_seeds(const Image& a, const Image& b);

// The error a reference has against the converged image, estimated from two independent renders
// a and b of it (the reference is their mean): per channel E[(a − b)²] = var a + var b =
// 4 var((a + b)/2), so mean (a − b)²/4 is the reference's MSE, and the same over r² + ε its
// relMSE (r the mean, as in image_error). No assumption on how each half converges (Sobol or
// independent samples, any spp each): only that they are unbiased and independent.
struct ReferenceError {
  double mse = 0.0;     // the reference's mean (r − truth)²
  double relmse = 0.0;  // mean (r − truth)² / (r² + relmse_epsilon)
};
struct SplitReference {
  Image image;  // (a + b) / 2
  ReferenceError error;
};
// Throws Error when the sizes differ or the images are empty.
SplitReference combine_halves(const Image& a, const Image& b);

// An error measured against a noisy reference r with r's own error taken out. x − r =
// (x − truth) − (r − truth) with independent terms, so E[(x − r)²] = MSE(x) + MSE(r): RMSE
// becomes √max(0, RMSE² − mse) and relMSE max(0, relMSE − relmse) (clamped at 0: both terms are
// estimates, and near convergence their difference can come out negative). MAE and SMAPE are
// not sums of squares and stay as measured.
ImageError without_reference_error(const ImageError& measured, const ReferenceError& reference);

// The mean of repeated measurements and its 95 % confidence interval, mean ± t·s/√n with s the
// sample standard deviation and t the Student t quantile 0.975 with n − 1 degrees of freedom
// (the repeats' errors taken as normal). With fewer than two values low and high are NaN.
struct Interval {
  double mean, low, high;
};
Interval mean_interval95(const std::vector<double>& values);
// The quantile 0.975 of Student's t with `dof` ≥ 1 degrees of freedom: 12.71 at 1, 2.78 at 4,
// 1.96 in the limit.
double student_t975(int dof);

// Whether a run of `seconds` is too short to time: under 0.1 s a run is a few scheduler slices,
// and its time is mostly the timer's, the caches' and the other processes' noise.
bool too_short_to_time(double seconds);

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
