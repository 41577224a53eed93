// The material extensions as their specifications write them, and as they combine:
// - KHR_materials_clearcoat: the base under the coat, the coat lobe and the emission under it are
//   weighted by 1 − clearcoat · F(V·N_c), written out here from the extension's fresnel_coat;
// - KHR_materials_sheen: the Charlie lobe with the Charlie visibility and the albedo scaling
//   min(1 − c E(V·N), 1 − c E(L·N)), written out here from the extension's implementation notes,
//   and E against values integrated here in double;
// - a volume (KHR_materials_volume) carries every layer the opaque BRDF has: clearcoat, sheen,
//   specular factor and colour, iridescence and anisotropy each change glass, sampling follows
//   the pdf (χ²), and the white furnace stays at or below 1;
// - a glass whose metallic comes from its texture is a volume;
// - KHR_materials_unlit is seen by camera rays and casts no light.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>
#include <sstream>
#include <vector>

#include "brdf_check.h"
#include "chi2.h"
#include "dacrt/integrators/lights.h"
#include "dacrt/integrators/media.h"
#include "dacrt/io/gltf.h"
#include "dacrt/materials/bsdf.h"
#include "dacrt/materials/ggx.h"
#include "dacrt/materials/sheen.h"
#include "dacrt/scene/surface.h"
#include "render_check.h"
#include "tests/gltf_check.h"
#include "tests/temp_dir.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

// The extension's Schlick Fresnel of the coat: F0 = 0.04, F90 = 1.
double coat_f(double cos_theta) {
  return 0.04 + 0.96 * std::pow(1.0 - std::clamp(cos_theta, 0.0, 1.0), 5.0);
}

// KHR_materials_sheen's implementation notes: the Charlie distribution (α = sheenRoughness²) and
// the Charlie visibility, in double.
double charlie_d(double cos_h, double alpha) {
  const double sin2 = std::max(0.0, 1.0 - cos_h * cos_h);
  return (2.0 + 1.0 / alpha) * std::pow(sin2, 0.5 / alpha) / (2.0 * glm::pi<double>());
}
double charlie_l(double x, double alpha) {
  const double t = (1.0 - alpha) * (1.0 - alpha);
  const double a = 21.5473 + (25.3245 - 21.5473) * t, b = 3.82987 + (3.32435 - 3.82987) * t;
  const double c = 0.19823 + (0.16801 - 0.19823) * t, d = -1.97760 + (-1.27393 + 1.97760) * t;
  const double e = -4.32054 + (-4.85967 + 4.32054) * t;
  return a / (1.0 + b * std::pow(x, c)) + d * x + e;
}
double charlie_lambda(double cos_theta, double alpha) {
  return std::abs(cos_theta) < 0.5
             ? std::exp(charlie_l(std::abs(cos_theta), alpha))
             : std::exp(2.0 * charlie_l(0.5, alpha) - charlie_l(1.0 - std::abs(cos_theta), alpha));
}
double charlie_v(double cos_o, double cos_i, double alpha) {
  return 1.0 /
         ((1.0 + charlie_lambda(cos_o, alpha) + charlie_lambda(cos_i, alpha)) * 4.0 * cos_o * cos_i);
}
// E(μ) = ∫ D V cos θi dωi, midpoint rule in (cos θi, φ), finer than the library's table.
double charlie_albedo(double mu, double roughness) {
  const double alpha = std::max(0.01, roughness * roughness);
  const glm::dvec3 wo(std::sqrt(1.0 - mu * mu), 0.0, mu);
  const int n = 400, m = 200;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double ci = (i + 0.5) / n, si = std::sqrt(1.0 - ci * ci);
    for (int j = 0; j < m; ++j) {
      const double phi = glm::pi<double>() * (j + 0.5) / m;
      const glm::dvec3 h = glm::normalize(wo + glm::dvec3(si * std::cos(phi), si * std::sin(phi), ci));
      sum += charlie_d(h.z, alpha) * charlie_v(mu, ci, alpha) * ci;
    }
  }
  return sum / n * glm::pi<double>() / m * 2.0;
}

glm::vec3 dir(float theta_deg, float phi) {
  return direction(glm::radians(theta_deg), phi);
}

