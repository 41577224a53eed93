// KHR_materials_anisotropy's lobe (materials/anisotropy.h) in the glTF BRDF: the anisotropic GGX
// is the isotropic one when both α agree, D and the visible normals are normalised, strength 0
// is the isotropic BRDF exactly, a rotation of the direction is a rotation of the lobe, sampling
// follows the pdf (χ², as tests/brdf_test.cpp), weights are eval · |cos| / pdf, eval is
// reciprocal, the white furnace returns at most what it receives (and what the model's own
// quadrature says, so sampling loses nothing), and the highlight stretches along the direction.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>
#include <sstream>
#include <vector>

#include "brdf_check.h"
#include "dacrt/materials/anisotropy.h"
#include "dacrt/materials/ggx.h"
#include "dacrt/materials/gltf_brdf.h"
#include "dacrt/materials/sampling.h"

using namespace dacrt;
using dacrt::test::brdf_albedo;
using dacrt::test::brdf_chi2_p_value;
using dacrt::test::direction;

namespace {

BrdfParams anisotropic(float metallic, float roughness, float strength, float rotation) {
  BrdfParams p;
  p.base_color = {0.8f, 0.5f, 0.2f};
  p.metallic = metallic;
  p.roughness = roughness;
  p.anisotropy = strength;
  p.anisotropy_direction = {std::cos(rotation), std::sin(rotation)};
  return p;
}

struct Config {
  BrdfParams params;
  float theta_o;
  std::string label() const {
    std::ostringstream s;
    s << "metallic " << params.metallic << ", roughness " << params.roughness << ", anisotropy "
      << params.anisotropy << " towards (" << params.anisotropy_direction.x << ", "
      << params.anisotropy_direction.y << "), transmission " << params.transmission
      << ", clearcoat " << params.clearcoat << ", sheen " << params.sheen_color.x
      << ", iridescence " << params.iridescence << ", θo "
      << glm::degrees(theta_o) << "°";
    return s.str();
  }
};

std::vector<Config> configs() {
  std::vector<Config> c;
  for (float roughness : {0.3f, 0.6f})
    for (float strength : {0.5f, 1.f})
      for (float rotation : {0.f, 1.f})
        for (float theta : {20.f, 70.f})
          c.push_back({anisotropic(1.f, roughness, strength, rotation), glm::radians(theta)});
  c.push_back({anisotropic(0.f, 0.4f, 0.8f, 0.5f), glm::radians(45.f)});  // dielectric
  c.push_back({anisotropic(0.5f, 0.4f, 0.8f, -2.f), glm::radians(60.f)});
  BrdfParams sheet = anisotropic(0.f, 0.4f, 0.8f, 0.5f);  // thin-walled transmission
  sheet.transmission = 1.f;
  c.push_back({sheet, glm::radians(30.f)});
  BrdfParams coated = anisotropic(1.f, 0.3f, 0.9f, 2.f);  // the coat stays isotropic
  coated.clearcoat = 0.5f, coated.clearcoat_roughness = 0.2f;
  c.push_back({coated, glm::radians(40.f)});
  BrdfParams sheen = anisotropic(0.f, 0.5f, 1.f, 0.f);
  sheen.sheen_color = glm::vec3(0.5f), sheen.sheen_roughness = 0.4f;
  c.push_back({sheen, glm::radians(50.f)});
  // With a thin film too (KHR_materials_iridescence changes the Fresnel terms, and with them
  // the lobes' sampling weights), over a half-metal.
  BrdfParams film = anisotropic(0.5f, 0.35f, 0.9f, 1.2f);
  film.iridescence = 1.f, film.iridescence_ior = 1.8f, film.iridescence_thickness = 300.f;
  c.push_back({film, glm::radians(35.f)});
  return c;
}

// v turned by `angle` about the normal.
glm::vec3 rotated(const glm::vec3& v, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}

}  // namespace

TEST_CASE("anisotropic GGX with α_t = α_b is the isotropic GGX") {
  Pcg32 rng(1);
  for (float alpha : {0.05f, 0.3f, 1.f})
    for (int k = 0; k < 200; ++k) {
      const glm::vec3 h = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
      const glm::vec3 wo = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
      const glm::vec3 wi = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
      if (!(h.z > 1e-2f && wo.z > 1e-2f && wi.z > 1e-2f)) continue;
      INFO("α " << alpha << ", h.z " << h.z << ", wo.z " << wo.z << ", wi.z " << wi.z);
      CHECK(ggx_d_anisotropic(h, alpha, alpha) == doctest::Approx(ggx_d(h.z, alpha)).epsilon(1e-4));
      CHECK(ggx_lambda_anisotropic(wo, alpha, alpha) ==
            doctest::Approx(ggx_lambda(wo.z, alpha)).epsilon(1e-5).scale(1.0));
      CHECK(ggx_visibility_anisotropic(wo, wi, alpha, alpha) ==
            doctest::Approx(ggx_visibility(wo.z, wi.z, alpha)).epsilon(1e-4));
    }
}

