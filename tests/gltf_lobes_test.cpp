// The material extensions of the BSDF's layers as loaded and shaded: KHR_materials_clearcoat,
// KHR_materials_sheen, KHR_materials_iridescence, KHR_materials_specular's textures and
// KHR_materials_unlit reach the
// Material (factors, textures with KHR_texture_transform) and surface_at (texture channels, sRGB
// for colours), and out-of-range values are refused naming the element.
#include <doctest/doctest.h>

#include "dacrt/io/gltf.h"
#include "dacrt/scene/surface.h"
#include "tests/gltf_check.h"
#include "tests/temp_dir.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

TEST_CASE("gltf: KHR_materials_clearcoat and KHR_materials_sheen factors and textures") {
  TempDir dir("lobes");
  const json transform = {{"KHR_texture_transform", {{"offset", {0.5, 0}}}}};
  GltfWriter w = quad_file(
      {{"extensions",
        {{"KHR_materials_clearcoat",
          {{"clearcoatFactor", 0.8},
           {"clearcoatRoughnessFactor", 0.4},
           {"clearcoatTexture", {{"index", 0}}},
           {"clearcoatRoughnessTexture", {{"index", 0}, {"extensions", transform}}},
           {"clearcoatNormalTexture", {{"index", 0}, {"scale", 0.5}}}}},
         {"KHR_materials_sheen",
          {{"sheenColorFactor", {0.5, 1, 1}},
           {"sheenRoughnessFactor", 0.6},
           {"sheenColorTexture", {{"index", 0}}},
           {"sheenRoughnessTexture", {{"index", 0}}}}},
         {"KHR_materials_specular",
          {{"specularFactor", 0.5},
           {"specularTexture", {{"index", 0}}},
           {"specularColorTexture", {{"index", 0}}}}}}}});
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);
  const Scene scene = load_gltf(w.write_gltf(dir / "lobes.gltf"));
  CHECK(!scene.ignored.any());  // all of it read
  const Material& m = scene.materials[0];
  CHECK(m.clearcoat == doctest::Approx(0.8f));
  CHECK(m.clearcoat_roughness == doctest::Approx(0.4f));
  CHECK(m.clearcoat_texture.texture == 0);
  CHECK(m.clearcoat_roughness_texture.apply({0.f, 0.f}) == glm::vec2(0.5f, 0.f));
  CHECK(m.clearcoat_normal_texture.texture == 0);
  CHECK(m.clearcoat_normal_scale == 0.5f);
  CHECK(near(m.sheen_color, {0.5f, 1.f, 1.f}));
  CHECK(m.sheen_roughness == doctest::Approx(0.6f));
  CHECK(m.sheen_color_texture.texture == 0);
  CHECK(m.sheen_roughness_texture.texture == 0);
  CHECK(m.specular_texture.texture == 0);
  CHECK(m.specular_color_texture.texture == 0);
  const BrdfParams p = m.brdf();
  CHECK(p.clearcoat == m.clearcoat);
  CHECK(p.sheen_color == m.sheen_color);

  // The red texel (255, 0, 0, 255) at the quad's top left, green (0, 255, 0, 128) at its top
  // right: the clearcoat's roughness texture is shifted by half the image.
  const SurfacePoint red = quad_surface(scene, 0.25f, 0.75f);
  CHECK(red.brdf.clearcoat == doctest::Approx(0.8f));                // .r = 1
  CHECK(red.brdf.clearcoat_roughness == doctest::Approx(0.4f));      // green's .g = 1
  CHECK(near(red.brdf.sheen_color, {0.5f, 0.f, 0.f}));               // sRGB .rgb
  CHECK(red.brdf.sheen_roughness == doctest::Approx(0.6f));          // .a = 1
  CHECK(red.brdf.specular == doctest::Approx(0.5f));                 // .a = 1
  CHECK(near(red.brdf.specular_color, {1.f, 0.f, 0.f}));             // sRGB .rgb
  const SurfacePoint green = quad_surface(scene, 0.75f, 0.75f);
  CHECK(green.brdf.clearcoat == 0.f);
  CHECK(green.brdf.clearcoat_roughness == 0.f);  // red's .g = 0
  CHECK(green.brdf.sheen_roughness == doctest::Approx(0.6f * 128.f / 255.f));
  CHECK(green.brdf.specular == doctest::Approx(0.5f * 128.f / 255.f));
  // The clearcoat normal map tilts the coat's normal (red: +x), the base's stays the normal.
  CHECK(red.normal == glm::vec3(0, 0, 1));
  CHECK(red.coat_normal.x > 0.1f);
}

