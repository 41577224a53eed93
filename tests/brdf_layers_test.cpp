// The layers over the glTF BRDF (KHR_materials_clearcoat's coat, KHR_materials_sheen's sheen):
// sampling follows the pdf (χ², as tests/brdf_test.cpp), sample weights are eval · |cos| / pdf,
// the sheen is reciprocal, the white furnace returns at most what it receives (and all of it where
// the model loses nothing), the sheen's albedo table is the lobe's albedo, and materials without
// the layers are exactly the base BRDF.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>
#include <sstream>
#include <vector>

#include "brdf_check.h"
#include "dacrt/materials/gltf_brdf.h"
#include "dacrt/materials/sampling.h"
#include "dacrt/materials/sheen.h"

using namespace dacrt;
using dacrt::test::brdf_albedo;
using dacrt::test::brdf_chi2_p_value;
using dacrt::test::direction;

namespace {

struct Layered {
  BrdfParams params;
  float theta_o;
  std::string label() const {
    std::ostringstream s;
    s << "metallic " << params.metallic << ", roughness " << params.roughness << ", clearcoat "
      << params.clearcoat << " (roughness " << params.clearcoat_roughness << ", normal "
      << params.clearcoat_normal.x << " " << params.clearcoat_normal.y << " "
      << params.clearcoat_normal.z << "), sheen " << params.sheen_color.x << " "
      << params.sheen_color.y << " " << params.sheen_color.z << " (roughness "
      << params.sheen_roughness << "), transmission " << params.transmission << ", θo "
      << glm::degrees(theta_o) << "°";
    return s.str();
  }
};

BrdfParams base(float metallic, float roughness) {
  BrdfParams p;
  p.base_color = {0.8f, 0.5f, 0.2f};
  p.metallic = metallic;
  p.roughness = roughness;
  return p;
}

std::vector<Layered> configs() {
  std::vector<Layered> c;
  const glm::vec3 tilted = glm::normalize(glm::vec3(0.3f, -0.2f, 1.f));
  for (float coat : {0.5f, 1.f})
    for (float coat_roughness : {0.25f, 0.6f})  // (α ≥ 0.06: the grid resolves the lobe)
      for (float theta : {10.f, 60.f, 85.f}) {
        BrdfParams p = base(0.f, 0.5f);
        p.clearcoat = coat, p.clearcoat_roughness = coat_roughness;
        c.push_back({p, glm::radians(theta)});
      }
  for (float theta : {20.f, 70.f}) {
    BrdfParams p = base(1.f, 0.3f);
    p.clearcoat = 1.f, p.clearcoat_roughness = 0.3f, p.clearcoat_normal = tilted;
    c.push_back({p, glm::radians(theta)});
  }
  for (float sheen_roughness : {0.f, 0.3f, 1.f})
    for (float theta : {10.f, 60.f, 85.f}) {
      BrdfParams p = base(0.f, 0.5f);
      p.sheen_color = {1.f, 0.6f, 0.3f}, p.sheen_roughness = sheen_roughness;
      c.push_back({p, glm::radians(theta)});
    }
  // Both, over a Lambert base (specular 0) and over a thin transmitting sheet.
  BrdfParams both = base(0.f, 0.7f);
  both.specular = 0.f;
  both.clearcoat = 0.8f, both.clearcoat_roughness = 0.2f;
  both.sheen_color = glm::vec3(0.5f), both.sheen_roughness = 0.5f;
  c.push_back({both, glm::radians(40.f)});
  both.specular = 1.f, both.transmission = 1.f;
  c.push_back({both, glm::radians(40.f)});
  return c;
}

}  // namespace

TEST_CASE("layered BRDF sampling follows its pdf (χ²), weights are eval · |cos| / pdf") {
  const auto all = configs();
  const double level = 1.0 - std::pow(1.0 - 0.01, 1.0 / double(all.size()));
  Pcg32 rng(7);
  for (size_t k = 0; k < all.size(); ++k) {
    const Layered& c = all[k];
    INFO(c.label());
    const GltfBrdf brdf(c.params);
    REQUIRE(brdf.layered());
    CHECK_FALSE(brdf.lambertian());
    const glm::vec3 wo = direction(c.theta_o, 0.3f);
    CHECK(brdf_chi2_p_value(brdf, brdf, wo, 3000 + k, 400000, 64) > level);
    dacrt::test::check_sample_weights(brdf, wo, rng);
  }
}

