// The convergence library (render/convergence.h) on images and curves computed by hand: each
// metric, the two-seed noise, the log-log slope fit, and the interpolations that the equal-error
// and equal-time comparisons of `dacrt converge` rest on.
#include "dacrt/render/convergence.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "dacrt/util/error.h"

using namespace dacrt;

namespace {

// A 2 × 1 image from its six channel values.
Image image(std::initializer_list<float> values) {
  Image i(2, 1);
  i.rgb.assign(values);
  return i;
}

}  // namespace

TEST_CASE("convergence: RMSE, relMSE, MAE and SMAPE of a hand-computed pair") {
  // Differences 0, 1, 0, 0, −1, 0.25 (two pixels, six channels).
  const Image x = image({1, 2, 0, 0, 0, 0.5f});
  const Image r = image({1, 1, 0, 0, 1, 0.25f});
  const ImageError e = image_error(x, r);
  CHECK(e.rmse == doctest::Approx(std::sqrt(2.0625 / 6)).epsilon(1e-12));
  // (x − r)² / (r² + 0.01): 1/1.01 twice, 0.0625/0.0725 once.
  CHECK(relmse_epsilon == 0.01);
  CHECK(e.relmse == doctest::Approx((2 / 1.01 + 0.0625 / 0.0725) / 6).epsilon(1e-12));
  CHECK(e.mae == doctest::Approx(2.25 / 6).epsilon(1e-12));
  // 2|x − r| / (|x| + |r|): 2/3, 2 (x = 0, r = 1), 2/3; the black pair counts 0.
  CHECK(e.smape == doctest::Approx((2.0 / 3 + 2 + 2.0 / 3) / 6).epsilon(1e-12));

  const ImageError same = image_error(x, x);
  CHECK(same.rmse == 0);
  CHECK(same.relmse == 0);
  CHECK(same.mae == 0);
  CHECK(same.smape == 0);
}

TEST_CASE("convergence: images of different sizes are an error naming both") {
  Image a(2, 1), b(1, 2);
  try {
    image_error(a, b);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(std::string(e.what()) == "cannot compare a 2 x 1 image with a 1 x 2 one");
  }
  CHECK_THROWS_AS(image_error(Image(), Image()), Error);
}

TEST_CASE("convergence: noise from two seeds is their RMSE over sqrt 2") {
  const Image a = image({1, 1, 1, 1, 1, 1}), b = image({0, 0, 0, 0, 0, 3});
  // Squared differences 1 × 5 and 4: RMSE √(9/6).
  CHECK(noise_from_seeds(a, b) == doctest::Approx(std::sqrt(1.5) / std::sqrt(2.0)));
}

TEST_CASE("convergence: the log-log fit is least squares on the logs") {
  SUBCASE("an exact power law") {
    const LogLogFit f = fit_log_log({1, 4, 16, 64}, {3, 1.5, 0.75, 0.375});
    CHECK(f.points == 4);
    CHECK(f.slope == doctest::Approx(-0.5));
    CHECK(f.intercept == doctest::Approx(std::log(3.0)));
  }
  SUBCASE("scattered points, solved by hand") {
    // log x = 0, L, 2L and log y = 0, −L, −L (L = ln 2): slope −L² / 2L² = −1/2, intercept
    // mean(log y) − slope·mean(log x) = −2L/3 + L/2 = −L/6.
    const LogLogFit f = fit_log_log({1, 2, 4}, {1, 0.5, 0.5});
    CHECK(f.points == 3);
    CHECK(f.slope == doctest::Approx(-0.5));
    CHECK(f.intercept == doctest::Approx(-std::log(2.0) / 6));
  }
  SUBCASE("zero, negative and non-finite points are left out") {
    const LogLogFit f = fit_log_log({1, 2, 4, 8, 16}, {1, 0, 0.25, NAN, -1});
    CHECK(f.points == 2);
    CHECK(f.slope == doctest::Approx(-1.0));
  }
  SUBCASE("too few points, or one x, have no slope") {
    CHECK(std::isnan(fit_log_log({2}, {1}).slope));
    CHECK(std::isnan(fit_log_log({2, 2}, {1, 0.5}).slope));
    CHECK(std::isnan(fit_log_log({}, {}).intercept));
  }
}

TEST_CASE("convergence: the cost to reach an error, interpolated in log-log") {
  const std::vector<double> cost = {1, 4, 16}, error = {1, 0.5, 0.25};
  CHECK(*cost_to_reach(cost, error, 0.5) == doctest::Approx(4));
  // 2^−1/2 is halfway between 1 and 0.5 in logs: halfway between 1 and 4, at 2.
  CHECK(*cost_to_reach(cost, error, std::sqrt(0.5)) == doctest::Approx(2));
  CHECK(*cost_to_reach(cost, error, 0.25 * std::sqrt(2.0)) == doctest::Approx(8));
  CHECK_FALSE(cost_to_reach(cost, error, 0.2));  // never reached
  CHECK(*cost_to_reach(cost, error, 2) == 1);    // already at the first point
  // A curve that goes back up: the first crossing counts.
  CHECK(*cost_to_reach({1, 4, 16, 64}, {1, 0.25, 0.8, 0.1}, 0.5) == doctest::Approx(2));
  CHECK_FALSE(cost_to_reach(cost, error, 0));
}

