// Tests for io/gltf: small files generated here (tests/gltf_writer.h) with known answers, and the
// real scenes of /work/shared/scenes when they are present. Malformed input, each giving one
// dacrt::Error line naming the file and the element: gltf_errors_test.cpp.
#include "dacrt/io/gltf.h"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>

#include "tests/captured_stderr.h"
#include "tests/gltf_check.h"
#include "tests/gltf_triangle.h"
#include "tests/gltf_writer.h"

using dacrt::load_gltf;
using dacrt::Scene;
using dacrt::test::check_error;
using dacrt::test::GltfWriter;
using dacrt::test::kTriangle;
using dacrt::test::TempDir;
using dacrt::test::triangle_file;
using nlohmann::json;

namespace {

const std::vector<glm::vec3> kQuad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};

bool near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) {
  return glm::all(glm::lessThanEqual(glm::abs(a - b), glm::vec3(eps)));
}

}  // namespace

TEST_CASE("gltf: one non-indexed triangle, default material, framed camera") {
  TempDir dir("one");
  Scene scene = load_gltf(triangle_file().write_gltf(dir / "one.gltf"));
  REQUIRE(scene.geometry.size() == 1);
  for (int k = 0; k < 3; ++k) CHECK(scene.geometry.vertex(0, k) == kTriangle[size_t(k)]);
  CHECK(scene.geometry.material[0] == 0);
  REQUIRE(scene.materials.size() == 1);
  CHECK(scene.materials[0].base_color == glm::vec3(1.f));
  CHECK(!scene.materials[0].emissive());
  CHECK(!scene.materials[0].double_sided);
  CHECK(scene.normals.empty());
  CHECK(scene.cameras_from_file == 0);
  REQUIRE(scene.cameras.size() == 1);
  CHECK(scene.cameras[0].position().z > 0.f);  // frame_bounds looks from +Z
  CHECK(scene.mesh_count == 1);
  CHECK(scene.primitive_count == 1);
  CHECK(scene.node_count == 1);
  CHECK(scene.path == dir / "one.gltf");
}

TEST_CASE("gltf: indexed u8, u16 and u32") {
  TempDir dir("indexed");
  auto check = [&](GltfWriter& w, const char* name) {
    Scene scene = load_gltf(w.write_gltf(dir / name));
    REQUIRE(scene.geometry.size() == 2);
    CHECK(scene.geometry.vertex(1, 0) == kQuad[0]);
    CHECK(scene.geometry.vertex(1, 1) == kQuad[2]);
    CHECK(scene.geometry.vertex(1, 2) == kQuad[3]);
    CHECK(scene.geometry.normal(0).z > 0.f);
  };
  GltfWriter w8, w16, w32;
  w8.add_triangles(kQuad, {{"indices", w8.add_indices(std::vector<uint8_t>{0, 1, 2, 0, 2, 3})}});
  w16.add_triangles(kQuad, {{"indices", w16.add_indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3})}});
  w32.add_triangles(kQuad, {{"indices", w32.add_indices(std::vector<uint32_t>{0, 1, 2, 0, 2, 3})}});
  check(w8, "u8.gltf");
  check(w16, "u16.gltf");
  check(w32, "u32.gltf");
}

TEST_CASE("gltf: interleaved POSITION and NORMAL with byteStride, .bin side file") {
  TempDir dir("interleaved");
  GltfWriter w;
  std::vector<glm::vec3> interleaved;  // position, normal, position, normal, ...
  for (const glm::vec3& p : kTriangle)
    interleaved.insert(interleaved.end(), {p, glm::vec3(0, 0, 2)});
  int view = w.add_view(interleaved.data(), interleaved.size() * sizeof(glm::vec3), 24);
  int position = w.add_accessor(view, dacrt::test::kFloat, 3, "VEC3");
  int normal = w.add_accessor(view, dacrt::test::kFloat, 3, "VEC3", 12);
  w.set_scene({w.add_node(
      {{"mesh", w.add_mesh(json{{"attributes", {{"POSITION", position}, {"NORMAL", normal}}}})}})});
  Scene scene = load_gltf(w.write_gltf(dir / "interleaved.gltf", /*embed=*/false));
  REQUIRE(scene.geometry.size() == 1);
  CHECK(scene.geometry.vertex(0, 2) == kTriangle[2]);
  REQUIRE(scene.normals.size() == 3);
  for (const glm::vec3& n : scene.normals) CHECK(near(n, {0, 0, 1}));  // normalised
}

