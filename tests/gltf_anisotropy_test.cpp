// KHR_materials_anisotropy as loaded and shaded: the factors and the texture reach the Material
// and surface_at (direction from the texture's .rg, turned by anisotropyRotation, in the tangent
// frame of the file's TANGENT or of tangents generated from the uvs; strength × .b), a primitive
// without any tangent space is warned about, malformed values are refused naming the element,
// and a rendered highlight on an anisotropic metal plane stretches along the tangent.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>

#include "dacrt/io/gltf.h"
#include "render_check.h"
#include "dacrt/scene/surface.h"
#include "tests/captured_stderr.h"
#include "tests/gltf_check.h"
#include "tests/temp_dir.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

json anisotropy(const json& members) {
  return {{"extensions", {{"KHR_materials_anisotropy", members}}}};
}

// The quad of quad_file with NORMAL +z and TANGENT (cos β, sin β, 0, w) at every corner.
GltfWriter tangent_quad(const json& material, float beta, float w) {
  GltfWriter out = quad_file(material);
  const std::vector<glm::vec3> normals(4, glm::vec3(0, 0, 1));
  const std::vector<glm::vec4> tangents(4, glm::vec4(std::cos(beta), std::sin(beta), 0.f, w));
  json& attributes = out.doc["meshes"][0]["primitives"][0]["attributes"];
  attributes["NORMAL"] = out.add_vec3(normals, false);
  attributes["TANGENT"] = out.add_accessor(out.add_view(tangents.data(), 64), kFloat, 4, "VEC4");
  return out;
}

glm::vec3 at_angle(float angle) {
  return {std::cos(angle), std::sin(angle), 0.f};
}

}  // namespace

TEST_CASE("gltf: KHR_materials_anisotropy factors and texture reach the material and surface") {
  TempDir dir("anisotropy");
  GltfWriter w = quad_file(anisotropy({{"anisotropyStrength", 0.6},
                                       {"anisotropyRotation", 0.5},
                                       {"anisotropyTexture", {{"index", 0}}}}));
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);
  const Scene scene = load_gltf(w.write_gltf(dir / "anisotropy.gltf"));
  CHECK(!scene.ignored.any());  // read, not warned about
  const Material& m = scene.materials[0];
  CHECK(m.anisotropy == doctest::Approx(0.6f));
  CHECK(m.anisotropy_rotation.x == doctest::Approx(std::cos(0.5f)));
  CHECK(m.anisotropy_rotation.y == doctest::Approx(std::sin(0.5f)));
  CHECK(m.anisotropy_texture.texture == 0);
  CHECK(m.anisotropic());
  CHECK(m.brdf().anisotropy == m.anisotropy);
  // No TANGENT: tangents from TEXCOORD_0 = (x, 1 − y), so the frame is (+x, +y).
  REQUIRE(!scene.tangents.empty());
  // The blue texel (0, 0, 255) at the quad's bottom left: direction (−1, −1) / √2 turned by 0.5,
  // strength 0.6 × 1.
  const SurfacePoint blue = quad_surface(scene, 0.25f, 0.25f);
  CHECK(blue.brdf.anisotropy == doctest::Approx(0.6f));
  CHECK(near(blue.anisotropy_direction, at_angle(-0.75f * glm::pi<float>() + 0.5f), 1e-4f));
  // The grey texel (188 of 255, read linearly) at its bottom right: (1, 1) / √2 turned by 0.5,
  // strength 0.6 × 188 / 255.
  const SurfacePoint grey = quad_surface(scene, 0.75f, 0.25f);
  CHECK(grey.brdf.anisotropy == doctest::Approx(0.6f * 188.f / 255.f));
  CHECK(near(grey.anisotropy_direction, at_angle(0.25f * glm::pi<float>() + 0.5f), 1e-4f));
  // The red texel's blue channel is 0: no anisotropy there.
  CHECK(quad_surface(scene, 0.25f, 0.75f).brdf.anisotropy == 0.f);
}

TEST_CASE("gltf: KHR_materials_anisotropy follows the file's TANGENT, turned counter-clockwise") {
  TempDir dir("anisotropy-tangent");
  const float beta = glm::radians(30.f);
  // The tangent 30° from +x, turned back by anisotropyRotation −30°: along +x.
  GltfWriter w = tangent_quad(
      anisotropy({{"anisotropyStrength", 1}, {"anisotropyRotation", -beta}}), beta, 1.f);
  Scene scene = load_gltf(w.write_gltf(dir / "a.gltf"));
  CHECK(near(quad_surface(scene, 0.3f, 0.6f).anisotropy_direction, {1.f, 0.f, 0.f}, 1e-5f));
  // Turned by +90°: along the bitangent cross(n, t) · w, flipped by w = −1.
  for (float sign : {1.f, -1.f}) {
    GltfWriter v = tangent_quad(
        anisotropy({{"anisotropyStrength", 1}, {"anisotropyRotation", glm::half_pi<float>()}}),
        beta, sign);
    scene = load_gltf(v.write_gltf(dir / "b.gltf"));
    INFO("w " << sign);
    CHECK(near(quad_surface(scene, 0.6f, 0.3f).anisotropy_direction,
               sign * at_angle(beta + glm::half_pi<float>()), 1e-5f));
  }
}

