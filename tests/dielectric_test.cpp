// The rough dielectric interface of KHR_materials_volume (materials/dielectric.h) and the BSDF
// that mixes it into the glTF BRDF (materials/bsdf.h): sampling follows the pdf on both the
// reflection and the refraction side (χ², as tests/brdf_test.cpp), samples carry eval · cos / pdf,
// the interface neither creates energy nor, when smooth, loses any, refraction obeys the
// generalised reciprocity f(wo, wi) / η_wo² = f(wi, wo) / η_wi², and its Fresnel and Snell's law
// are the textbook ones. KHR_materials_dispersion's IOR is the spec's formula.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <sstream>

#include "chi2.h"
#include "test_geometry.h"
#include "dacrt/materials/bsdf.h"
#include "dacrt/materials/dielectric.h"
#include "dacrt/util/random.h"

using namespace dacrt;
using dacrt::test::direction;

namespace {

struct Case {
  float eta, alpha, theta_o;
  std::string label() const {
    std::ostringstream s;
    s << "η " << eta << ", α " << alpha << ", θo " << glm::degrees(theta_o) << "°";
    return s.str();
  }
};

// η > 1 (entering glass) and η < 1 (leaving it, with total internal reflection beyond the
// critical angle), rough enough for the grid to resolve.
std::vector<Case> cases() {
  std::vector<Case> c;
  for (float eta : {1.5f, 1.f / 1.5f, 1.1f})
    for (float alpha : {0.2f, 0.5f})
      for (float theta : {15.f, 60.f}) c.push_back({eta, alpha, glm::radians(theta)});
  return c;
}

template <class Model>
double p_value(const Model& model, const glm::vec3& wo, uint64_t seed, int sub = 16) {
  return dacrt::test::chi2_p_value(
      [&](Pcg32& rng) -> std::optional<glm::vec3> {
        const float u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
        const auto s = model.sample(wo, u0, u1, u2);
        if (!s) return std::nullopt;
        return s->wi;
      },
      [&](const glm::vec3& wi) { return model.pdf(wo, wi); }, seed, 400000, sub);
}

// A mirror in z: the same interface seen from its other side.
glm::vec3 flip(const glm::vec3& v) {
  return {v.x, v.y, -v.z};
}

}  // namespace

TEST_CASE("dielectric: Fresnel is 0.04 head-on into glass, 1 beyond the critical angle, symmetric") {
  CHECK(fresnel_dielectric(1.f, 1.5f) == doctest::Approx(0.04f).epsilon(1e-5));
  CHECK(fresnel_dielectric(1.f, 1.f / 1.5f) == doctest::Approx(0.04f).epsilon(1e-5));
  // Leaving glass: sin θc = 1 / 1.5.
  const float critical = std::asin(1.f / 1.5f);
  CHECK(fresnel_dielectric(std::cos(critical + 0.01f), 1.f / 1.5f) == 1.f);
  CHECK(fresnel_dielectric(std::cos(critical - 0.01f), 1.f / 1.5f) < 1.f);
  // The same interface from either side at Snell-related angles reflects alike.
  for (float theta_i : {0.2f, 0.7f, 1.2f}) {
    const float theta_t = std::asin(std::sin(theta_i) / 1.5f);
    CHECK(fresnel_dielectric(std::cos(theta_i), 1.5f) ==
          doctest::Approx(fresnel_dielectric(std::cos(theta_t), 1.f / 1.5f)).epsilon(1e-4));
  }
  // s and p at 45° into glass, by hand: rs = −0.3034, rp = 0.0920.
  CHECK(fresnel_dielectric(std::cos(glm::quarter_pi<float>()), 1.5f) ==
        doctest::Approx(0.5 * (0.30346 * 0.30346 + 0.09204 * 0.09204)).epsilon(1e-3));
}

