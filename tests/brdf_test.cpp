// The glTF metallic-roughness BRDF: its sampling follows its pdf (Pearson's χ² test as in
// Mitsuba: an odd grid over the sphere, the pdf integrated per cell, low-expectation cells
// pooled, significance 0.01 with Šidák's correction over all the tests), the weights it returns
// are eval · cos / pdf, it is reciprocal, and it never reflects more than it receives.
#include "materials/gltf_brdf.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <numeric>
#include <sstream>
#include <vector>

#include "materials/sampling.h"
#include "util/random.h"

using namespace dacrt;

namespace {

// Regularised upper incomplete gamma Q(a, x): its series below a + 1, its continued fraction
// (modified Lentz) above.
double gamma_q(double a, double x) {
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
double chi2_survival(double x, int dof) {
  return gamma_q(0.5 * dof, 0.5 * x);
}

glm::vec3 direction(float theta, float phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

struct Config {
  BrdfParams params;
  float theta_o;  // viewing angle from the normal, radians
  std::string label() const {
    std::ostringstream s;
    s << "roughness " << params.roughness << ", metallic " << params.metallic << ", ior "
      << params.ior << ", specular " << params.specular << ", θo " << glm::degrees(theta_o) << "°";
    return s.str();
  }
};

// Histogram of directions sampled by `sampler` against the pdf of `model` integrated over each
// cell of a θ × φ grid; returns the p-value and fails on a sample in a cell of zero expectation.
double chi2_p_value(const GltfBrdf& sampler, const GltfBrdf& model, const glm::vec3& wo,
                    uint64_t seed, size_t samples) {
  constexpr int res_theta = 15, res_phi = 31, sub = 16;  // odd grid; Simpson sub-intervals
  const float d_theta = glm::pi<float>() / res_theta, d_phi = glm::two_pi<float>() / res_phi;
  std::vector<double> observed(res_theta * res_phi, 0.0), expected(res_theta * res_phi, 0.0);
  Pcg32 rng(seed);
  for (size_t k = 0; k < samples; ++k) {
    const float u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    const auto s = sampler.sample(wo, u0, u1, u2);
    if (!s) continue;
    const float theta = std::acos(std::clamp(s->wi.z, -1.f, 1.f));
    const float phi = std::atan2(s->wi.y, s->wi.x) + glm::pi<float>();
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
          sum += wa * wb * model.pdf(wo, direction(theta, phi)) * std::sin(theta);
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

std::vector<Config> configs() {
  std::vector<Config> c;
  const glm::vec3 color(0.8f, 0.5f, 0.2f);
  for (float roughness : {0.25f, 0.5f, 1.f})
    for (float metallic : {0.f, 0.5f, 1.f})
      for (float theta : {10.f, 45.f, 80.f})
        c.push_back({{color, metallic, roughness, 1.5f, 1.f, glm::vec3(1.f)}, glm::radians(theta)});
  for (float ior : {1.1f, 2.5f})
    for (float theta : {30.f, 70.f})
      c.push_back({{color, 0.f, 0.4f, ior, 1.f, glm::vec3(1.f)}, glm::radians(theta)});
  // KHR_materials_specular: weaker and coloured dielectric reflection.
  c.push_back({{color, 0.f, 0.4f, 1.5f, 0.3f, glm::vec3(1.f, 0.2f, 0.5f)}, glm::radians(50.f)});
  c.push_back({{color, 0.2f, 0.4f, 1.5f, 0.f, glm::vec3(1.f)}, glm::radians(20.f)});
  return c;
}

}  // namespace

TEST_CASE("the χ² survival function matches tabulated values") {
  CHECK(chi2_survival(3.841459, 1) == doctest::Approx(0.05).epsilon(1e-5));
  CHECK(chi2_survival(11.344867, 3) == doctest::Approx(0.01).epsilon(1e-5));
  CHECK(chi2_survival(124.342, 100) == doctest::Approx(0.05).epsilon(1e-4));
  CHECK(chi2_survival(2.0, 2) == doctest::Approx(std::exp(-1.0)).epsilon(1e-12));
  CHECK(chi2_survival(0.0, 5) == 1.0);
}

TEST_CASE("glTF BRDF sampling follows its pdf (χ²)") {
  const auto all = configs();
  // Šidák: every test at this level keeps the family's false-failure rate at 1 %.
  const double level = 1.0 - std::pow(1.0 - 0.01, 1.0 / double(all.size()));
  for (size_t k = 0; k < all.size(); ++k) {
    const Config& c = all[k];
    INFO(c.label());
    const GltfBrdf brdf(c.params);
    const double p = chi2_p_value(brdf, brdf, direction(c.theta_o, 0.3f), 1000 + k, 400000);
    CHECK(p > level);
  }
}

TEST_CASE("the χ² test notices a pdf that is slightly off") {
  // Samples from roughness 0.45 against the pdf of roughness 0.5: a test that passed this would
  // prove nothing.
  BrdfParams params{glm::vec3(0.8f, 0.5f, 0.2f), 0.f, 0.5f, 1.5f, 1.f, glm::vec3(1.f)};
  const GltfBrdf model(params);
  params.roughness = 0.45f;
  const GltfBrdf sampler(params);
  CHECK(chi2_p_value(sampler, model, direction(glm::radians(45.f), 0.3f), 99, 400000) < 1e-6);
}

TEST_CASE("glTF BRDF samples carry eval · cos / pdf, and pdf() is their density") {
  Pcg32 rng(3);
  for (const Config& c : configs()) {
    INFO(c.label());
    const GltfBrdf brdf(c.params);
    const glm::vec3 wo = direction(c.theta_o, 1.1f);
    for (int k = 0; k < 2000; ++k) {
      const auto s = brdf.sample(wo, rng.uniform(), rng.uniform(), rng.uniform());
      if (!s) continue;
      REQUIRE(s->wi.z > 0.f);
      CHECK(s->pdf == doctest::Approx(brdf.pdf(wo, s->wi)).epsilon(1e-5));
      const glm::vec3 expected = brdf.eval(wo, s->wi) * s->wi.z / s->pdf;
      for (int ch = 0; ch < 3; ++ch) CHECK(s->weight[ch] == doctest::Approx(expected[ch]).epsilon(1e-5));
    }
  }
}

TEST_CASE("glTF BRDF is reciprocal and zero below the surface") {
  Pcg32 rng(5);
  for (const Config& c : configs()) {
    INFO(c.label());
    const GltfBrdf brdf(c.params);
    for (int k = 0; k < 500; ++k) {
      const glm::vec3 a = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
      const glm::vec3 b = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
      const glm::vec3 fab = brdf.eval(a, b), fba = brdf.eval(b, a);
      for (int ch = 0; ch < 3; ++ch) CHECK(fab[ch] == doctest::Approx(fba[ch]).epsilon(1e-4));
      const glm::vec3 below(b.x, b.y, -b.z);
      CHECK(brdf.eval(a, below) == glm::vec3(0.f));
      CHECK(brdf.pdf(a, below) == 0.f);
    }
  }
}

TEST_CASE("glTF BRDF never reflects more than it receives, and a white mirror reflects it all") {
  // Albedo ∫ f cos dωi by importance sampling, per channel, for white materials.
  auto albedo = [](const BrdfParams& p, float theta, uint64_t seed) {
    const GltfBrdf brdf(p);
    Pcg32 rng(seed);
    const glm::vec3 wo = direction(theta, 0.f);
    constexpr int n = 200000;
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int k = 0; k < n; ++k) {
      const auto s = brdf.sample(wo, rng.uniform(), rng.uniform(), rng.uniform());
      if (!s) continue;
      const glm::dvec3 w(s->weight);
      sum += w, sum2 += w * w;
    }
    const glm::dvec3 mean = sum / double(n);
    const glm::dvec3 error = glm::sqrt(glm::max(sum2 / double(n) - mean * mean, 0.0) / double(n));
    return std::pair{mean, error};
  };
  // The metal, the dielectric's specular layer alone (black base) and the diffuse layer alone
  // (specular 0) at every angle; the full dielectric up to 30°. Beyond that the specification's
  // fresnel_mix itself reflects more than it receives: it weights the base by 1 − F(v·h) per
  // direction, not by what the layer really reflects (a white dielectric returns up to 1.0016 at
  // 45°, 1.2 at 75° and 1.85 at 89° when smooth), and it is rendered as specified.
  struct Case {
    glm::vec3 base;
    float metallic, specular, max_theta;
  };
  for (const Case& c : {Case{glm::vec3(1.f), 1.f, 1.f, 89.f}, Case{glm::vec3(0.f), 0.f, 1.f, 89.f},
                        Case{glm::vec3(1.f), 0.f, 0.f, 89.f}, Case{glm::vec3(1.f), 0.f, 1.f, 30.f},
                        Case{glm::vec3(1.f), 0.5f, 1.f, 30.f}})
    for (float roughness : {0.f, 0.3f, 0.7f, 1.f})
      for (float ior : {1.1f, 1.5f, 3.f})
        for (float theta : {0.f, 30.f, 45.f, 75.f, 89.f}) {
          if (theta > c.max_theta) continue;
          const BrdfParams p{c.base, c.metallic, roughness, ior, c.specular, glm::vec3(1.f)};
          INFO("base " << c.base.x << ", metallic " << c.metallic << ", specular " << c.specular
                       << ", roughness " << roughness << ", ior " << ior << ", θo " << theta);
          const auto [mean, error] = albedo(p, glm::radians(theta), 11);
          for (int ch = 0; ch < 3; ++ch) CHECK(mean[ch] <= 1.0 + 4.0 * error[ch] + 1e-6);
        }
  // A smooth white metal (roughness 0: α clamped to 1e-3) is a mirror that loses nothing.
  for (float theta : {0.f, 45.f, 80.f}) {
    INFO("θo " << theta);
    const auto [mean, error] =
        albedo({glm::vec3(1.f), 1.f, 0.f, 1.5f, 1.f, glm::vec3(1.f)}, glm::radians(theta), 13);
    CHECK(mean.x == doctest::Approx(1.0).epsilon(2e-3));
  }
  // specular 0 leaves white Lambert: every sample's weight is exactly 1.
  const auto [mean, error] =
      albedo({glm::vec3(1.f), 0.f, 0.5f, 1.5f, 0.f, glm::vec3(1.f)}, glm::radians(30.f), 17);
  CHECK(mean.x == doctest::Approx(1.0).epsilon(1e-6));
}