TEST_CASE("gltf: TRS and matrix hierarchy") {
  TempDir dir("hierarchy");
  GltfWriter w;
  int mesh = w.add_mesh(GltfWriter::primitive(w.add_vec3(kTriangle)));
  // child: matrix = translate(0, 0, 5) * scale(2), column-major
  json matrix = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 5, 1};
  int child = w.add_node({{"mesh", mesh}, {"matrix", matrix}});
  float s = std::sqrt(0.5f);  // 90° about +Z, xyzw
  int parent =
      w.add_node({{"translation", {10, 0, 0}}, {"rotation", {0, 0, s, s}}, {"children", {child}}});
  int plain = w.add_node({{"mesh", mesh}});  // a second instance, untransformed
  w.set_scene({parent, plain});
  Scene scene = load_gltf(w.write_gltf(dir / "hierarchy.gltf"));
  REQUIRE(scene.geometry.size() == 2);
  // (1,0,0) -> child (2,0,5) -> rotated (0,2,5) -> translated (10,2,5)
  CHECK(near(scene.geometry.vertex(0, 0), {10, 0, 5}));
  CHECK(near(scene.geometry.vertex(0, 1), {10, 2, 5}));
  CHECK(near(scene.geometry.vertex(0, 2), {8, 0, 5}));
  CHECK(scene.geometry.vertex(1, 1) == kTriangle[1]);
  CHECK(scene.mesh_count == 1);
  CHECK(scene.primitive_count == 1);
  CHECK(scene.node_count == 3);
}

TEST_CASE("gltf: a negative determinant keeps the front face and the normals") {
  TempDir dir("mirror");
  for (glm::vec3 scale : {glm::vec3(-1, 1, 1), glm::vec3(1, 1, -1), glm::vec3(-1, -1, -1)}) {
    CAPTURE(scale);
    GltfWriter w;
    std::vector<glm::vec3> normals(3, glm::vec3(0, 0, 1));
    int mesh = w.add_mesh(
        json{{"attributes",
              {{"POSITION", w.add_vec3(kTriangle)}, {"NORMAL", w.add_vec3(normals, false)}}}});
    w.set_scene({w.add_node({{"mesh", mesh}, {"scale", {scale.x, scale.y, scale.z}}})});
    Scene scene = load_gltf(w.write_gltf(dir / "mirror.gltf"));
    REQUIRE(scene.geometry.size() == 1);
    REQUIRE(scene.normals.size() == 3);
    // A mirror of a +Z-facing triangle faces scale.z * Z; so must its winding and its normals.
    glm::vec3 expected(0, 0, scale.z);
    CHECK(near(glm::normalize(scene.geometry.normal(0)), expected));
    for (const glm::vec3& n : scene.normals) CHECK(near(n, expected));
  }
}

TEST_CASE("gltf: normals mixed with primitives without NORMAL, bad normals fall back") {
  TempDir dir("normals");
  GltfWriter w;
  float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<glm::vec3> normals = {{0, 0, 3}, {nan, 0, 0}, {0, 0, 0}};
  json plain = GltfWriter::primitive(w.add_vec3(kTriangle));
  json with_normals = {
      {"attributes",
       {{"POSITION", w.add_vec3(kTriangle)}, {"NORMAL", w.add_vec3(normals, false)}}}};
  w.set_scene({w.add_node({{"mesh", w.add_mesh(json::array({plain, with_normals}))}})});
  Scene scene = load_gltf(w.write_gltf(dir / "normals.gltf"));
  REQUIRE(scene.geometry.size() == 2);
  REQUIRE(scene.normals.size() == 6);
  for (const glm::vec3& n : scene.normals) CHECK(near(n, {0, 0, 1}));  // geometric or given
}