TEST_CASE("dielectric: sampling follows the pdf on both sides of the interface (χ²)") {
  const auto all = cases();
  // Šidák: an overall significance of 0.01 over every test.
  const double level = 1.0 - std::pow(0.99, 1.0 / double(all.size() + 2));
  uint64_t seed = 7000;
  for (const Case& c : all) {
    INFO(c.label());
    const RoughDielectric d(c.eta, c.alpha, glm::vec3(1.f));
    const glm::vec3 wo = direction(c.theta_o, 0.4f);
    // Both lobes are sampled (else the test would only cover one side).
    Pcg32 rng(seed);
    int reflected = 0, refracted = 0;
    for (int k = 0; k < 2000; ++k)
      if (auto s = d.sample(wo, rng.uniform(), rng.uniform(), rng.uniform()))
        (s->wi.z > 0.f ? reflected : refracted)++;
    CHECK(reflected > 0);
    if (!(c.eta < 1.f && c.theta_o > std::asin(c.eta) + 0.3f)) CHECK(refracted > 0);
    // (Near η = 1 the refracted lobe is narrow: finer integration of the pdf per cell.)
    CHECK(p_value(d, wo, ++seed, c.eta == 1.1f ? 96 : 16) > level);
  }
  // The mixture of the glTF BRDF and the interface (a half-transmissive, half-metallic volume).
  BrdfParams p;
  p.base_color = glm::vec3(0.8f, 0.6f, 0.3f), p.metallic = 0.3f, p.roughness = 0.6f;
  p.transmission = 0.7f;
  for (float theta : {20.f, 70.f}) {
    INFO("mixture, θo " << theta);
    CHECK(p_value(Bsdf::volume(p, 1.5f), direction(glm::radians(theta), 1.f), ++seed) > level);
  }
}

TEST_CASE("dielectric: the χ² test notices refraction sampled with the wrong η") {
  const RoughDielectric sampler(1.5f, 0.3f, glm::vec3(1.f)), model(1.4f, 0.3f, glm::vec3(1.f));
  const glm::vec3 wo = direction(glm::radians(40.f), 0.2f);
  const double p = dacrt::test::chi2_p_value(
      [&](Pcg32& rng) -> std::optional<glm::vec3> {
        const auto s = sampler.sample(wo, rng.uniform(), rng.uniform(), rng.uniform());
        return s ? std::optional<glm::vec3>(s->wi) : std::nullopt;
      },
      [&](const glm::vec3& wi) { return model.pdf(wo, wi); }, 99, 400000);
  CHECK(p < 1e-6);
}

TEST_CASE("dielectric: samples carry eval · cos / pdf, and pdf() is their density") {
  for (const Case& c : cases()) {
    INFO(c.label());
    const RoughDielectric d(c.eta, c.alpha, glm::vec3(0.9f, 0.7f, 0.5f));
    const glm::vec3 wo = direction(c.theta_o, 1.3f);
    Pcg32 rng(11);
    for (int k = 0; k < 200; ++k) {
      const auto s = d.sample(wo, rng.uniform(), rng.uniform(), rng.uniform());
      if (!s) continue;
      CHECK(s->pdf == doctest::Approx(d.pdf(wo, s->wi)).epsilon(1e-3));
      const glm::vec3 expected = d.eval(wo, s->wi) * (std::abs(s->wi.z) / s->pdf);
      for (int ch = 0; ch < 3; ++ch)
        CHECK(s->weight[ch] == doctest::Approx(expected[ch]).epsilon(1e-3));
    }
  }
}

TEST_CASE("dielectric: white furnace: energy <= 1, and all of it when smooth") {
  // Light arriving along wo leaves along wi with the adjoint BSDF: f(wo, wi) for reflection and
  // η² f(wo, wi) for refraction (f is radiance's BSDF, with its 1/η²). Its albedo is the mean
  // sample weight times that η².
  for (float eta : {1.5f, 1.f / 1.33f, 2.4f})
    for (float alpha : {GltfBrdf::min_alpha, 0.3f, 0.8f})
      for (float theta : {5.f, 40.f, 75.f}) {
        INFO("η " << eta << ", α " << alpha << ", θo " << theta);
        const RoughDielectric d(eta, alpha, glm::vec3(1.f));
        const glm::vec3 wo = direction(glm::radians(theta), 0.7f);
        Pcg32 rng(5);
        const int n = 200000;
        double sum = 0.0, sum2 = 0.0;
        for (int k = 0; k < n; ++k) {
          const auto s = d.sample(wo, rng.uniform(), rng.uniform(), rng.uniform());
          const double w = s ? s->weight.x * (s->wi.z < 0.f ? eta * eta : 1.f) : 0.0;
          sum += w, sum2 += w * w;
        }
        const double mean = sum / n, error = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
        CHECK(mean <= 1.0 + 4.0 * error + 1e-6);
        if (alpha == GltfBrdf::min_alpha) CHECK(mean == doctest::Approx(1.0).epsilon(2e-3));
        // (Single scattering loses energy on rough interfaces, most from inside, where much is
        // reflected back and shadowed, not most of it.)
        if (alpha > 0.5f) CHECK(mean > (eta > 1.f ? 0.7 : 0.45));
      }
}

