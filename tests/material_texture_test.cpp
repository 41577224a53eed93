// Textured materials end to end through surface_at (what the path tracer shades with):
// baseColor × factor × vertex colour with alpha, metallic-roughness, emissive, transmission, the
// sampler's wrap modes as the file gives them, COLOR_0, and an emissive texture rendered texel for
// texel.
#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "dacrt/integrators/integrator.h"
#include "dacrt/io/gltf.h"
#include "dacrt/scene/surface.h"
#include "dacrt/render/render_job.h"
#include "tests/gltf_check.h"
#include "tests/temp_dir.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

// The quad's alpha at (x, y) (what the hit filter tests).
float quad_alpha(const Scene& scene, float x, float y) {
  const QuadPoint p = quad_point(scene, x, y);
  return alpha_at(scene, p.tri, p.u, p.v);
}

}  // namespace

TEST_CASE("textures: baseColor × factor × vertex colour, sRGB-decoded, with alpha") {
  TempDir dir("base-color");
  for (Embed embed : {Embed::data_uri, Embed::buffer_view, Embed::file}) {
    INFO("embedding " << int(embed));
    const std::vector<glm::vec4> colors(4, glm::vec4(1.f, 0.5f, 1.f, 0.5f));
    GltfWriter w = quad_file(
        {{"pbrMetallicRoughness",
          {{"baseColorFactor", {0.5, 1, 1, 0.8}}, {"baseColorTexture", {{"index", 0}}}}}});
    w.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
        w.add_accessor(w.add_view(colors.data(), 64), kFloat, 4, "VEC4");
    add_texture(w, png8(2, 2, 4, kTexels), kNearest, embed, dir.path());
    const std::string path = embed == Embed::buffer_view ? w.write_glb(dir / "quad.glb")
                                                         : w.write_gltf(dir / "quad.gltf");
    const Scene scene = load_gltf(path);
    REQUIRE(scene.images.size() == 1);
    CHECK(scene.images[0].width == 2);
    CHECK(scene.texcoords[1].empty());  // no material samples set 1
    // Point (x, y) has uv (x, 1 − y): the image's top-left texel is at the quad's top left.
    const SurfacePoint red = quad_surface(scene, 0.25f, 0.75f);
    CHECK(near(red.brdf.base_color, glm::vec3(0.5f, 0.f, 0.f)));
    CHECK(quad_alpha(scene, 0.25f, 0.75f) == doctest::Approx(0.8f * 0.5f));
    const SurfacePoint green = quad_surface(scene, 0.75f, 0.75f);
    CHECK(near(green.brdf.base_color, glm::vec3(0.f, 0.5f, 0.f)));
    CHECK(quad_alpha(scene, 0.75f, 0.75f) == doctest::Approx(0.8f * 0.5f * 128.f / 255.f));
    const SurfacePoint grey = quad_surface(scene, 0.75f, 0.25f);
    CHECK(near(grey.brdf.base_color, glm::vec3(0.5f, 0.5f, 1.f) * kGrey));
    CHECK(grey.normal == glm::vec3(0, 0, 1));
  }
}