// Plain smooth-ish glass, and the same with one layer or lobe added.
BrdfParams glass() {
  BrdfParams p;
  p.base_color = glm::vec3(1.f), p.metallic = 0.f, p.roughness = 0.3f, p.transmission = 1.f;
  return p;
}
struct Variant {
  const char* name;
  BrdfParams params;
};
std::vector<Variant> layered_glasses() {
  std::vector<Variant> v;
  BrdfParams p = glass();
  p.clearcoat = 1.f, p.clearcoat_roughness = 0.3f;  // (α 0.09: the χ² grid resolves it)
  v.push_back({"clearcoat", p});
  p = glass(), p.specular = 0.f;
  v.push_back({"specularFactor 0", p});
  p = glass(), p.specular_color = glm::vec3(1.f, 0.2f, 0.2f);
  v.push_back({"specularColorFactor", p});
  p = glass(), p.iridescence = 1.f, p.iridescence_thickness = 400.f;
  v.push_back({"iridescence", p});
  p = glass(), p.sheen_color = glm::vec3(1.f, 0.8f, 0.6f), p.sheen_roughness = 0.5f;
  v.push_back({"sheen", p});
  p = glass(), p.anisotropy = 0.8f, p.anisotropy_direction = {0.6f, 0.8f};
  v.push_back({"anisotropy", p});
  return v;
}

// Light arriving along wo leaves with the adjoint BSDF (η² f for refraction, f radiance's): its
// albedo is the mean sample weight times that η² (as tests/dielectric_test.cpp's furnace).
std::pair<double, double> furnace(const Bsdf& b, const glm::vec3& wo, float eta, uint64_t seed) {
  Pcg32 rng(seed);
  const int n = 50000;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    const auto s = b.sample(wo, rng.uniform(), rng.uniform(), rng.uniform());
    const double w = s ? double(s->weight.x + s->weight.y + s->weight.z) / 3.0 *
                             (s->wi.z < 0.f ? eta * eta : 1.f)
                       : 0.0;
    sum += w, sum2 += w * w;
  }
  const double mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

}  // namespace

TEST_CASE("coat: the base, the coat lobe and the emission under it are weighted by 1 − c F(V·N_c)") {
  // A white coat of roughness 0.3 over Lambert 0.8 (specular 0): the extension's
  //   f = c F(V·N_c) D V + (1 − c F(V·N_c)) · 0.8 / π,
  // with F at the view direction only, also where the light grazes (75°, 85°).
  BrdfParams p;
  p.base_color = glm::vec3(0.8f), p.metallic = 0.f, p.specular = 0.f;
  p.clearcoat = 0.7f, p.clearcoat_roughness = 0.3f;
  const GltfBrdf brdf(p);
  const float alpha = 0.09f;
  for (float theta_o : {0.f, 40.f, 75.f, 85.f})
    for (float theta_i : {0.f, 30.f, 75.f, 85.f}) {
      const glm::vec3 wo = dir(theta_o, 0.3f), wi = dir(theta_i, 2.5f);
      const glm::vec3 h = glm::normalize(wo + wi);
      const double f = coat_f(wo.z);
      const double expected = 0.7 * f * ggx_d(h.z, alpha) * ggx_visibility(wo.z, wi.z, alpha) +
                              (1.0 - 0.7 * f) * 0.8 / glm::pi<double>();
      INFO("θo " << theta_o << "°, θi " << theta_i << "°");
      CHECK(brdf.eval(wo, wi).x == doctest::Approx(expected).epsilon(1e-5));
    }

  // The emission under a coat of 0.6 (no normal map: the interpolated normal), seen at angles.
  TempDir tmp("coat-emission");
  GltfWriter w = quad_file({{"emissiveFactor", {1, 0.5, 0.25}},
                            {"extensions", {{"KHR_materials_clearcoat", {{"clearcoatFactor", 0.6}}}}}});
  const Scene scene = load_gltf(w.write_gltf(tmp / "coat.gltf"));
  const QuadPoint q = quad_point(scene, 0.3f, 0.6f);
  for (float theta : {0.f, 45.f, 70.f, 85.f}) {
    const glm::vec3 towards = dir(theta, 1.f);
    const glm::vec3 e = emission_at(scene, q.tri, q.u, q.v, towards);
    const double weight = 1.0 - 0.6 * coat_f(towards.z);
    INFO("seen at " << theta << "°");
    CHECK(e.x == doctest::Approx(weight).epsilon(1e-5));
    CHECK(e.z == doctest::Approx(0.25 * weight).epsilon(1e-5));
  }
}