TEST_CASE("dielectric: reflection is reciprocal, refraction f(wo, wi) / η_wo² = f(wi, wo) / η_wi²") {
  Pcg32 rng(3);
  for (float eta : {1.5f, 1.f / 1.2f})
    for (float alpha : {0.1f, 0.5f}) {
      INFO("η " << eta << ", α " << alpha);
      const RoughDielectric above(eta, alpha, glm::vec3(1.f)), below(1.f / eta, alpha, glm::vec3(1.f));
      int compared = 0;
      for (int k = 0; k < 400; ++k) {
        glm::vec3 wo = dacrt::test::random_direction(rng), wi = dacrt::test::random_direction(rng);
        wo.z = std::abs(wo.z);
        // Reflection: both above.
        const glm::vec3 up(wi.x, wi.y, std::abs(wi.z));
        const float fr = above.eval(wo, up).x, fr_swapped = above.eval(up, wo).x;
        CHECK(fr == doctest::Approx(fr_swapped).epsilon(1e-3));
        // Refraction: wo on the side of IOR 1, wi on the side of IOR η; swapped, the viewer is
        // on η's side, seen from the mirrored frame where it is above, with 1/η.
        const glm::vec3 down(wi.x, wi.y, -std::abs(wi.z));
        const float ft = above.eval(wo, down).x;
        const float ft_swapped = below.eval(flip(down), flip(wo)).x;
        if (ft > 1e-4f) ++compared;
        CHECK(ft / 1.f == doctest::Approx(ft_swapped / (eta * eta)).epsilon(2e-3));
      }
      CHECK(compared > 25);
    }
}

TEST_CASE("dielectric: a smooth interface refracts by Snell's law, tinted, index-matched passes") {
  const float eta = 1.5f, theta_o = glm::radians(50.f);
  const RoughDielectric d(eta, 0.f, glm::vec3(0.5f, 1.f, 1.f));
  const glm::vec3 wo = direction(theta_o, 0.f);
  const auto s = d.sample(wo, 0.999f, 0.3f, 0.6f);  // above F: refraction
  REQUIRE(s);
  REQUIRE(s->wi.z < 0.f);
  const float sin_t = std::sqrt(s->wi.x * s->wi.x + s->wi.y * s->wi.y);
  CHECK(sin_t == doctest::Approx(std::sin(theta_o) / eta).epsilon(5e-3));
  CHECK(s->wi.x < 0.f);  // on the far side of the normal
  // Weight tint / η² (radiance is compressed into the denser medium; the 1 − F of f is the
  // probability of choosing refraction), to within the smoothed distribution's shadowing.
  CHECK(s->weight.y == doctest::Approx(1.f / (eta * eta)).epsilon(1e-3));
  CHECK(s->weight.x == doctest::Approx(0.5f * s->weight.y).epsilon(1e-4));
  // Index-matched: straight through, all of it, whatever the roughness.
  const RoughDielectric matched(1.f, 0.7f, glm::vec3(1.f));
  CHECK(matched.index_matched());
  const auto m = matched.sample(wo, 0.1f, 0.3f, 0.6f);
  REQUIRE(m);
  CHECK(m->wi == -wo);
  CHECK(m->weight == glm::vec3(1.f));
  CHECK(matched.eval(wo, -wo) == glm::vec3(0.f));
}

TEST_CASE("dispersion: the IOR per wavelength is the KHR_materials_dispersion formula") {
  // n(λ) = max(n_d + (n_d − 1) / V_d · (523655 / λ² − 1.5168), 1), V_d = 20 / dispersion.
  const float nd = 1.5f, dispersion = 1.f, vd = 20.f / dispersion;
  for (float lambda : {465.f, 532.f, 587.6f, 630.f}) {
    INFO("λ " << lambda);
    const float n = nd + (nd - 1.f) / vd * (523655.f / (lambda * lambda) - 1.5168f);
    CHECK(dispersive_ior(nd, dispersion, lambda) == doctest::Approx(n).epsilon(1e-6));
  }
  CHECK(dispersive_ior(nd, dispersion, 587.6f) == doctest::Approx(nd).epsilon(1e-4));
  // The Abbe number: (n_d − 1) / (n_F − n_C) = V_d.
  const float nf = dispersive_ior(nd, dispersion, 486.1f), nc = dispersive_ior(nd, dispersion, 656.3f);
  CHECK((nd - 1.f) / (nf - nc) == doctest::Approx(vd).epsilon(2e-3));
  // Red bends least, blue most; no dispersion, one IOR; never below 1.
  CHECK(dispersive_ior(nd, 1.f, channel_wavelength[0]) < dispersive_ior(nd, 1.f, channel_wavelength[1]));
  CHECK(dispersive_ior(nd, 1.f, channel_wavelength[1]) < dispersive_ior(nd, 1.f, channel_wavelength[2]));
  CHECK(dispersive_ior(nd, 0.f, 400.f) == nd);
  CHECK(dispersive_ior(1.01f, 1e6f, 700.f) == 1.f);
}