TEST_CASE("gltf: the coat's normal without its normal map is the interpolated one") {
  TempDir dir("coat-normal");
  GltfWriter w = quad_file(
      {{"normalTexture", {{"index", 0}}},
       {"extensions", {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1}}}}}});
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);
  const Scene scene = load_gltf(w.write_gltf(dir / "coat.gltf"));
  const SurfacePoint red = quad_surface(scene, 0.25f, 0.75f);
  CHECK(red.normal.x > 0.1f);  // the base's normal map
  CHECK(red.coat_normal == glm::vec3(0, 0, 1));
}

TEST_CASE("gltf: KHR_materials_unlit emits its base colour and reflects nothing") {
  TempDir dir("unlit");
  GltfWriter w = quad_file({{"pbrMetallicRoughness",
                             {{"baseColorFactor", {0.5, 1, 1, 1}},
                              {"baseColorTexture", {{"index", 0}}},
                              {"metallicFactor", 0}}},
                            {"emissiveFactor", {1, 1, 1}},
                            {"extensions", {{"KHR_materials_unlit", json::object()}}}});
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);
  const Scene scene = load_gltf(w.write_gltf(dir / "unlit.gltf"));
  CHECK(!scene.ignored.any());
  const Material& m = scene.materials[0];
  CHECK(m.unlit);
  CHECK(m.emissive());
  CHECK(near(m.emission, {0.5f, 1.f, 1.f}));  // the base colour, not emissiveFactor
  CHECK(GltfBrdf(m.brdf()).lambertian());
  CHECK(GltfBrdf(m.brdf()).base() == glm::vec3(0.f));
  const SurfacePoint red = quad_surface(scene, 0.25f, 0.75f);
  CHECK(near(red.emission, {0.5f, 0.f, 0.f}));
  CHECK(red.brdf.base_color == glm::vec3(0.f));
  const QuadPoint q = quad_point(scene, 0.75f, 0.25f);
  CHECK(near(emission_at(scene, q.tri, q.u, q.v, glm::vec3(0.f, 0.f, 1.f)),
             glm::vec3(0.5f, 1.f, 1.f) * kGrey));
}

TEST_CASE("gltf: KHR_materials_unlit takes the vertex colours too") {
  TempDir dir("unlit-colors");
  const std::vector<glm::vec4> colors(4, glm::vec4(1.f, 0.5f, 0.25f, 1.f));
  GltfWriter w = quad_file({{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 1, 1, 1}}}},
                            {"extensions", {{"KHR_materials_unlit", json::object()}}}});
  w.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
      w.add_accessor(w.add_view(colors.data(), 64), kFloat, 4, "VEC4");
  const Scene scene = load_gltf(w.write_gltf(dir / "unlit.gltf"));
  const QuadPoint q = quad_point(scene, 0.25f, 0.75f);
  CHECK(near(emission_at(scene, q.tri, q.u, q.v, glm::vec3(0.f, 0.f, 1.f)), {0.5f, 0.5f, 0.25f}));
  CHECK(near(quad_surface(scene, 0.25f, 0.75f).emission, {0.5f, 0.5f, 0.25f}));
}

TEST_CASE("gltf: out-of-range clearcoat and sheen values are refused, naming the element") {
  TempDir dir("lobes-bad");
  struct Bad {
    json extensions;
    const char* pointer;
  };
  const Bad bad[] = {
      {{{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.01}}}},
       "/materials/0/extensions/KHR_materials_clearcoat/clearcoatFactor"},
      {{{"KHR_materials_clearcoat", {{"clearcoatRoughnessFactor", -1}}}},
       "/materials/0/extensions/KHR_materials_clearcoat/clearcoatRoughnessFactor"},
      {{{"KHR_materials_sheen", {{"sheenColorFactor", {0, 0, 1.5}}}}},
       "/materials/0/extensions/KHR_materials_sheen/sheenColorFactor/2"},
      {{{"KHR_materials_sheen", {{"sheenRoughnessFactor", "0.5"}}}},
       "/materials/0/extensions/KHR_materials_sheen/sheenRoughnessFactor"},
      {{{"KHR_materials_sheen", {{"sheenColorTexture", {{"index", 3}}}}}},
       "/materials/0/extensions/KHR_materials_sheen/sheenColorTexture/index"},
      {{{"KHR_materials_specular", {{"specularTexture", {{"index", 1}}}}}},
       "/materials/0/extensions/KHR_materials_specular/specularTexture/index"},
      {{{"KHR_materials_unlit", json::array()}}, "/materials/0/extensions/KHR_materials_unlit"},
  };
  for (const Bad& b : bad) {
    INFO(b.pointer);
    GltfWriter w = quad_file({{"extensions", b.extensions}});
    add_texture(w, png8(2, 2, 4, kTexels), kNearest);
    check_error(w.write_gltf(dir / "bad.gltf"), {b.pointer});
  }
}