TEST_CASE("the χ² test notices a coat or sheen pdf that is slightly off") {
  const glm::vec3 wo = direction(glm::radians(45.f), 0.3f);
  BrdfParams p = base(0.f, 0.5f);
  p.clearcoat = 1.f, p.clearcoat_roughness = 0.3f;
  const GltfBrdf coat_model(p);
  p.clearcoat_roughness = 0.27f;
  CHECK(brdf_chi2_p_value(GltfBrdf(p), coat_model, wo, 98, 400000) < 1e-6);
}

TEST_CASE("a sheen is reciprocal, layered BRDFs are zero below the surface without transmission") {
  // (The coat is not reciprocal: the extension takes its Fresnel at the view direction only.)
  Pcg32 rng(9);
  for (Layered c : configs()) {
    if (c.params.transmission > 0.f) continue;
    c.params.clearcoat = 0.f;
    INFO(c.label());
    dacrt::test::check_reciprocal_reflection(GltfBrdf(c.params), rng, 1e-3f);
  }
}

TEST_CASE("clearcoat: the white furnace") {
  for (float coat_roughness : {0.f, 0.3f, 0.7f, 1.f})
    for (float theta : {0.f, 30.f, 60.f, 80.f, 89.f}) {
      const glm::vec3 wo = direction(glm::radians(theta), 0.f);
      // Over white Lambert (specular 0) and over a white rough metal: at most what arrives.
      for (float metallic : {0.f, 1.f}) {
        BrdfParams p;
        p.base_color = glm::vec3(1.f), p.metallic = metallic, p.roughness = 0.5f;
        p.specular = 0.f, p.clearcoat = 1.f, p.clearcoat_roughness = coat_roughness;
        const auto [mean, error] = brdf_albedo(GltfBrdf(p), wo, 41);
        INFO("metallic " << metallic << ", coat roughness " << coat_roughness << ", θo " << theta
                         << ": " << mean.x << " ± " << error.x);
        CHECK(mean.x <= 1.0 + 4.0 * error.x + 1e-6);
      }
    }
  // A smooth coat over a smooth white metal loses nothing: the coat reflects F(θo), the metal
  // the rest (1 − F) of what the coat lets through, at the same angle.
  for (float theta : {0.f, 45.f, 80.f}) {
    BrdfParams p;
    p.base_color = glm::vec3(1.f), p.metallic = 1.f, p.roughness = 0.f;
    p.clearcoat = 1.f, p.clearcoat_roughness = 0.f;
    const auto [mean, error] = brdf_albedo(GltfBrdf(p), direction(glm::radians(theta), 0.f), 43);
    INFO("θo " << theta << ": " << mean.x);
    CHECK(mean.x == doctest::Approx(1.0).epsilon(2e-3));
  }
}

TEST_CASE("sheen: the white furnace") {
  for (float sheen_roughness : {0.f, 0.3f, 0.7f, 1.f})
    for (float theta : {0.f, 30.f, 60.f, 80.f, 89.f}) {
      BrdfParams p;
      p.base_color = glm::vec3(1.f), p.metallic = 0.f, p.specular = 0.f;
      p.sheen_color = glm::vec3(1.f), p.sheen_roughness = sheen_roughness;
      const auto [mean, error] = brdf_albedo(GltfBrdf(p), direction(glm::radians(theta), 0.f), 47);
      INFO("sheen roughness " << sheen_roughness << ", θo " << theta << ": " << mean.x << " ± "
                              << error.x);
      CHECK(mean.x <= 1.0 + 4.0 * error.x + 2e-3);  // (2e-3: the table's interpolation)
    }
  // A black base: the sheen alone returns its albedo E, the table's value (where E ≤ 1 at every
  // angle, from roughness 0.5 on; below, the lobe is divided by E where E > 1).
  for (float sheen_roughness : {0.5f, 0.7f, 1.f})
    for (float theta : {0.f, 45.f, 80.f}) {
      BrdfParams p;
      p.base_color = glm::vec3(0.f), p.metallic = 0.f, p.specular = 0.f;
      p.sheen_color = glm::vec3(1.f), p.sheen_roughness = sheen_roughness;
      const float mu = std::cos(glm::radians(theta));
      const auto [mean, error] = brdf_albedo(GltfBrdf(p), direction(glm::radians(theta), 0.f), 53);
      INFO("sheen roughness " << sheen_roughness << ", θo " << theta << ": " << mean.x << " ± "
                              << error.x << ", table " << sheen_albedo(mu, sheen_roughness));
      CHECK(std::abs(mean.x - sheen_albedo(mu, sheen_roughness)) <= 4.0 * error.x + 2e-3);
    }
}