TEST_CASE("sheen: the Charlie lobe and visibility with the specification's albedo scaling") {
  // A sheen over Lambert 0.5 (specular 0), where its albedo E stays below 1 (sheenRoughness ≥ 0.3
  // or away from grazing): f = sheenColor D V + min(1 − c E(V·N), 1 − c E(L·N)) · 0.5 / π.
  for (float roughness : {0.3f, 0.6f, 1.f}) {
    BrdfParams p;
    p.base_color = glm::vec3(0.5f), p.metallic = 0.f, p.specular = 0.f;
    p.sheen_color = glm::vec3(0.9f, 0.6f, 0.3f), p.sheen_roughness = roughness;
    const GltfBrdf brdf(p);
    const double alpha = double(roughness) * roughness;
    for (float theta_o : {0.f, 50.f, 80.f})
      for (float theta_i : {10.f, 60.f, 85.f}) {
        const glm::vec3 wo = dir(theta_o, 0.f), wi = dir(theta_i, 2.f);
        const glm::vec3 h = glm::normalize(wo + wi);
        const double e_o = sheen_albedo(wo.z, roughness), e_i = sheen_albedo(wi.z, roughness);
        const double scaling = std::min(1.0 - 0.9 * e_o, 1.0 - 0.9 * e_i);
        const double expected =
            0.9 * charlie_d(h.z, alpha) * charlie_v(wo.z, wi.z, alpha) + scaling * 0.5 / glm::pi<double>();
        INFO("sheen roughness " << roughness << ", θo " << theta_o << "°, θi " << theta_i << "°");
        REQUIRE(std::max(e_o, e_i) <= 1.0);
        CHECK(brdf.eval(wo, wi).x == doctest::Approx(expected).epsilon(1e-4));
      }
  }
}

TEST_CASE("sheen: the albedo table is the Charlie lobe's E, integrated here in double") {
  // (With Ashikhmin's visibility E is 1.5x these at roughness 0.3 and 15-35 % lower at 1.)
  for (float roughness : {0.3f, 0.5f, 0.7f, 1.f})
    for (float mu : {0.05f, 0.2f, 0.5f, 0.9f}) {
      const double e = charlie_albedo(mu, roughness);
      INFO("roughness " << roughness << ", μ " << mu << ": " << e << ", table "
                        << sheen_albedo(mu, roughness));
      CHECK(sheen_albedo(mu, roughness) == doctest::Approx(e).epsilon(0.02).scale(1.0));
      CHECK(e < 1.0);
    }
}

