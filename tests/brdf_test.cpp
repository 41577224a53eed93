// The glTF metallic-roughness BRDF: its sampling follows its pdf (Pearson's χ² test as in
// Mitsuba: an odd grid over the sphere, the pdf integrated per cell, low-expectation cells
// pooled, significance 0.01 with Šidák's correction over all the tests), the weights it returns
// are eval · cos / pdf, it is reciprocal, and it never reflects more than it receives.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <numeric>
#include <sstream>
#include <vector>

#include "brdf_check.h"
#include "chi2.h"
#include "dacrt/materials/gltf_brdf.h"
#include "dacrt/materials/sampling.h"
#include "dacrt/util/random.h"

using namespace dacrt;
using dacrt::test::chi2_survival;
using dacrt::test::direction;

namespace {

double chi2_p_value(const GltfBrdf& sampler, const GltfBrdf& model, const glm::vec3& wo,
                    uint64_t seed, size_t samples) {
  return dacrt::test::brdf_chi2_p_value(sampler, model, wo, seed, samples);
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
      for (int ch = 0; ch < 3; ++ch)
        CHECK(s->weight[ch] == doctest::Approx(expected[ch]).epsilon(1e-5));
    }
  }
}

TEST_CASE("glTF BRDF: a coloured specular does not tint the diffuse, an infinite IOR is a mirror") {
  // Far from the mirror direction of a sharp lobe only the diffuse part is left: grey for a white
  // base, whatever the specular colour (fresnel_mix keeps 1 − max F of the base).
  const GltfBrdf tinted({glm::vec3(1.f), 0.f, 0.05f, 1.5f, 1.f, glm::vec3(1.f, 0.f, 0.f)});
  const glm::vec3 f =
      tinted.eval(direction(glm::radians(60.f), 0.f), direction(glm::radians(10.f), 2.f));
  CHECK(f.x > 0.f);
  CHECK(f.y == doctest::Approx(f.x).epsilon(1e-4));
  CHECK(f.z == doctest::Approx(f.x).epsilon(1e-4));
  // Spec-gloss conversions write huge IORs for "F0 = 1": finite values, a full specular layer.
  const GltfBrdf huge({glm::vec3(0.5f), 0.f, 0.5f, 1e30f, 1.f, glm::vec3(1.f)});
  const glm::vec3 wo = direction(glm::radians(40.f), 0.f);
  const glm::vec3 g = huge.eval(wo, direction(glm::radians(40.f), glm::pi<float>()));
  CHECK(std::isfinite(g.x));
  CHECK(g.x > 0.f);
  CHECK(std::isfinite(huge.pdf(wo, glm::vec3(0, 0, 1))));
}

TEST_CASE("cos_sin_quarter is within 1.5 x 2^-24 of cos and sin on [-pi/4, pi/4]") {
  double worst = 0.0;
  for (int k = -100000; k <= 100000; ++k) {
    const float x = glm::quarter_pi<float>() * float(k) / 100000.f;
    const glm::vec2 cs = cos_sin_quarter(x);
    worst = std::max({worst, std::abs(double(cs.x) - std::cos(double(x))),
                      std::abs(double(cs.y) - std::sin(double(x)))});
  }
  CHECK(worst <= 1.5 * 0x1p-24);
}

TEST_CASE("cosine hemisphere sampling is the concentric mapping, unit length, in both cases") {
  // The mapping with libm's cos and sin, in double: every point of a 1001 × 1001 grid (both of
  // its cases, the diagonals and the centre) lands within float rounding of it.
  double worst = 0.0, worst_length = 0.0;
  for (int i = 0; i <= 1000; ++i)
    for (int j = 0; j <= 1000; ++j) {
      const float u1 = std::min(float(i) / 1000.f, 0x1.fffffep-1f), u2 = float(j) / 1000.f;
      const double a = 2.0 * u1 - 1.0, b = 2.0 * double(u2) - 1.0;
      double r = 0.0, phi = 0.0;
      if (a != 0.0 || b != 0.0) {
        if (std::abs(a) > std::abs(b))
          r = a, phi = glm::quarter_pi<double>() * (b / a);
        else
          r = b, phi = glm::half_pi<double>() - glm::quarter_pi<double>() * (a / b);
      }
      const glm::dvec3 expect(r * std::cos(phi), r * std::sin(phi),
                              std::sqrt(std::max(0.0, 1.0 - r * r)));
      const glm::vec3 got = sample_cosine_hemisphere(u1, u2);
      // (z near the rim is √ of a tiny difference: compared as z², what the float rounding leaves.)
      worst = std::max({worst, std::abs(got.x - expect.x), std::abs(got.y - expect.y),
                        std::abs(double(got.z) * got.z - expect.z * expect.z)});
      worst_length = std::max(worst_length, std::abs(glm::length(glm::dvec3(got)) - 1.0));
      REQUIRE(got.z >= 0.f);
    }
  CHECK(worst < 3e-7);
  CHECK(worst_length < 3e-7);
}