TEST_CASE("gltf: perspective and orthographic cameras and their rigid transforms") {
  TempDir dir("camera");
  GltfWriter w;
  w.add_triangles(kTriangle);
  w.doc["cameras"] = {{{"type", "perspective"},
                       {"name", "cam"},
                       {"perspective", {{"yfov", 0.5}, {"aspectRatio", 1.5}, {"znear", 0.1}}}},
                      {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.01}}}},
                      {{"type", "orthographic"},
                       {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"zfar", 10}, {"znear", 0}}}}};
  float s = std::sqrt(0.5f);  // 90° about +Y: the camera looks down -X
  int cam0 = w.add_node({{"camera", 0},
                         {"translation", {1, 2, 3}},
                         {"rotation", {0, s, 0, s}},
                         {"scale", {2, 2, 2}}});
  int cam1 = w.add_node({{"camera", 1}});
  int ortho = w.add_node({{"camera", 2}});
  w.doc["scenes"][0]["nodes"] = {0, cam0, cam1, ortho};
  Scene scene = load_gltf(w.write_gltf(dir / "camera.gltf"));
  CHECK(scene.cameras_from_file == 3);
  REQUIRE(scene.cameras.size() == 3);
  const dacrt::Camera& o = scene.cameras[2];
  CHECK(o.orthographic);
  CHECK(o.ymag == 1.f);
  CHECK(o.aspect == 1.f);
  const dacrt::Camera& c = scene.cameras[0];
  CHECK(c.name == "cam");
  CHECK(near(c.position(), {1, 2, 3}));
  CHECK(c.yfov == doctest::Approx(0.5));
  CHECK(c.aspect == doctest::Approx(1.5));
  CHECK(c.znear == doctest::Approx(0.1));
  CHECK(near(glm::vec3(c.to_world * glm::vec4(0, 0, -1, 0)), {-1, 0, 0}));  // scale removed
  CHECK(near(glm::vec3(c.to_world[1]), {0, 1, 0}));
  CHECK(scene.cameras[1].aspect == 0.f);
  CHECK(scene.cameras[1].yfov == doctest::Approx(0.8));
}

TEST_CASE("gltf: materials, emissive strength and the default material") {
  TempDir dir("materials");
  GltfWriter w;
  w.add_material(
      {{"name", "red"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.1, 0.2, 1}}}}});
  w.add_material(
      {{"name", "light"},
       {"emissiveFactor", {1, 0.5, 0.25}},
       {"doubleSided", true},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}});
  int position = w.add_vec3(kTriangle);
  json primitives = {
      GltfWriter::primitive(position, {{"material", 1}}), GltfWriter::primitive(position),
      GltfWriter::primitive(position, {{"material", 0}}), GltfWriter::primitive(position)};
  w.set_scene({w.add_node({{"mesh", w.add_mesh(primitives)}})});
  Scene scene = load_gltf(w.write_gltf(dir / "materials.gltf"));
  REQUIRE(scene.materials.size() == 3);  // the default material appended once
  CHECK(scene.materials[0].name == "red");
  CHECK(near(scene.materials[0].base_color, {0.8f, 0.1f, 0.2f}));
  CHECK(!scene.materials[0].emissive());
  CHECK(near(scene.materials[1].emission, {4, 2, 1}));
  CHECK(scene.materials[1].double_sided);
  CHECK(scene.materials[2].base_color == glm::vec3(1.f));
  CHECK(!scene.materials[2].emissive());
  REQUIRE(scene.geometry.size() == 4);
  CHECK(scene.geometry.material == std::vector<uint32_t>{1, 2, 0, 2});
  CHECK(scene.primitive_count == 4);
  // glTF's defaults: a rough metal, IOR 1.5, full specular.
  CHECK(scene.materials[2].metallic == 1.f);
  CHECK(scene.materials[2].roughness == 1.f);
  CHECK(scene.materials[2].ior == 1.5f);
  CHECK(scene.materials[2].specular == 1.f);
  CHECK(scene.materials[2].specular_color == glm::vec3(1.f));
}