TEST_CASE("gltf: KHR_materials_iridescence factors and textures") {
  TempDir dir("iridescence");
  GltfWriter w = quad_file(
      {{"extensions",
        {{"KHR_materials_iridescence",
          {{"iridescenceFactor", 0.5},
           {"iridescenceTexture", {{"index", 0}}},
           {"iridescenceIor", 1.8},
           {"iridescenceThicknessMinimum", 150},
           {"iridescenceThicknessMaximum", 450},
           {"iridescenceThicknessTexture", {{"index", 1}}}}}}}});
  w.doc["materials"].push_back({{"extensions", {{"KHR_materials_iridescence", json::object()}}}});
  w.doc["materials"].push_back(
      {{"extensions",
        {{"KHR_materials_iridescence",
          {{"iridescenceFactor", 1}, {"iridescenceThicknessMaximum", 250}}}}}});
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);  // (its own image: both are decoded)
  const Scene scene = load_gltf(w.write_gltf(dir / "iridescence.gltf"));
  CHECK(!scene.ignored.any());  // read, so not warned about
  const Material& m = scene.materials[0];
  CHECK(m.iridescence == 0.5f);
  CHECK(m.iridescence_ior == doctest::Approx(1.8f));
  CHECK(m.iridescence_thickness_min == 150.f);
  CHECK(m.iridescence_thickness_max == 450.f);
  CHECK(m.iridescence_texture.texture == 0);
  CHECK(m.iridescence_thickness_texture.texture == 1);
  // The defaults: no film (factor 0), IOR 1.3, 100 to 400 nm, and their textures not sampled.
  const Material& defaults = scene.materials[1];
  CHECK(defaults.iridescence == 0.f);
  CHECK(defaults.iridescence_ior == doctest::Approx(1.3f));
  CHECK(defaults.iridescence_thickness_min == 100.f);
  CHECK(defaults.iridescence_thickness_max == 400.f);
  // Without a thickness texture the film is the maximum thick.
  const BrdfParams untextured = scene.materials[2].brdf();
  CHECK(untextured.iridescence == 1.f);
  CHECK(untextured.iridescence_thickness == 250.f);
  CHECK(untextured.iridescence_ior == doctest::Approx(1.3f));

  // Red (255, 0, 0, 255) at the top left: factor × .r = 0.5, thickness at .g = 0: the minimum.
  const SurfacePoint red = quad_surface(scene, 0.25f, 0.75f);
  CHECK(red.brdf.iridescence == doctest::Approx(0.5f));
  CHECK(red.brdf.iridescence_thickness == doctest::Approx(150.f));
  CHECK(red.brdf.iridescence_ior == doctest::Approx(1.8f));
  // Green (0, 255, 0, 128) at the top right: no iridescence, the maximum thickness.
  const SurfacePoint green = quad_surface(scene, 0.75f, 0.75f);
  CHECK(green.brdf.iridescence == 0.f);
  CHECK(green.brdf.iridescence_thickness == doctest::Approx(450.f));
}

TEST_CASE("gltf: malformed KHR_materials_iridescence values are refused, naming the element") {
  TempDir dir("iridescence-bad");
  const char* base = "/materials/0/extensions/KHR_materials_iridescence/";
  struct Bad {
    json film;
    std::string member;
  };
  const Bad bad[] = {
      {{{"iridescenceFactor", 1.5}}, "iridescenceFactor"},
      {{{"iridescenceFactor", -0.1}}, "iridescenceFactor"},
      {{{"iridescenceFactor", "1"}}, "iridescenceFactor"},
      {{{"iridescenceIor", 0.9}}, "iridescenceIor"},
      {{{"iridescenceThicknessMinimum", -1}}, "iridescenceThicknessMinimum"},
      {{{"iridescenceThicknessMaximum", -400}}, "iridescenceThicknessMaximum"},
      {{{"iridescenceTexture", {{"index", 3}}}}, "iridescenceTexture/index"},
      {{{"iridescenceThicknessTexture", {{"index", -1}}}}, "iridescenceThicknessTexture/index"},
  };
  for (const Bad& b : bad) {
    const std::string pointer = base + b.member;
    INFO(pointer);
    GltfWriter w = quad_file({{"extensions", {{"KHR_materials_iridescence", b.film}}}});
    add_texture(w, png8(2, 2, 4, kTexels), kNearest);
    check_error(w.write_gltf(dir / "bad.gltf"), {pointer});
  }
}