TEST_CASE("glTF BRDF is reciprocal and zero below the surface") {
  Pcg32 rng(5);
  for (const Config& c : configs()) {
    INFO(c.label());
    dacrt::test::check_reciprocal_reflection(GltfBrdf(c.params), rng, -1.f);  // every pair
  }
}

TEST_CASE("glTF BRDF never reflects more than it receives, and a white mirror reflects it all") {
  // Albedo ∫ f cos dωi by importance sampling, per channel, for white materials.
  auto albedo = [](const BrdfParams& p, float theta, uint64_t seed) {
    return dacrt::test::brdf_albedo(GltfBrdf(p), direction(theta, 0.f), seed);
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

// KHR_materials_transmission (thin-walled): the specular lobe mirrored through the surface.
namespace {

std::vector<Config> transmission_configs() {
  std::vector<Config> c;
  const glm::vec3 color(0.8f, 0.5f, 0.2f);
  for (float transmission : {0.5f, 1.f})
    for (float roughness : {0.3f, 0.8f})
      for (float theta : {20.f, 70.f}) {
        BrdfParams p{color, 0.f, roughness, 1.5f, 1.f, glm::vec3(1.f)};
        p.transmission = transmission;
        c.push_back({p, glm::radians(theta)});
      }
  BrdfParams partly_metal{color, 0.4f, 0.5f, 1.5f, 1.f, glm::vec3(1.f)};
  partly_metal.transmission = 1.f;
  c.push_back({partly_metal, glm::radians(45.f)});
  return c;
}

}  // namespace

TEST_CASE(
    "transmission: sampling both sides follows the pdf (χ²), weights are eval · |cos| / pdf") {
  const auto all = transmission_configs();
  const double level = 1.0 - std::pow(1.0 - 0.01, 1.0 / double(all.size()));
  Pcg32 rng(21);
  for (size_t k = 0; k < all.size(); ++k) {
    const Config& c = all[k];
    INFO(c.label() << ", transmission " << c.params.transmission);
    const GltfBrdf brdf(c.params);
    const glm::vec3 wo = direction(c.theta_o, 0.3f);
    CHECK(chi2_p_value(brdf, brdf, wo, 2000 + k, 400000) > level);
    CHECK(dacrt::test::check_sample_weights(brdf, wo, rng) > 200);  // the transmission lobe is sampled
  }
}

TEST_CASE("transmission: the BTDF is the reflection lobe mirrored, tinted, weighted 1 − F") {
  BrdfParams p{glm::vec3(1.f, 0.5f, 0.25f), 0.f, 0.5f, 1.5f, 1.f, glm::vec3(1.f)};
  p.transmission = 1.f;
  const GltfBrdf brdf(p);
  const float alpha = 0.25f;
  for (float theta : {0.f, 30.f, 60.f}) {
    const glm::vec3 wo = direction(glm::radians(theta), 0.f);
    // Straight through, wi = −wo: mirrored through the surface it is wo's mirror direction m,
    // so the half vector is the normal.
    const glm::vec3 through(-wo.x, -wo.y, -wo.z);
    const glm::vec3 m(-wo.x, -wo.y, wo.z);
    const glm::vec3 h = glm::normalize(wo + m);
    const float f0 = 0.04f, w = std::pow(1.f - glm::dot(wo, h), 5.f);
    const float expected =
        (1.f - (f0 + (1.f - f0) * w)) * ggx_d(h.z, alpha) * ggx_visibility(wo.z, m.z, alpha);
    const glm::vec3 f = brdf.eval(wo, through);
    CHECK(f.x == doctest::Approx(expected).epsilon(1e-4));
    CHECK(f.y == doctest::Approx(0.5f * expected).epsilon(1e-4));  // tinted by the base colour
  }
  // No diffuse is left above at full transmission, none is transmitted without it or by a metal.
  const glm::vec3 wo = direction(glm::radians(30.f), 0.f);
  const glm::vec3 off = direction(glm::radians(70.f), 2.5f);  // far from the mirror direction
  BrdfParams opaque = p;
  opaque.transmission = 0.f;
  CHECK(GltfBrdf(opaque).eval(wo, off).x > 10.f * brdf.eval(wo, off).x);
  CHECK(GltfBrdf(opaque).eval(wo, -off) == glm::vec3(0.f));
  BrdfParams metal = p;
  metal.metallic = 1.f;
  CHECK(GltfBrdf(metal).eval(wo, glm::vec3(-wo.x, -wo.y, -wo.z)) == glm::vec3(0.f));
}

TEST_CASE("transmission: a white thin sheet scatters at most what it receives, all when smooth") {
  for (float roughness : {0.f, 0.3f, 0.7f, 1.f})
    for (float theta : {0.f, 30.f, 45.f}) {
      BrdfParams p{glm::vec3(1.f), 0.f, roughness, 1.5f, 1.f, glm::vec3(1.f)};
      p.transmission = 1.f;
      const GltfBrdf brdf(p);
      Pcg32 rng(31);
      const glm::vec3 wo = direction(glm::radians(theta), 0.f);
      double sum = 0.0, sum2 = 0.0;
      constexpr int n = 200000;
      for (int k = 0; k < n; ++k) {
        const auto s = brdf.sample(wo, rng.uniform(), rng.uniform(), rng.uniform());
        if (!s) continue;
        sum += s->weight.x, sum2 += double(s->weight.x) * s->weight.x;
      }
      const double mean = sum / n, error = std::sqrt(std::max(sum2 / n - mean * mean, 0.0) / n);
      INFO("roughness " << roughness << ", θo " << theta << ": " << mean << " ± " << error);
      CHECK(mean <= 1.0 + 4.0 * error + 1e-6);
      if (roughness == 0.f) CHECK(mean == doctest::Approx(1.0).epsilon(2e-3));
    }
}

TEST_CASE(
    "glTF BRDF: with no specular, metal or transmission it is Lambert's, and continuous there") {
  BrdfParams lambert;
  lambert.base_color = {0.7f, 0.4f, 0.2f};
  lambert.metallic = 0.f;
  lambert.specular = 0.f;
  lambert.roughness = 0.3f;
  const GltfBrdf f(lambert);
  CHECK(f.lambertian());
  BrdfParams almost = lambert;  // the general formula, a hair away
  almost.specular = 1e-7f;
  const GltfBrdf g(almost);
  CHECK_FALSE(g.lambertian());
  BrdfParams dielectric = lambert;
  dielectric.specular = 1.f;
  CHECK_FALSE(GltfBrdf(dielectric).lambertian());
  Pcg32 rng(3);
  for (int k = 0; k < 2000; ++k) {
    const glm::vec3 wo = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
    const glm::vec3 wi = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
    if (!(wo.z > 1e-3f && wi.z > 1e-3f)) continue;
    const glm::vec3 e = f.eval(wo, wi), e_ref = lambert.base_color * glm::one_over_pi<float>();
    for (int c = 0; c < 3; ++c) {
      CHECK(e[c] == doctest::Approx(e_ref[c]).epsilon(1e-6));
      CHECK(g.eval(wo, wi)[c] == doctest::Approx(e[c]).epsilon(1e-5));
    }
    CHECK(f.pdf(wo, wi) == doctest::Approx(wi.z / glm::pi<float>()).epsilon(1e-6));
    CHECK(g.pdf(wo, wi) == doctest::Approx(f.pdf(wo, wi)).epsilon(1e-5));
    CHECK(f.eval(wo, -wi) == glm::vec3(0.f));
    CHECK(f.pdf(wo, -wi) == 0.f);
    const auto s = f.sample(wo, rng.uniform(), rng.uniform(), rng.uniform());
    REQUIRE(s);
    CHECK(s->wi.z > 0.f);
    CHECK(s->pdf == doctest::Approx(f.pdf(wo, s->wi)).epsilon(1e-6));
    for (int c = 0; c < 3; ++c)
      CHECK(s->weight[c] == doctest::Approx(f.eval(wo, s->wi)[c] * s->wi.z / s->pdf).epsilon(1e-5));
  }
}