TEST_CASE("anisotropic GGX: D projects to 1, visible normals to cos θo (numerical integration)") {
  // ∫ D(h) cos θh dω = 1 and ∫ G₁(wo) max(0, wo·h) D(h) dω = cos θo, by the midpoint rule over a
  // fine (θ, φ) grid of the hemisphere (the narrowest lobe, α = 0.1, spans ~100 θ steps).
  constexpr int n_theta = 4000, n_phi = 512;
  const double d_theta = glm::half_pi<double>() / n_theta, d_phi = glm::two_pi<double>() / n_phi;
  struct Alphas {
    float t, b;
  };
  for (const Alphas a : {Alphas{1.f, 0.1f}, Alphas{0.5f, 0.2f}, Alphas{0.15f, 0.6f}})
    for (float theta_o : {0.f, 50.f, 80.f}) {
      const glm::vec3 wo = direction(glm::radians(theta_o), 0.7f);
      const double g1 = 1.0 / (1.0 + ggx_lambda_anisotropic(wo, a.t, a.b));
      double projected = 0.0, visible = 0.0;
      for (int i = 0; i < n_theta; ++i) {
        const float theta = float((i + 0.5) * d_theta);
        for (int j = 0; j < n_phi; ++j) {
          const glm::vec3 h = direction(theta, float((j + 0.5) * d_phi));
          const double d = ggx_d_anisotropic(h, a.t, a.b) * std::sin(theta) * d_theta * d_phi;
          projected += d * h.z;
          visible += d * g1 * std::max(0.f, glm::dot(wo, h));
        }
      }
      INFO("α_t " << a.t << ", α_b " << a.b << ", θo " << theta_o);
      CHECK(projected == doctest::Approx(1.0).epsilon(2e-3));
      CHECK(visible == doctest::Approx(wo.z).epsilon(2e-3));
    }
}

TEST_CASE("anisotropy 0 (or roughness 1, or a Lambert base) is the isotropic BRDF exactly") {
  Pcg32 rng(2);
  for (const Config& c : configs()) {
    BrdfParams zero = c.params, none = c.params;
    zero.anisotropy = 0.f;
    none.anisotropy_direction = {1.f, 0.f};
    none.anisotropy = 0.f;
    const GltfBrdf a(zero), b(none);
    CHECK_FALSE(a.anisotropic());
    const glm::vec3 wo = direction(c.theta_o, 0.4f);
    for (int k = 0; k < 200; ++k) {
      const glm::vec3 wi = direction(std::acos(rng.uniform()) * 1.2f, 6.3f * rng.uniform());
      CHECK(a.eval(wo, wi) == b.eval(wo, wi));
      CHECK(a.pdf(wo, wi) == b.pdf(wo, wi));
      const float u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
      const auto sa = a.sample(wo, u0, u1, u2), sb = b.sample(wo, u0, u1, u2);
      REQUIRE(bool(sa) == bool(sb));
      if (sa) CHECK((sa->wi == sb->wi && sa->weight == sb->weight && sa->pdf == sb->pdf));
    }
  }
  CHECK_FALSE(GltfBrdf(anisotropic(1.f, 1.f, 1.f, 0.3f)).anisotropic());  // α_t = α_b = 1
  BrdfParams lambert = anisotropic(0.f, 0.5f, 1.f, 0.f);
  lambert.specular = 0.f;
  CHECK(GltfBrdf(lambert).lambertian());
  CHECK_FALSE(GltfBrdf(lambert).anisotropic());
  CHECK(GltfBrdf(anisotropic(1.f, 0.5f, 0.1f, 0.f)).anisotropic());
}