TEST_CASE("gltf: metallic-roughness factors, KHR_materials_ior and KHR_materials_specular") {
  TempDir dir("brdf");
  GltfWriter w;
  w.add_material({{"pbrMetallicRoughness", {{"metallicFactor", 0.25}, {"roughnessFactor", 0.6}}},
                  {"extensions",
                   {{"KHR_materials_ior", {{"ior", 1.33}}},
                    {"KHR_materials_specular",
                     {{"specularFactor", 0.4}, {"specularColorFactor", {1.0, 0.5, 0.25}}}}}}});
  // The ends of the spec's [0, 1] (outside it is a schema error: tests/gltf_schema_test.cpp); ior 0
  // is the spec-gloss compatibility value (Fresnel 1).
  w.add_material({{"pbrMetallicRoughness", {{"metallicFactor", 1}, {"roughnessFactor", 0}}},
                  {"extensions", {{"KHR_materials_ior", {{"ior", 0}}}}}});
  int position = w.add_vec3(kTriangle);
  w.set_scene(
      {w.add_node({{"mesh", w.add_mesh({GltfWriter::primitive(position, {{"material", 0}}),
                                        GltfWriter::primitive(position, {{"material", 1}})})}})});
  Scene scene = load_gltf(w.write_gltf(dir / "brdf.gltf"));
  REQUIRE(scene.materials.size() == 2);
  const dacrt::Material& a = scene.materials[0];
  CHECK(a.metallic == 0.25f);
  CHECK(a.roughness == doctest::Approx(0.6f));
  CHECK(a.ior == doctest::Approx(1.33f));
  CHECK(a.specular == doctest::Approx(0.4f));
  CHECK(near(a.specular_color, {1.f, 0.5f, 0.25f}));
  const dacrt::Material& b = scene.materials[1];
  CHECK(b.metallic == 1.f);
  CHECK(b.roughness == 0.f);
  CHECK(b.ior == 0.f);
  CHECK(b.specular == 1.f);
}

