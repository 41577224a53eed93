// Normal maps and tangent space: tangents from the file and generated ones (MikkTSpace's welding
// of shared corners) agree, +Y of the map is up the image, and mirrored uvs or nodes mirror the
// tilt with the geometry.
#include <doctest/doctest.h>

#include <cmath>

#include "dacrt/io/gltf.h"
#include "tests/temp_dir.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

TEST_CASE("normal maps: tangents from the file or generated agree, mirrors and +Y up") {
  TempDir dir("normal-map");
  // A constant normal map tilted towards +X of tangent space, or +Y.
  const float s = std::sin(0.5f), c = std::cos(0.5f);
  auto byte = [](float x) { return uint8_t(std::lround((x * 0.5f + 0.5f) * 255.f)); };
  const std::vector<uint8_t> towards_x = {byte(s), byte(0), byte(c)};
  const std::vector<uint8_t> towards_y = {byte(0), byte(s), byte(c)};
  auto file = [&](const std::vector<uint8_t>& texel, bool tangents, bool mirror_uv, json node) {
    GltfWriter w = quad_file({{"normalTexture", {{"index", 0}, {"scale", 1.0}}}});
    const std::vector<glm::vec3> normals(4, glm::vec3(0, 0, 1));
    w.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = w.add_vec3(normals, false);
    if (tangents) {
      // A mirrored layout runs +u along −x and keeps +Y up: w = −1.
      const float sign = mirror_uv ? -1.f : 1.f;
      const std::vector<glm::vec4> t(4, glm::vec4(sign, 0, 0, sign));
      w.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] =
          w.add_accessor(w.add_view(t.data(), 64), kFloat, 4, "VEC4");
    } else {
      // Tangents that would tilt the wrong way, but without NORMAL the spec says to ignore them.
      const std::vector<glm::vec4> wrong(4, glm::vec4(0, -1, 0, 1));
      w.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] =
          w.add_accessor(w.add_view(wrong.data(), 64), kFloat, 4, "VEC4");
      w.doc["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
    }
    if (mirror_uv) {
      const std::vector<glm::vec2> uv = {{1, 1}, {0, 1}, {0, 0}, {1, 0}};
      w.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] =
          w.add_accessor(w.add_view(uv.data(), 32), kFloat, 4, "VEC2");
    }
    std::vector<uint8_t> image;
    for (int i = 0; i < 4; ++i) image.insert(image.end(), texel.begin(), texel.end());
    add_texture(w, png8(2, 2, 3, image), kNearest);
    w.doc["nodes"][0].update(node);
    return load_gltf(w.write_gltf(dir / "quad.gltf"));
  };
  const glm::vec3 tilted_x(s, 0, c), tilted_y(0, s, c);
  for (bool tangents : {true, false}) {
    INFO("tangents from the file: " << tangents);
    const Scene plain = file(towards_x, tangents, false, json::object());
    REQUIRE(plain.tangents.size() == 6);
    CHECK(near(glm::vec3(plain.tangents[0]), glm::vec3(1, 0, 0)));
    CHECK(plain.tangents[0].w == 1.f);
    // +X of tangent space is +u, here +x; +Y is up the image (−v), here +y.
    CHECK(near(quad_surface(plain, 0.6f, 0.3f).normal, tilted_x, 0.01f));
    CHECK(near(quad_surface(file(towards_y, tangents, false, json::object()), 0.3f, 0.6f).normal,
               tilted_y, 0.01f));
    // The image mirrored left to right: +u runs along −x, and so does the tilt; +Y stays up.
    const Scene mirrored_uv = file(towards_x, tangents, true, json::object());
    CHECK(near(quad_surface(mirrored_uv, 0.6f, 0.3f).normal, glm::vec3(-s, 0, c), 0.01f));
    CHECK(near(quad_surface(file(towards_y, tangents, true, json::object()), 0.3f, 0.6f).normal,
               tilted_y, 0.01f));
    // A node that mirrors x (and flips the winding back) mirrors the tilt with the geometry.
    const Scene mirrored_node = file(towards_y, tangents, false, {{"scale", {-1, 1, 1}}});
    const glm::vec3 n = surface_at(mirrored_node, 0, 0.3f, 0.3f, glm::vec3(0, 0, 1)).normal;
    CHECK(near(n, tilted_y, 0.01f));
    const Scene mirrored_x = file(towards_x, tangents, false, {{"scale", {-1, 1, 1}}});
    CHECK(near(surface_at(mirrored_x, 0, 0.3f, 0.3f, glm::vec3(0, 0, 1)).normal,
               glm::vec3(-s, 0, c), 0.01f));
  }
}

TEST_CASE("generated tangents: corners with the same position, normal and uv share one tangent") {
  // Two unindexed triangles of a quad (six vertices): the corners they share get the same
  // tangent, the angle-weighted mean of their different uv tangents, as MikkTSpace welds them.
  TempDir dir("welded");
  GltfWriter w;
  const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},
                                    {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  // uv (x, 1 − y), except the last corner: v 0.2, which turns the second triangle's ∂p/∂u.
  // The shared corner (0, 0, 0) has u = −0 once and +0 once: the same uv.
  const std::vector<glm::vec2> uv = {{-0.f, 1}, {1, 1}, {1, 0}, {0, 1}, {1, 0}, {0, 0.2f}};
  const std::vector<glm::vec3> n(6, glm::vec3(0, 0, 1));
  w.add_material({{"normalTexture", {{"index", 0}}}});
  json attributes = {{"POSITION", w.add_vec3(p)},
                     {"NORMAL", w.add_vec3(n, false)},
                     {"TEXCOORD_0", w.add_accessor(w.add_view(uv.data(), 48), kFloat, 6, "VEC2")}};
  w.set_scene({w.add_node({{"mesh", w.add_mesh({{"attributes", attributes}, {"material", 0}})}})});
  add_texture(w, png8(2, 2, 4, kTexels));
  const Scene scene = load_gltf(w.write_gltf(dir / "welded.gltf"));
  REQUIRE(scene.tangents.size() == 6);
  // Corner 0 of each triangle is (0, 0, 0); corner 2 of the first and 1 of the second (1, 1, 0).
  CHECK(near(glm::vec3(scene.tangents[0]), glm::vec3(scene.tangents[3])));
  CHECK(near(glm::vec3(scene.tangents[2]), glm::vec3(scene.tangents[4])));
  // Between the first triangle's +x and the second's (1, −0.25, 0) direction.
  CHECK(scene.tangents[0].y < -0.01f);
  CHECK(scene.tangents[0].y > -0.24f);
  CHECK(near(glm::vec3(scene.tangents[1]), glm::vec3(1, 0, 0)));  // its own vertex: +x
}