TEST_CASE("volume: glass carries every layer: each changes it, and the layered BSDF samples its "
          "pdf (χ²) and returns at most what it receives") {
  const float eta = 1.5f;
  const Bsdf plain = Bsdf::volume(glass(), eta, true);
  const auto variants = layered_glasses();
  const double level = 1.0 - std::pow(0.99, 1.0 / double(variants.size()));
  uint64_t seed = 4800;
  for (const Variant& v : variants) {
    INFO(std::string(v.name));
    const Bsdf layered = Bsdf::volume(v.params, eta, true);
    // Different from plain glass, in reflection or refraction.
    Pcg32 rng(seed);
    double difference = 0.0;
    for (int k = 0; k < 400; ++k) {
      const glm::vec3 wo = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
      glm::vec3 wi = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
      if (k % 2) wi.z = -wi.z;
      difference += glm::length(layered.eval(wo, wi) - plain.eval(wo, wi));
    }
    CHECK(difference > 1e-3);
    for (float theta : {25.f, 70.f}) {
      const glm::vec3 wo = dir(theta, 0.4f);
      CHECK(dacrt::test::chi2_p_value(
                [&](Pcg32& r) -> std::optional<glm::vec3> {
                  const auto s = layered.sample(wo, r.uniform(), r.uniform(), r.uniform());
                  return s ? std::optional<glm::vec3>(s->wi) : std::nullopt;
                },
                [&](const glm::vec3& wi) { return layered.pdf(wo, wi); }, ++seed, 100000, 16) >
            level);
      Pcg32 r(seed);
      for (int k = 0; k < 300; ++k) {
        const auto s = layered.sample(wo, r.uniform(), r.uniform(), r.uniform());
        if (!s) continue;
        CHECK(s->pdf == doctest::Approx(layered.pdf(wo, s->wi)).epsilon(1e-3));
        const glm::vec3 expected = layered.eval(wo, s->wi) * (std::abs(s->wi.z) / s->pdf);
        for (int ch = 0; ch < 3; ++ch)
          CHECK(s->weight[ch] == doctest::Approx(expected[ch]).epsilon(1e-3));
      }
      const auto [mean, error] = furnace(layered, wo, eta, seed);
      INFO("θo " << theta << "°: albedo " << mean << " ± " << error);
      CHECK(mean <= 1.0 + 4.0 * error + 1e-6);
    }
  }
  // From inside (the back face), the layers on the outside play no part: the bare interface.
  for (const Variant& v : variants) {
    if (v.params.anisotropy > 0.f || v.params.specular != 1.f ||
        v.params.specular_color != glm::vec3(1.f))
      continue;  // (the interface's own lobes act on both sides)
    INFO(std::string(v.name) << ", from inside");
    const Bsdf inside = Bsdf::volume(v.params, 1.f / eta, false);
    const Bsdf bare = Bsdf::volume(glass(), 1.f / eta, false);
    Pcg32 rng(seed++);
    for (int k = 0; k < 100; ++k) {
      const glm::vec3 wo = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
      glm::vec3 wi = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
      if (k % 2) wi.z = -wi.z;
      CHECK(inside.eval(wo, wi) == bare.eval(wo, wi));
    }
  }
}

TEST_CASE("volume: specularFactor 0 glass refracts everything, a smooth coat reflects F(V·N)") {
  // Smooth glass with specularFactor 0 reflects nothing: head-on, all of the light goes in.
  BrdfParams p = glass();
  p.roughness = 0.f, p.specular = 0.f;
  const auto [in, in_error] = furnace(Bsdf::volume(p, 1.5f, true), dir(0.f, 0.f), 1.5f, 3);
  CHECK(in == doctest::Approx(1.0).epsilon(2e-3));
  Pcg32 rng(1);
  for (int k = 0; k < 100; ++k) {
    const auto s = Bsdf::volume(p, 1.5f, true).sample(dir(30.f, 0.f), rng.uniform(),
                                                       rng.uniform(), rng.uniform());
    if (s) CHECK(s->wi.z < 0.f);
  }
  // A smooth coat over smooth glass: at 60° the coat reflects 0.04 + 0.96 (1 − cos 60°)⁵ of it.
  p = glass();
  p.roughness = 0.f, p.clearcoat = 1.f;
  const Bsdf coated = Bsdf::volume(p, 1.5f, true);
  Pcg32 r(2);
  double reflected = 0.0;
  const int n = 200000;
  const glm::vec3 wo = dir(60.f, 0.f);
  for (int k = 0; k < n; ++k)
    if (auto s = coated.sample(wo, r.uniform(), r.uniform(), r.uniform()); s && s->wi.z > 0.f)
      reflected += s->weight.x;
  // The coat's F plus the glass's own Fresnel reflection of what the coat lets through.
  const double f_coat = coat_f(0.5), f_glass = fresnel_dielectric(0.5f, 1.5f);
  CHECK(reflected / n == doctest::Approx(f_coat + (1.0 - f_coat) * f_glass).epsilon(0.01));
}