TEST_CASE("gltf: KHR_materials_volume and KHR_materials_dispersion are read, without warnings") {
  TempDir dir("volume");
  GltfWriter w;
  w.add_material({{"pbrMetallicRoughness", {{"metallicFactor", 0}}},
                  {"extensions",
                   {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                    {"KHR_materials_volume",
                     {{"thicknessFactor", 0.3},
                      {"attenuationDistance", 2.5},
                      {"attenuationColor", {0.5, 0.25, 1.0}}}},
                    {"KHR_materials_dispersion", {{"dispersion", 0.36}}}}}});
  // Defaults: thin-walled, no absorption, no dispersion.
  w.add_material({{"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}}}});
  int position = w.add_vec3(kTriangle);
  w.set_scene(
      {w.add_node({{"mesh", w.add_mesh({GltfWriter::primitive(position, {{"material", 0}}),
                                        GltfWriter::primitive(position, {{"material", 1}})})}})});
  dacrt::test::CapturedStderr err;
  Scene scene = load_gltf(w.write_gltf(dir / "volume.gltf"));
  const std::string warnings = err.text();
  CHECK_MESSAGE(warnings.find("warning") == std::string::npos, warnings);
  REQUIRE(scene.materials.size() == 2);
  const dacrt::Material& a = scene.materials[0];
  CHECK(a.thickness == doctest::Approx(0.3f));
  CHECK(a.attenuation_distance == doctest::Approx(2.5f));
  CHECK(near(a.attenuation_color, {0.5f, 0.25f, 1.f}));
  CHECK(a.dispersion == doctest::Approx(0.36f));
  CHECK(a.volume());
  const dacrt::Material& b = scene.materials[1];
  CHECK(b.thickness == 0.f);
  CHECK(b.attenuation_distance == INFINITY);
  CHECK(b.attenuation_color == glm::vec3(1.f));
  CHECK(b.dispersion == 0.f);
  CHECK(!b.volume());
}

TEST_CASE("gltf: KHR_lights_punctual lights, placed by their nodes") {
  TempDir dir("lights");
  GltfWriter w;
  w.add_triangles(kTriangle);
  w.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"},
       {"name", "bulb"},
       {"color", {1, 0.5, 0.25}},
       {"intensity", 8},
       {"range", 3}},
      {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}},
      {{"type", "directional"}, {"intensity", 2}}};
  float s = std::sqrt(0.5f);  // 90° about +X: -Z turns to +Y
  int bulb = w.add_node(
      {{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  int spot = w.add_node(
      {{"rotation", {s, 0, 0, s}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  int sun = w.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  w.doc["scenes"][0]["nodes"] = {0, bulb, spot, sun};
  Scene scene = load_gltf(w.write_gltf(dir / "lights.gltf"));
  REQUIRE(scene.lights.size() == 3);
  const dacrt::PunctualLight& p = scene.lights[0];
  CHECK(p.type == dacrt::PunctualLight::Type::point);
  CHECK(p.name == "bulb");
  CHECK(near(p.intensity, {8, 4, 2}));
  CHECK(p.range == 3.f);
  CHECK(near(p.position, {1, 2, 3}));
  const dacrt::PunctualLight& sp = scene.lights[1];
  CHECK(sp.type == dacrt::PunctualLight::Type::spot);
  CHECK(near(sp.direction, {0, 1, 0}));
  CHECK(sp.cos_inner == doctest::Approx(std::cos(0.2)));
  CHECK(sp.cos_outer == doctest::Approx(std::cos(0.5)));
  CHECK(near(sp.intensity, {1, 1, 1}));
  const dacrt::PunctualLight& sun_light = scene.lights[2];
  CHECK(sun_light.type == dacrt::PunctualLight::Type::directional);
  CHECK(near(sun_light.direction, {0, 0, -1}));
  CHECK(sun_light.range == 0.f);
}

TEST_CASE("gltf: EXT_mesh_gpu_instancing draws the mesh once per instance") {
  TempDir dir("instancing");
  GltfWriter w;
  int position = w.add_vec3(kTriangle);
  int mesh = w.add_mesh({GltfWriter::primitive(position)});
  int translation = w.add_vec3({{10, 0, 0}, {0, 10, 0}, {0, 0, 10}}, false);
  // Instance rotations as normalised SHORTs: identity, identity, 90° about +Z.
  const int16_t s = int16_t(std::lround(32767 * std::sqrt(0.5)));
  std::vector<int16_t> quats = {0, 0, 0, 32767, 0, 0, 0, 32767, 0, 0, s, s};
  int rotation = w.add_accessor(w.add_view(quats.data(), quats.size() * 2), 5122, 3, "VEC4");
  w.doc["accessors"][rotation]["normalized"] = true;
  int scale = w.add_vec3({{1, 1, 1}, {2, 2, 2}, {1, 1, 1}}, false);
  int node = w.add_node(
      {{"mesh", mesh},
       {"translation", {0, 0, 1}},
       {"extensions",
        {{"EXT_mesh_gpu_instancing",
          {{"attributes",
            {{"TRANSLATION", translation}, {"ROTATION", rotation}, {"SCALE", scale}}}}}}}});
  w.set_scene({node});
  w.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  w.doc["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  Scene scene = load_gltf(w.write_gltf(dir / "instances.gltf"));
  REQUIRE(scene.geometry.size() == 3);  // never at the node itself
  const dacrt::Geometry& g = scene.geometry;
  // The node's transform applies after the instance's: corners + (0, 0, 1).
  CHECK(near(g.vertex(0, 0), kTriangle[0] + glm::vec3(10, 0, 1)));
  CHECK(near(g.vertex(1, 1), 2.f * kTriangle[1] + glm::vec3(0, 10, 1)));
  // 90° about +Z turns +X into +Y.
  CHECK(near(g.vertex(2, 1) - g.vertex(2, 0),
             glm::vec3(-(kTriangle[1] - kTriangle[0]).y, (kTriangle[1] - kTriangle[0]).x, 0),
             1e-4f));
  CHECK(scene.mesh_count == 1);
}

TEST_CASE("gltf: what this version does not render is counted (and warned about)") {
  TempDir dir("ignored");
  GltfWriter w;
  // (A KHR_materials_specular texture of a material with specularFactor 0 is never sampled, so
  // never decoded.)
  w.add_material({{"extensions",
                   {{"KHR_materials_specular",
                     {{"specularFactor", 0}, {"specularTexture", {{"index", 0}}}}}}}});
  w.doc["textures"] = json::array({json::object()});
  w.add_material({{"alphaMode", "MASK"},
                  {"extensions", {{"KHR_materials_volume", {{"thicknessFactor", 0.5}}}}}});
  w.add_material({{"alphaMode", "BLEND"},
                  {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}}}});
  int position = w.add_vec3(kTriangle);
  int color = w.add_vec3({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, false);
  w.set_scene({w.add_node(
      {{"mesh", w.add_mesh({GltfWriter::primitive(position, {{"material", 0}}),
                            GltfWriter::primitive(position, {{"material", 1}}),
                            GltfWriter::primitive(position, {{"material", 2}}),
                            {{"attributes", {{"POSITION", position}, {"COLOR_0", color}}}}})}})});
  Scene scene = load_gltf(w.write_gltf(dir / "ignored.gltf"));
  CHECK(scene.geometry.size() == 4);
  const Scene::Ignored& i = scene.ignored;
  // KHR_materials_volume is read; without transmission it has no effect (no light enters).
  CHECK(scene.materials[1].thickness == 0.5f);
  CHECK(!scene.materials[1].volume());
  // Vertex colours are rendered: triangles before the first coloured one get white.
  REQUIRE(scene.colors.size() == 12);
  CHECK(scene.colors[0] == glm::vec4(1.f));
  CHECK(scene.colors[9] == glm::vec4(1, 0, 0, 1));
  // Alpha modes are rendered.
  CHECK(scene.materials[1].alpha_mode == dacrt::Material::AlphaMode::mask);
  CHECK(scene.materials[2].alpha_mode == dacrt::Material::AlphaMode::blend);
  CHECK(scene.materials[2].transmission == 1.f);
  CHECK(i.any());
  CHECK(!load_gltf(triangle_file().write_gltf(dir / "plain.gltf")).ignored.any());
}

TEST_CASE("gltf: an empty scene is valid and still has a material and a camera") {
  TempDir dir("empty");
  GltfWriter w;
  w.set_scene({w.add_node(json::object())});
  Scene scene = load_gltf(w.write_gltf(dir / "empty.gltf"));
  CHECK(scene.geometry.size() == 0);
  CHECK(scene.materials.size() == 1);
  CHECK(scene.cameras.size() == 1);
  CHECK(scene.node_count == 1);
}

TEST_CASE("gltf: GLB gives the same scene as .gltf") {
  TempDir dir("glb");
  GltfWriter w;
  w.add_triangles(kQuad, {{"indices", w.add_indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3, 0})}});
  Scene glb = load_gltf(w.write_glb(dir / "quad.glb"));
  Scene gltf = load_gltf(w.write_gltf(dir / "quad.gltf"));
  REQUIRE(glb.geometry.size() == 2);  // the trailing index is an incomplete triangle
  CHECK(glb.geometry.corners == gltf.geometry.corners);
  // The magic decides, not the extension.
  std::filesystem::copy_file(dir / "quad.glb", dir / "quad-glb.gltf");
  CHECK(load_gltf(dir / "quad-glb.gltf").geometry.size() == 2);
}

TEST_CASE("gltf: triangle strips and fans become triangles, points and lines are skipped") {
  TempDir dir("modes");
  GltfWriter w;
  int position = w.add_vec3(kQuad);
  json primitives = json::array();
  for (int mode : {0, 1, 2, 3, 4, 5, 6})
    primitives.push_back(GltfWriter::primitive(position, {{"mode", mode}}));
  primitives.push_back(GltfWriter::primitive(position));  // mode absent = 4
  w.set_scene({w.add_node({{"mesh", w.add_mesh(primitives)}})});
  Scene scene = load_gltf(w.write_gltf(dir / "modes.gltf"));
  // Lists: 1 triangle each (the fourth vertex is an incomplete triangle); strip and fan: 2.
  REQUIRE(scene.geometry.size() == 6);
  CHECK(scene.primitive_count == 4);
  const dacrt::Geometry& g = scene.geometry;
  auto corners = [&](size_t t, int a, int b, int c) {
    return g.vertex(t, 0) == kQuad[a] && g.vertex(t, 1) == kQuad[b] && g.vertex(t, 2) == kQuad[c];
  };
  // The strip: (0, 1, 2), then (1, 3, 2), which keeps the first triangle's winding.
  CHECK(corners(1, 0, 1, 2));
  CHECK(corners(2, 1, 3, 2));
  // The fan: (1, 2, 0) and (2, 3, 0), both counter-clockwise seen from +z like the quad.
  CHECK(corners(3, 1, 2, 0));
  CHECK(corners(4, 2, 3, 0));
  CHECK(g.normal(3).z > 0.f);
  CHECK(g.normal(4).z > 0.f);
}

TEST_CASE("gltf: an indexed strip drops the degenerate triangles that join its parts") {
  TempDir dir("strip");
  GltfWriter w;
  int position = w.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 0, 0}, {2, 1, 0}});
  // Two strips, (0 1 2 3) and (1 4 3 5), joined by repeating 3 and 1.
  int indices = w.add_indices(std::vector<uint16_t>{0, 1, 2, 3, 3, 1, 1, 4, 3, 5});
  w.set_scene({w.add_node({{"mesh", w.add_mesh({GltfWriter::primitive(
                                        position, {{"mode", 5}, {"indices", indices}})})}})});
  Scene scene = load_gltf(w.write_gltf(dir / "strip.gltf"));
  CHECK(scene.geometry.size() == 4);
  for (size_t t = 0; t < scene.geometry.size(); ++t) CHECK(scene.geometry.area(t) > 0.f);
}

TEST_CASE("gltf: sparse accessors and accessors without bufferView") {
  TempDir dir("sparse");
  GltfWriter w;
  w.add_triangles(kTriangle);
  std::vector<uint16_t> indices = {2, 0};
  std::vector<glm::vec3> values = {{5, 6, 7}, {-1, -1, -1}};
  int index_view = w.add_view(indices.data(), 4);
  int value_view = w.add_view(values.data(), sizeof(glm::vec3) * 2);
  json sparse = {
      {"count", 2},
      {"indices", {{"bufferView", index_view}, {"componentType", dacrt::test::kUnsignedShort}}},
      {"values", {{"bufferView", value_view}}}};
  w.doc["accessors"][0]["sparse"] = sparse;
  Scene scene = load_gltf(w.write_gltf(dir / "sparse.gltf"));
  REQUIRE(scene.geometry.size() == 1);
  CHECK(scene.geometry.vertex(0, 0) == glm::vec3(-1));
  CHECK(scene.geometry.vertex(0, 1) == kTriangle[1]);
  CHECK(scene.geometry.vertex(0, 2) == glm::vec3(5, 6, 7));

  w.doc["accessors"][0].erase("bufferView");  // zeros, then patched (not on one line)
  scene = load_gltf(w.write_gltf(dir / "zeros.gltf"));
  REQUIRE(scene.geometry.size() == 1);
  CHECK(scene.geometry.vertex(0, 1) == glm::vec3(0));
  CHECK(scene.geometry.vertex(0, 2) == glm::vec3(5, 6, 7));
}

TEST_CASE("gltf: scene selection") {
  TempDir dir("scenes");
  GltfWriter w;
  int mesh = w.add_mesh(GltfWriter::primitive(w.add_vec3(kTriangle)));
  w.add_node({{"mesh", mesh}});
  w.add_node({{"mesh", mesh}, {"translation", {0, 0, 1}}});
  w.doc["scenes"] = {{{"nodes", {0}}}, {{"nodes", {0, 1}}}};
  w.doc["scene"] = 1;
  std::string path = w.write_gltf(dir / "scenes.gltf");
  CHECK(load_gltf(path).geometry.size() == 2);
  CHECK(load_gltf(path, {.scene = 0}).geometry.size() == 1);
  check_error(path, {"scene 2"}, {.scene = 2});
  w.doc["scene"] = 7;
  check_error(w.write_gltf(dir / "default.gltf"), {"/scene", "7 is not an index"});
}

TEST_CASE("gltf: a zero scale gives degenerate triangles but no NaN") {
  TempDir dir("zero-scale");
  // Scale 0 along x: the triangle in the x-y plane has no area left (dropped, counted); the one
  // in the y-z plane keeps its shape, and its normal through the singular transform is no NaN.
  GltfWriter w;
  std::vector<glm::vec3> normals(3, glm::vec3(0, 0, 1));
  int flat = w.add_mesh(
      json{{"attributes",
            {{"POSITION", w.add_vec3(kTriangle)}, {"NORMAL", w.add_vec3(normals, false)}}}});
  const std::vector<glm::vec3> upright = {{0, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  std::vector<glm::vec3> across(3, glm::vec3(1, 0, 0));
  int kept = w.add_mesh(
      json{{"attributes",
            {{"POSITION", w.add_vec3(upright)}, {"NORMAL", w.add_vec3(across, false)}}}});
  w.set_scene({w.add_node({{"mesh", flat}, {"scale", {0, 1, 1}}}),
               w.add_node({{"mesh", kept}, {"scale", {0, 1, 1}}})});
  Scene scene = load_gltf(w.write_gltf(dir / "zero.gltf"));
  CHECK(scene.degenerate_triangles == 1);
  REQUIRE(scene.geometry.size() == 1);
  REQUIRE(scene.normals.size() == 3);
  for (const glm::vec3& n : scene.normals) CHECK(glm::length(n) == doctest::Approx(1.f));
}

// ---------------------------------------------------------------------------------------------
// Real scenes (made by others, validator-clean), when the shared folder is there.

TEST_CASE("gltf: real scenes from ../shared/scenes") {
  std::filesystem::path root = DACRT_SOURCE_DIR "/../shared/scenes";
  if (!std::filesystem::is_directory(root)) {
    MESSAGE("skipped: " << root.string() << " does not exist");
    return;
  }
  struct Expected {
    const char* path;
    size_t triangles;
  };
  // Triangle counts from the folder's README (scenes that need strips, fans or instancing, which
  // this version does not expand, are left out).
  for (Expected e : {Expected{"khronos/Box/Box.glb", 12},
                     {"khronos/BoxVertexColors/BoxVertexColors.glb", 12},
                     {"khronos/TriangleWithoutIndices/TriangleWithoutIndices.gltf", 1},
                     {"khronos/OrientationTest/OrientationTest.glb", 524},
                     {"khronos/NegativeScaleTest/NegativeScaleTest.glb", 7724},
                     {"khronos/SimpleSparseAccessor/SimpleSparseAccessor.gltf", 12},
                     {"khronos/EmissiveStrengthTest/EmissiveStrengthTest.glb", 90},
                     {"khronos/TextureTransformTest/TextureTransformTest.gltf", 24},
                     {"mcguire/cornell-box/CornellBox-Original.glb", 36},
                     {"stanford/bunny/bunny.glb", 69451}}) {
    std::string path = (root / e.path).string();
    CAPTURE(path);
    if (!std::filesystem::exists(path)) {
      MESSAGE("missing: " << path);
      continue;
    }
    Scene scene = load_gltf(path);
    CHECK(scene.geometry.size() == e.triangles);
    CHECK(!scene.materials.empty());
    CHECK(!scene.cameras.empty());
    CHECK(!scene.bounds().empty());
    CHECK((scene.normals.empty() || scene.normals.size() == 3 * scene.geometry.size()));
  }
  std::string sparse = (root / "khronos/SimpleSparseAccessor/SimpleSparseAccessor.gltf").string();
  if (std::filesystem::exists(sparse))  // the sparse values lift 3 vertices to the accessor's max
    CHECK(load_gltf(sparse).bounds().hi == glm::vec3(6, 4, 0));
  std::string cornell = (root / "mcguire/cornell-box/CornellBox-Original.glb").string();
  if (std::filesystem::exists(cornell)) {
    Scene scene = load_gltf(cornell);
    bool light = false;
    for (const dacrt::Material& m : scene.materials) light |= m.emission.x > 10.f;  // Ke 17 12 4
    CHECK(light);
    CHECK(scene.cameras_from_file == 0);
  }
}