TEST_CASE("textures: metallic-roughness (G, B), emissive (sRGB) and the sampler's wrap modes") {
  TempDir dir("metal-rough");
  GltfWriter w = quad_file({{"pbrMetallicRoughness",
                             {{"metallicFactor", 0.5},
                              {"roughnessFactor", 1.0},
                              {"metallicRoughnessTexture", {{"index", 0}}}}},
                            {"emissiveFactor", {1, 1, 0.5}},
                            {"emissiveTexture", {{"index", 1}}}});
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);
  add_texture(w, png8(2, 2, 4, kTexels), {{"magFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33648}});
  const Scene scene = load_gltf(w.write_gltf(dir / "quad.gltf"));
  REQUIRE(scene.textures.size() == 2);
  CHECK(scene.textures[0].wrap_s == Wrap::repeat);
  CHECK(scene.textures[1].wrap_s == Wrap::clamp);
  CHECK(scene.textures[1].wrap_t == Wrap::mirror);
  CHECK(scene.textures[1].nearest);
  const SurfacePoint blue = quad_surface(scene, 0.25f, 0.25f);  // texel (0, 1): 0, 0, 255
  CHECK(blue.brdf.metallic == doctest::Approx(0.5f));
  CHECK(blue.brdf.roughness == 0.f);
  CHECK(near(blue.emission, glm::vec3(0, 0, 0.5f)));
  const SurfacePoint green = quad_surface(scene, 0.75f, 0.75f);  // texel (1, 0): 0, 255, 0
  CHECK(green.brdf.metallic == 0.f);
  CHECK(green.brdf.roughness == doctest::Approx(1.f));
  CHECK(near(green.emission, glm::vec3(0, 1, 0)));
  CHECK(near(emission_at(scene, 0, 0.f, 0.75f, glm::vec3(0.f, 0.f, 1.f)),
             green.emission));  // the point (0.75, 0.75)
}

TEST_CASE("textures: KHR_materials_transmission's factor × transmissionTexture (R)") {
  TempDir dir("transmission");
  GltfWriter w =
      quad_file({{"extensions",
                  {{"KHR_materials_transmission",
                    {{"transmissionFactor", 0.8},
                     {"transmissionTexture",
                      {{"index", 0},
                       {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0}}}}}}}}}}}}});
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);
  const Scene scene = load_gltf(w.write_gltf(dir / "quad.gltf"));
  CHECK(scene.materials[0].transmission == doctest::Approx(0.8f));
  // (0.75, 0.75) has uv (0.75, 0.25), shifted by 0.5: (0.25, 0.25), the red texel.
  CHECK(quad_surface(scene, 0.75f, 0.75f).brdf.transmission == doctest::Approx(0.8f));
  CHECK(quad_surface(scene, 0.25f, 0.75f).brdf.transmission == 0.f);  // green: R = 0
  w.doc["materials"][0]["extensions"]["KHR_materials_transmission"]["transmissionTexture"] =
      json{{"texCoord", 0}};
  check_error(
      w.write_gltf(dir / "no-index.gltf"),
      {"/materials/0/extensions/KHR_materials_transmission/transmissionTexture/index", "missing"});
}

TEST_CASE("textures: COLOR_0 as normalised UNSIGNED_BYTE VEC3 is linear and interpolated") {
  TempDir dir("colors");
  GltfWriter w = quad_file(json::object());
  const std::vector<uint8_t> colors = {255, 0, 0, 255, 0, 0, 0, 0, 255, 0, 0, 255};
  int a = w.add_accessor(w.add_view(colors.data(), colors.size()), kUnsignedByte, 4, "VEC3");
  w.doc["accessors"][a]["normalized"] = true;
  w.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = a;
  const Scene scene = load_gltf(w.write_gltf(dir / "colors.gltf"));
  REQUIRE(scene.colors.size() == 6);
  // Red along y = 0, blue along y = 1: halfway up, half of each, alpha 1.
  const SurfacePoint s = quad_surface(scene, 0.7f, 0.5f);
  CHECK(near(s.brdf.base_color, glm::vec3(0.5f, 0.f, 0.5f)));
  CHECK(quad_alpha(scene, 0.7f, 0.5f) == 1.f);
  CHECK(scene.texcoords[0].empty());  // nothing samples a texture

  w.doc["accessors"][a]["normalized"] = false;
  check_error(w.write_gltf(dir / "unnormalized.gltf"), {"accessor", "COLOR_0", "normalized"});
}

TEST_CASE("an emissive texture renders texel for texel (uv, barycentrics and sRGB end to end)") {
  TempDir dir("emissive-render");
  GltfWriter w = quad_file({{"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", {{"index", 0}}}});
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);
  Scene scene = load_gltf(w.write_gltf(dir / "quad.gltf"));
  // An orthographic camera whose 8 × 8 pixels cover exactly the quad.
  Camera cam;
  cam.orthographic = true;
  cam.ymag = 0.5f;
  cam.to_world = glm::inverse(
      glm::lookAt(glm::vec3(0.5f, 0.5f, 3.f), glm::vec3(0.5f, 0.5f, 0.f), glm::vec3(0, 1, 0)));
  scene.cameras = {cam};
  RenderSettings s;
  s.width = s.height = 8;
  s.spp = 4;
  s.max_depth = 0;
  auto backend = Backend::create("dacrt", scene.geometry);
  RenderJob job(scene, *backend, s);
  Film film = job.film();
  Progress quiet("test", 1, false);
  job.run(film, 0, uint32_t(s.spp), quiet);
  const glm::vec3 expected[2][2] = {{{1, 0, 0}, {0, 1, 0}}, {{0, 0, 1}, glm::vec3(kGrey)}};
  const Image image = film.resolve();
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      INFO("pixel " << x << ", " << y);
      const float* p = image.pixel(x, y);
      CHECK(near(glm::vec3(p[0], p[1], p[2]), expected[y / 4][x / 4]));
    }
}