TEST_CASE("anisotropy: turning the direction by φ turns the lobe by φ") {
  // f_φ(wo, wi) = f_0(R(−φ) wo, R(−φ) wi) (reflection and transmission), the same for pdf, and
  // a metal's sampling with the same numbers gives the turned direction (the diffuse lobe, which
  // does not turn, is sampled alike); t and −t are the same lobe.
  Pcg32 rng(4);
  for (float phi : {0.4f, 1.5707964f, -2.5f}) {
    BrdfParams turned = anisotropic(0.5f, 0.4f, 0.9f, phi);
    turned.transmission = 0.5f;
    BrdfParams base = turned, opposite = turned;
    base.anisotropy_direction = {1.f, 0.f};
    opposite.anisotropy_direction = -turned.anisotropy_direction;
    const GltfBrdf f(turned), f0(base), f_opposite(opposite);
    BrdfParams metal = turned, metal0 = base;
    metal.metallic = metal0.metallic = 1.f;
    const GltfBrdf m(metal), m0(metal0);
    for (int k = 0; k < 300; ++k) {
      const glm::vec3 wo = direction(std::acos(rng.uniform()), 6.3f * rng.uniform());
      const glm::vec3 wi = direction(std::acos(2.f * rng.uniform() - 1.f), 6.3f * rng.uniform());
      if (!(wo.z > 1e-2f) || std::abs(wi.z) < 1e-2f) continue;
      INFO("φ " << phi << ", wo " << wo.x << " " << wo.y << " " << wo.z << ", wi " << wi.x << " "
                << wi.y << " " << wi.z);
      const glm::vec3 e = f.eval(wo, wi), e0 = f0.eval(rotated(wo, -phi), rotated(wi, -phi));
      for (int ch = 0; ch < 3; ++ch) {
        CHECK(e[ch] == doctest::Approx(e0[ch]).epsilon(1e-3).scale(1e-6));
        CHECK(f_opposite.eval(wo, wi)[ch] == doctest::Approx(e[ch]).epsilon(1e-4).scale(1e-6));
      }
      CHECK(f.pdf(wo, wi) ==
            doctest::Approx(f0.pdf(rotated(wo, -phi), rotated(wi, -phi))).epsilon(1e-3));
      const float u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
      const auto s = m.sample(wo, u0, u1, u2), s0 = m0.sample(rotated(wo, -phi), u0, u1, u2);
      REQUIRE(bool(s) == bool(s0));
      if (s) {
        const glm::vec3 back = rotated(s0->wi, phi);
        CHECK(glm::length(s->wi - back) < 1e-3f);
      }
    }
  }
}

TEST_CASE("anisotropic BRDF sampling follows its pdf (χ²), weights are eval · |cos| / pdf") {
  const auto all = configs();
  const double level = 1.0 - std::pow(1.0 - 0.01, 1.0 / double(all.size()));
  Pcg32 rng(6);
  for (size_t k = 0; k < all.size(); ++k) {
    const Config& c = all[k];
    INFO(c.label());
    const GltfBrdf brdf(c.params);
    REQUIRE(brdf.anisotropic());
    const glm::vec3 wo = direction(c.theta_o, 0.3f);
    CHECK(brdf_chi2_p_value(brdf, brdf, wo, 5000 + k, 400000, 32) > level);
    dacrt::test::check_sample_weights(brdf, wo, rng);
  }
}

TEST_CASE("the χ² test notices an anisotropic pdf turned or stretched slightly") {
  const glm::vec3 wo = direction(glm::radians(45.f), 0.3f);
  const GltfBrdf model(anisotropic(1.f, 0.4f, 0.8f, 0.f));
  CHECK(brdf_chi2_p_value(GltfBrdf(anisotropic(1.f, 0.4f, 0.8f, 0.15f)), model, wo, 97, 400000) <
        1e-6);
  CHECK(brdf_chi2_p_value(GltfBrdf(anisotropic(1.f, 0.4f, 0.7f, 0.f)), model, wo, 96, 400000) <
        1e-6);
}

TEST_CASE("anisotropic BRDF is reciprocal and zero below the surface without transmission") {
  Pcg32 rng(8);
  for (Config c : configs()) {
    if (c.params.transmission > 0.f) continue;
    c.params.clearcoat = 0.f;  // (the coat's Fresnel is at the view only: not reciprocal)
    INFO(c.label());
    dacrt::test::check_reciprocal_reflection(GltfBrdf(c.params), rng, 1e-3f);
  }
}