TEST_CASE("gltf: an anisotropic primitive without TANGENT or uvs is warned about") {
  TempDir dir("anisotropy-untangented");
  GltfWriter w = quad_file(anisotropy({{"anisotropyStrength", 0.5}}));
  w.doc["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_0");
  const std::string path = w.write_gltf(dir / "a.gltf");
  CapturedStderr err;
  const Scene scene = load_gltf(path);
  const std::string text = err.text();
  CHECK(text.find("1 primitives of anisotropic materials have no TANGENT and no TEXCOORD") !=
        std::string::npos);
  CHECK(scene.ignored.untangented_anisotropic == 1);  // and `dacrt info` lists it
  // An arbitrary direction, but one in the tangent plane.
  const SurfacePoint s = quad_surface(scene, 0.3f, 0.6f);
  CHECK(std::abs(glm::length(s.anisotropy_direction) - 1.f) < 1e-5f);
  CHECK(std::abs(s.anisotropy_direction.z) < 1e-5f);
  // With uvs (and no texture), tangents come from TEXCOORD_0 without a word.
  GltfWriter v = quad_file(anisotropy({{"anisotropyStrength", 0.5}}));
  CapturedStderr quiet;
  const Scene with_uv = load_gltf(v.write_gltf(dir / "b.gltf"));
  CHECK(quiet.text().find("TANGENT") == std::string::npos);
  CHECK(near(quad_surface(with_uv, 0.3f, 0.6f).anisotropy_direction, {1.f, 0.f, 0.f}, 1e-5f));
  CHECK(with_uv.texcoords[0].empty());  // read for the tangents, not kept
}

TEST_CASE("gltf: malformed KHR_materials_anisotropy values are refused, naming the element") {
  TempDir dir("anisotropy-bad");
  const std::string p = "/materials/0/extensions/KHR_materials_anisotropy/";
  struct Bad {
    json members;
    std::string where;
  };
  const Bad bad[] = {
      {{{"anisotropyStrength", 1.5}}, p + "anisotropyStrength"},
      {{{"anisotropyStrength", -0.5}}, p + "anisotropyStrength"},
      {{{"anisotropyStrength", "1"}}, p + "anisotropyStrength"},
      {{{"anisotropyRotation", "0.5"}}, p + "anisotropyRotation"},
      {{{"anisotropyRotation", 1e39}}, "material 0: KHR_materials_anisotropy.anisotropyRotation"},
      {{{"anisotropyTexture", {{"index", 3}}}}, p + "anisotropyTexture/index"},
      {{{"anisotropyTexture", 0}}, p + "anisotropyTexture"},
  };
  for (const Bad& b : bad) {
    INFO(b.where);
    GltfWriter w = quad_file(anisotropy(b.members));
    add_texture(w, png8(2, 2, 4, kTexels), kNearest);
    check_error(w.write_gltf(dir / "bad.gltf"), {b.where});
  }
}

TEST_CASE("render: a point light's highlight on an anisotropic metal stretches along the tangent") {
  // lit_plane() as a metal of roughness 0.3 under a point light above its centre, seen from
  // straight above: the highlight's second moment of x against y (pixel values weighted by x², y²)
  // is larger along the tangent, across it when the direction is turned by 90°, and equal for
  // the isotropic metal.
  RenderSettings s;
  s.environment = glm::vec3(0.f);  // its lights alone (a sky of 1 stays beside the file's lights)
  s.width = s.height = 16, s.spp = 16;
  auto moments = [&](float strength, float rotation) {
    Scene scene = lit_plane();
    Material m;
    m.metallic = 1.f, m.roughness = 0.3f, m.base_color = glm::vec3(1.f);
    m.anisotropy = strength;
    m.anisotropy_rotation = {std::cos(rotation), std::sin(rotation)};
    scene.materials = {m};
    scene.tangents.assign(3 * scene.geometry.size(), glm::vec4(1.f, 0.f, 0.f, 1.f));
    PunctualLight l;
    l.position = glm::vec3(0.f, 0.f, 1.f);
    scene.lights = {l};
    const Result r = render(scene, s);
    glm::dvec2 moment(0.0);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        const double value = r.film.mean_and_error(size_t(y) * 16 + x).x;
        const glm::dvec2 p(-1.0 + (x + 0.5) / 8.0, 1.0 - (y + 0.5) / 8.0);
        moment += value * p * p;
      }
    return moment;
  };
  const glm::dvec2 along = moments(1.f, 0.f), across = moments(1.f, glm::half_pi<float>());
  const glm::dvec2 isotropic = moments(0.f, 0.f);
  INFO("along " << along.x << " " << along.y << ", across " << across.x << " " << across.y
                << ", isotropic " << isotropic.x << " " << isotropic.y);
  CHECK(along.x > 2.0 * along.y);
  CHECK(across.y > 2.0 * across.x);
  CHECK(isotropic.x == doctest::Approx(isotropic.y).epsilon(0.05));
}