TEST_CASE("convergence: the error at a cost, interpolated in log-log") {
  const std::vector<double> cost = {1, 4, 16}, error = {1, 0.5, 0.25};
  CHECK(*error_at(cost, error, 2) == doctest::Approx(std::sqrt(0.5)));
  CHECK(*error_at(cost, error, 4) == doctest::Approx(0.5));
  CHECK(*error_at(cost, error, 8) == doctest::Approx(0.25 * std::sqrt(2.0)));
  CHECK(*error_at(cost, error, 1) == 1);
  CHECK_FALSE(error_at(cost, error, 0.5));  // before the first point
  CHECK_FALSE(error_at(cost, error, 32));   // after the last
}

TEST_CASE("convergence: the reference's own error, from its halves, is subtracted") {
  // A synthetic truth in [0.5, 2], a render x of it with noise σx, and a reference made of two
  // halves with noise σh each: the reference's MSE is σh²/2, and x's MSE against it σx² + σh²/2.
  // (relMSE's correction is first order: its denominator is the noisy reference's, so it holds
  // while the reference's relative noise is small, here 4 % at the darkest.)
  const int w = 200, h = 200;
  const double sx = 0.1, sh = 0.06;
  std::mt19937 rng(12345);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> level(0.5, 2.0);
  Image truth(w, h), x(w, h), a(w, h), b(w, h);
  for (size_t k = 0; k < truth.rgb.size(); ++k) {
    truth.rgb[k] = float(level(rng));
    x.rgb[k] = float(truth.rgb[k] + sx * normal(rng));
    a.rgb[k] = float(truth.rgb[k] + sh * normal(rng));
    b.rgb[k] = float(truth.rgb[k] + sh * normal(rng));
  }
  const SplitReference r = combine_halves(a, b);
  CHECK(r.image.rgb[7] == doctest::Approx(0.5 * (a.rgb[7] + b.rgb[7])));
  const double true_reference_mse =
      image_error(r.image, truth).rmse * image_error(r.image, truth).rmse;
  CHECK(r.error.mse == doctest::Approx(sh * sh / 2).epsilon(0.02).scale(0));
  CHECK(r.error.mse == doctest::Approx(true_reference_mse).epsilon(0.02).scale(0));
  const ImageError raw = image_error(x, r.image), truth_error = image_error(x, truth);
  CHECK(raw.rmse * raw.rmse == doctest::Approx(sx * sx + sh * sh / 2).epsilon(0.02).scale(0));
  const ImageError corrected = without_reference_error(raw, r.error);
  // The MSE against the truth, recovered from the noisy reference to within 2 %.
  CHECK(corrected.rmse == doctest::Approx(truth_error.rmse).epsilon(0.02).scale(0));
  CHECK(corrected.relmse == doctest::Approx(truth_error.relmse).epsilon(0.03).scale(0));
  CHECK(corrected.mae == raw.mae);  // not a sum of squares: as measured
  CHECK(corrected.smape == raw.smape);
  // Against a noisier reference than the image, the difference is clamped at 0.
  const ImageError clamped = without_reference_error({0.1, 0.01, 0.2, 0.3}, {0.02, 0.02});
  CHECK(clamped.rmse == 0);
  CHECK(clamped.relmse == 0);
  CHECK(clamped.mae == 0.2);
}

TEST_CASE("convergence: the 95 % interval of repeats, Student t") {
  CHECK(student_t975(1) == doctest::Approx(12.7062).epsilon(1e-5).scale(0));
  CHECK(student_t975(4) == doctest::Approx(2.77645).epsilon(1e-5).scale(0));
  CHECK(student_t975(30) == doctest::Approx(2.04227).epsilon(1e-5).scale(0));
  CHECK(student_t975(31) == doctest::Approx(2.03951).epsilon(1e-5).scale(0));
  CHECK(student_t975(60) == doctest::Approx(2.00030).epsilon(1e-5).scale(0));
  CHECK(student_t975(100000) == doctest::Approx(1.95999).epsilon(1e-5).scale(0));
  // 1..5: mean 3, s = √2.5, half width t(4)·s/√5 = 2.77645·0.707107 = 1.96324.
  const Interval i = mean_interval95({1, 2, 3, 4, 5});
  CHECK(i.mean == doctest::Approx(3));
  CHECK(i.low == doctest::Approx(3 - 1.963243).epsilon(1e-5).scale(0));
  CHECK(i.high == doctest::Approx(3 + 1.963243).epsilon(1e-5).scale(0));
  const Interval one = mean_interval95({0.25});
  CHECK(one.mean == 0.25);
  CHECK(std::isnan(one.low));
  CHECK(std::isnan(one.high));
  // Coverage: of 4000 intervals of 4 normal draws, about 95 % hold the true mean (± 4σ of the
  // binomial count, σ = 0.0034); with the normal quantile instead of t it would be 0.88.
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(5.0, 2.0);
  int covered = 0;
  const int trials = 4000;
  for (int t = 0; t < trials; ++t) {
    const Interval s = mean_interval95({normal(rng), normal(rng), normal(rng), normal(rng)});
    covered += s.low <= 5.0 && 5.0 <= s.high;
  }
  CHECK(double(covered) / trials == doctest::Approx(0.95).epsilon(0.0145).scale(0));
}

TEST_CASE("convergence: runs under 0.1 s are too short to time") {
  CHECK(too_short_to_time(0.0));
  CHECK(too_short_to_time(0.05));
  CHECK(too_short_to_time(0.0999));
  CHECK_FALSE(too_short_to_time(0.1));
  CHECK_FALSE(too_short_to_time(3.0));
}