TEST_CASE("anisotropy: the white furnace") {
  // A white metal returns at most what it receives, whatever the strength and direction.
  for (float roughness : {0.f, 0.3f, 0.7f})
    for (float strength : {0.3f, 0.7f, 1.f})
      for (float rotation : {0.f, 1.f})
        for (float theta : {0.f, 45.f, 80.f}) {
          BrdfParams p = anisotropic(1.f, roughness, strength, rotation);
          p.base_color = glm::vec3(1.f);
          const auto [mean, error] = brdf_albedo(GltfBrdf(p), direction(glm::radians(theta), 0.f), 43);
          INFO("roughness " << roughness << ", strength " << strength << ", rotation " << rotation
                            << ", θo " << theta << ": " << mean.x << " ± " << error.x);
          CHECK(mean.x <= 1.0 + 4.0 * error.x + 1e-6);
          // A slightly anisotropic smooth metal (α_t = 0.09) is nearly a mirror: it loses
          // little to single scattering.
          if (roughness == 0.f && strength == 0.3f && theta < 60.f) CHECK(mean.x > 0.99);
        }
  // What importance sampling returns is the model's albedo: the same as a midpoint quadrature of
  // ∫ f cos dωi (the energy single-scattering GGX loses, and no more).
  constexpr int n_theta = 1000, n_phi = 2000;
  const double d_theta = glm::half_pi<double>() / n_theta, d_phi = glm::two_pi<double>() / n_phi;
  for (float roughness : {0.5f, 0.8f})
    for (float strength : {0.5f, 1.f})
      for (float theta_o : {30.f, 70.f}) {
        BrdfParams p = anisotropic(1.f, roughness, strength, 0.6f);
        p.base_color = glm::vec3(1.f);
        const GltfBrdf brdf(p);
        const glm::vec3 wo = direction(glm::radians(theta_o), 0.f);
        double quadrature = 0.0;
        for (int i = 0; i < n_theta; ++i) {
          const float theta = float((i + 0.5) * d_theta);
          for (int j = 0; j < n_phi; ++j) {
            const glm::vec3 wi = direction(theta, float((j + 0.5) * d_phi));
            quadrature += brdf.eval(wo, wi).x * wi.z * std::sin(theta) * d_theta * d_phi;
          }
        }
        const auto [mean, error] = brdf_albedo(brdf, wo, 47);
        INFO("roughness " << roughness << ", strength " << strength << ", θo " << theta_o << ": "
                          << mean.x << " ± " << error.x << ", quadrature " << quadrature);
        CHECK(std::abs(mean.x - quadrature) <= 4.0 * error.x + 1e-3);
        CHECK(quadrature < 1.0);
      }
}

TEST_CASE("anisotropy: the highlight stretches along the direction, not across it") {
  // Seen from the normal, light 20° off the mirror direction along t is reflected far more than
  // light 20° off along b; turning the direction by 90° swaps them.
  const glm::vec3 wo(0.f, 0.f, 1.f);
  const float off = glm::radians(20.f);
  const glm::vec3 along_x = direction(off, 0.f), along_y = direction(off, glm::half_pi<float>());
  const GltfBrdf x(anisotropic(1.f, 0.3f, 1.f, 0.f));
  const GltfBrdf y(anisotropic(1.f, 0.3f, 1.f, glm::half_pi<float>()));
  const GltfBrdf iso(anisotropic(1.f, 0.3f, 0.f, 0.f));
  CHECK(x.eval(wo, along_x).x > 10.f * x.eval(wo, along_y).x);
  CHECK(y.eval(wo, along_y).x > 10.f * y.eval(wo, along_x).x);
  CHECK(iso.eval(wo, along_x).x == doctest::Approx(iso.eval(wo, along_y).x).epsilon(1e-5));
  // Along t the lobe reaches much further than the material's own (isotropic) roughness.
  const glm::vec3 far_x = direction(2.f * off, 0.f);
  CHECK(x.eval(wo, far_x).x > 10.f * iso.eval(wo, far_x).x);
  // So does the thin-walled transmission lobe, the reflection's mirror image below.
  BrdfParams sheet = anisotropic(0.f, 0.3f, 1.f, 0.f);
  sheet.transmission = 1.f;
  const GltfBrdf through(sheet);
  const glm::vec3 below_x(-along_x.x, -along_x.y, -along_x.z), below_y(-along_y.x, -along_y.y,
                                                                        -along_y.z);
  CHECK(through.eval(wo, below_x).x > 10.f * through.eval(wo, below_y).x);
}

TEST_CASE("anisotropy: a white metal's lobe is D · V with α_t = mix(α, 1, strength²), α_b = α") {
  // (A white metal's Fresnel is 1.)
  Pcg32 rng(10);
  for (float roughness : {0.2f, 0.6f})
    for (float strength : {0.4f, 1.f}) {
      BrdfParams p = anisotropic(1.f, roughness, strength, 0.7f);
      p.base_color = glm::vec3(1.f);
      const GltfBrdf brdf(p);
      const float alpha = roughness * roughness;
      Anisotropy a;
      a.alpha_t = alpha * (1.f - strength * strength) + strength * strength;
      a.alpha_b = alpha;
      a.t = p.anisotropy_direction;
      for (int k = 0; k < 100; ++k) {
        const glm::vec3 wo = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
        const glm::vec3 wi = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
        if (!(wo.z > 1e-2f && wi.z > 1e-2f)) continue;
        const glm::vec3 h = glm::normalize(wo + wi);
        const float expected =
            ggx_d_anisotropic(a.to_local(h), a.alpha_t, a.alpha_b) *
            ggx_visibility_anisotropic(a.to_local(wo), a.to_local(wi), a.alpha_t, a.alpha_b);
        CHECK(brdf.eval(wo, wi).x == doctest::Approx(expected).epsilon(1e-4));
      }
    }
}
