// Pearson's χ² test of a direction sampler against its claimed solid-angle pdf, as Mitsuba's
// test suite does it: sampled directions are counted on an odd θ × φ grid over the sphere, the pdf
// is integrated over each cell (composite Simpson with the sin θ Jacobian), cells expecting fewer
// than 5 samples are pooled, and the p-value comes from the χ² distribution.
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <numeric>
#include <optional>
#include <vector>

#include "dacrt/util/random.h"

namespace dacrt::test {

// Regularised upper incomplete gamma Q(a, x): its series below a + 1, its continued fraction
// (modified Lentz) above.
inline double gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 1000 && std::abs(term) > 1e-16 * std::abs(sum); ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return 1.0 - sum * std::exp(log_prefix);
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int n = 1; n < 1000; ++n) {
    const double an = -n * (n - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double step = d * c;
    h *= step;
    if (std::abs(step - 1.0) < 1e-15) break;
  }
  return std::exp(log_prefix) * h;
}

// P(χ²_dof ≥ x).
inline double chi2_survival(double x, int dof) {
  return gamma_q(0.5 * dof, 0.5 * x);
}

// (sin θ cos φ, sin θ sin φ, cos θ): z is the pole.
inline glm::vec3 direction(float theta, float phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// Counts `samples` directions from `sample(rng)` (an optional: nullopt = no sample) against
// `pdf(direction)` integrated over each cell; returns the p-value. A sample in a cell where the
// pdf integrates to zero fails the calling test.
// `sub` Simpson intervals per cell side: more for pdfs with jumps (piecewise-constant ones).
template <typename Sample, typename Pdf>
double chi2_p_value(Sample sample, Pdf pdf, uint64_t seed, size_t samples, int sub = 16) {
  constexpr int res_theta = 15, res_phi = 31;  // an odd grid
  const float d_theta = glm::pi<float>() / res_theta, d_phi = glm::two_pi<float>() / res_phi;
  std::vector<double> observed(res_theta * res_phi, 0.0), expected(res_theta * res_phi, 0.0);
  Pcg32 rng(seed);
  for (size_t k = 0; k < samples; ++k) {
    const std::optional<glm::vec3> d = sample(rng);
    if (!d) continue;
    const float theta = std::acos(std::clamp(d->z, -1.f, 1.f));
    const float phi = std::atan2(d->y, d->x) + glm::pi<float>();
    const int i = std::min(res_theta - 1, int(theta / d_theta));
    const int j = std::min(res_phi - 1, int(phi / d_phi));
    observed[i * res_phi + j] += 1.0;
  }
  // Composite Simpson over each cell, in (θ, φ) with the sin θ Jacobian.
  for (int i = 0; i < res_theta; ++i)
    for (int j = 0; j < res_phi; ++j) {
      double sum = 0.0;
      for (int a = 0; a <= sub; ++a)
        for (int b = 0; b <= sub; ++b) {
          const double wa = (a == 0 || a == sub) ? 1 : (a % 2 ? 4 : 2);
          const double wb = (b == 0 || b == sub) ? 1 : (b % 2 ? 4 : 2);
          const float theta = (i + float(a) / sub) * d_theta;
          const float phi = (j + float(b) / sub) * d_phi - glm::pi<float>();
          sum += wa * wb * pdf(direction(theta, phi)) * std::sin(theta);
        }
      expected[i * res_phi + j] = sum * (d_theta / sub / 3.0) * (d_phi / sub / 3.0) * samples;
    }
  // Pool the cells expecting fewer than 5 samples; a sample where none can be is a failure.
  std::vector<int> order(observed.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
  double pooled_obs = 0.0, pooled_exp = 0.0, chi2 = 0.0;
  int cells = 0;
  for (int c : order) {
    if (expected[c] == 0.0) {
      CHECK_MESSAGE(observed[c] == 0.0, "samples in cell " << c << " where the pdf is zero");
      continue;
    }
    // (and further cells until the pool itself expects 5)
    if (expected[c] < 5.0 || (pooled_exp > 0.0 && pooled_exp < 5.0)) {
      pooled_obs += observed[c], pooled_exp += expected[c];
      continue;
    }
    chi2 += (observed[c] - expected[c]) * (observed[c] - expected[c]) / expected[c];
    ++cells;
  }
  if (pooled_exp > 0.0) {
    chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++cells;
  }
  return chi2_survival(chi2, cells - 1);
}

}  // namespace dacrt::test