TEST_CASE("volume: a glass whose metallic comes from its texture (factor 1) is a volume") {
  // Blender's exporter leaves metallicFactor at its default 1 and writes metallic 0 in the
  // texture's blue channel.
  TempDir tmp("textured-glass");
  GltfWriter w = quad_file({{"pbrMetallicRoughness",
                             {{"metallicRoughnessTexture", {{"index", 0}}}, {"roughnessFactor", 0}}},
                            {"extensions",
                             {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                              {"KHR_materials_volume", {{"thicknessFactor", 0.1}}}}}});
  add_texture(w, png8(1, 1, 4, {255, 255, 0, 255}), kNearest);
  const Scene scene = load_gltf(w.write_gltf(tmp / "glass.gltf"));
  const Material& m = scene.materials[0];
  CHECK(m.metallic == 1.f);
  CHECK(m.volume());
  CHECK(medium_of(m).has_value());
  CHECK(quad_surface(scene, 0.5f, 0.3f).brdf.metallic == 0.f);  // where the path enters it
  // Without the texture, metallic 1 is no volume.
  Material metal = m;
  metal.metallic_roughness_texture = TextureRef{};
  CHECK_FALSE(metal.volume());

  // Rendered: a slab 1 thick of index-matched glass that absorbs to 0.25 over a distance of 2,
  // seen head-on under a sky of 1, transmits 0.25^(1/2) = 0.5 (thin-walled, it would be 1).
  GltfWriter box;
  const std::vector<glm::vec3> corners = {{-9, -9, 0}, {9, -9, 0}, {9, 9, 0}, {-9, 9, 0},
                                          {-9, -9, 1}, {9, -9, 1}, {9, 9, 1}, {-9, 9, 1}};
  const std::vector<glm::vec2> uv(8, glm::vec2(0.5f));
  const std::vector<uint8_t> faces = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                      1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
  box.add_material({{"pbrMetallicRoughness",
                     {{"metallicRoughnessTexture", {{"index", 0}}}, {"roughnessFactor", 0}}},
                    {"extensions",
                     {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                      {"KHR_materials_ior", {{"ior", 1}}},
                      {"KHR_materials_volume",
                       {{"thicknessFactor", 1},
                        {"attenuationColor", {0.25, 0.25, 0.25}},
                        {"attenuationDistance", 2}}}}}});
  add_texture(box, png8(1, 1, 4, {255, 255, 0, 255}), kNearest);
  const int mesh = box.add_mesh(
      {{"attributes",
        {{"POSITION", box.add_vec3(corners)},
         {"TEXCOORD_0", box.add_accessor(box.add_view(uv.data(), 64), kFloat, 8, "VEC2")}}},
       {"indices", box.add_indices(faces)},
       {"material", 0}});
  box.set_scene({box.add_node({{"mesh", mesh}})});
  Scene slab = load_gltf(box.write_gltf(tmp / "slab.gltf"));
  Camera down = looking_at(glm::vec3(0.f, 0.f, 5.f), glm::vec3(0.f), 1.f);
  down.orthographic = true, down.ymag = 0.5f;
  slab.cameras = {down};
  RenderSettings s;
  s.width = s.height = 8, s.spp = 4, s.environment = glm::vec3(1.f);
  const Image image = render(slab, s).film.resolve();
  for (float v : image.rgb) CHECK(v == doctest::Approx(0.5f).epsilon(1e-3));
}

TEST_CASE("unlit: camera rays see its colour, it lights nothing") {
  // A white Lambert plane seen from above and, beside the view, an unlit quad facing it.
  Scene scene = lit_plane();
  Material unlit;
  unlit.unlit = true, unlit.emission = glm::vec3(0.8f, 0.4f, 0.2f), unlit.double_sided = true;
  scene.materials.push_back(unlit);
  const glm::vec3 a(1.5f, -1.f, 1.f), b(1.5f, 1.f, 1.f), c(1.5f, 1.f, 0.2f), d(1.5f, -1.f, 0.2f);
  scene.geometry.add(a, b, c, 1);
  scene.geometry.add(a, c, d, 1);
  CHECK(LightSampler(scene, {}).empty());
  RenderSettings s;
  s.width = s.height = 16, s.spp = 4, s.environment = glm::vec3(0.f);
  {
    const Result r = render(scene, s);
    const Image image = r.film.resolve();
    for (float v : image.rgb) CHECK(v == 0.f);  // the plane is in the dark
  }
  // Seen head-on, the quad is its colour exactly.
  scene.cameras = {looking_at(glm::vec3(4.f, 0.f, 0.6f), glm::vec3(1.5f, 0.f, 0.6f), 0.1f)};
  const Image image = render(scene, s).film.resolve();
  for (size_t k = 0; k < image.rgb.size(); k += 3) {
    CHECK(image.rgb[k] == doctest::Approx(0.8f));
    CHECK(image.rgb[k + 2] == doctest::Approx(0.2f));
  }
}