TEST_CASE("sheen: the albedo table interpolates the lobe's albedo") {
  for (float r : {0.f, 0.05f, 0.2f, 0.5f, 0.77f, 1.f})
    for (float mu : {0.f, 0.003f, 0.05f, 0.3f, 0.5f, 0.91f, 1.f}) {
      const float e = sheen_albedo_integral(mu, r), table = sheen_albedo(mu, r);
      INFO("roughness " << r << ", μ " << mu << ": " << e << ", table " << table);
      CHECK(e >= 0.f);
      // (Within 2 % where E > 1, smooth and grazing, where it changes fastest.)
      CHECK(std::abs(table - e) <= (e > 1.f ? 0.02f : 0.01f) * e + 1e-3f);
    }
}

TEST_CASE("a clearcoat or sheen of 0 leaves the base BRDF exactly") {
  BrdfParams p = base(0.3f, 0.4f);
  p.clearcoat_roughness = 0.5f, p.sheen_roughness = 0.5f;  // without their factors: nothing
  const GltfBrdf plain(base(0.3f, 0.4f)), zero(p);
  CHECK_FALSE(zero.layered());
  BrdfParams lambert = base(0.f, 0.4f);
  lambert.specular = 0.f;
  CHECK(GltfBrdf(lambert).lambertian());
  lambert.clearcoat = 0.1f;
  CHECK_FALSE(GltfBrdf(lambert).lambertian());
  lambert.clearcoat = 0.f, lambert.sheen_color = glm::vec3(0.f, 0.f, 0.1f);
  CHECK_FALSE(GltfBrdf(lambert).lambertian());
  Pcg32 rng(11);
  for (int k = 0; k < 1000; ++k) {
    const glm::vec3 wo = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
    const glm::vec3 wi = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
    CHECK(plain.eval(wo, wi) == zero.eval(wo, wi));
    CHECK(plain.pdf(wo, wi) == zero.pdf(wo, wi));
  }
}

TEST_CASE("a coat's normal is taken normalised, the default (0, 0, 1) as it is") {
  // (MaterialLayers skips the normalisation of the default normal: the same vector.)
  auto coated = [](glm::vec3 n) {
    BrdfParams p = base(0.2f, 0.5f);
    p.clearcoat = 1.f, p.clearcoat_roughness = 0.3f, p.clearcoat_normal = n;
    return GltfBrdf(p);
  };
  const GltfBrdf up = coated({0.f, 0.f, 1.f}), long_up = coated({0.f, 0.f, 4.f});
  const GltfBrdf tilted = coated({3.f, 0.f, 4.f}), unit = coated({0.6f, 0.f, 0.8f});
  Pcg32 rng(51);
  int differ = 0, far = 0;
  for (int k = 0; k < 1000; ++k) {
    const glm::vec3 wo = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
    const glm::vec3 wi = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
    differ += up.eval(wo, wi) != long_up.eval(wo, wi) || up.pdf(wo, wi) != long_up.pdf(wo, wi);
    const glm::vec3 a = tilted.eval(wo, wi), b = unit.eval(wo, wi);
    far += glm::length(a - b) > 1e-4f * (1.f + glm::length(b)) ||
           std::abs(tilted.pdf(wo, wi) - unit.pdf(wo, wi)) > 1e-4f * (1.f + unit.pdf(wo, wi));
  }
  CHECK(differ == 0);
  CHECK(far == 0);
}
