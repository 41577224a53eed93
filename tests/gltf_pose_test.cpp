// Posing a loaded scene (GltfAnimation::pose): bit for bit the scene a fresh load at that time
// makes (triangles in order, the same dropped zero-area ones, normals, uvs, colours, tangents,
// cameras, lights), on a generated file with every path posing takes (a skin, morph targets that
// collapse a triangle, a mirrored instance, a strip over a few of many vertices, a normal map's
// tangents from the file and generated, an animated camera and light) and on the Khronos samples
// where they are; and the file is decoded once: a pose reads no accessor and decompresses
// nothing (meshopt and Draco seeds included), the one exception a morph target first weighed.
#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>

#include "dacrt/io/gltf.h"
#include "gltf_writer.h"
#include "png.h"
#include "temp_dir.h"
#include "texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool same_bytes(const glm::vec3& a, const glm::vec3& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// What pose() replaces, compared bit for bit.
void check_same(const Scene& posed, const Scene& loaded) {
  REQUIRE(posed.geometry.size() == loaded.geometry.size());
  CHECK(same_bytes(posed.geometry.corners, loaded.geometry.corners));
  CHECK(posed.geometry.material == loaded.geometry.material);
  CHECK(posed.degenerate_triangles == loaded.degenerate_triangles);
  CHECK(same_bytes(posed.normals, loaded.normals));
  REQUIRE(posed.texcoords.size() == loaded.texcoords.size());
  for (size_t s = 0; s < posed.texcoords.size(); ++s)
    CHECK(same_bytes(posed.texcoords[s], loaded.texcoords[s]));
  CHECK(same_bytes(posed.colors, loaded.colors));
  CHECK(same_bytes(posed.tangents, loaded.tangents));
  REQUIRE(posed.cameras.size() == loaded.cameras.size());
  for (size_t i = 0; i < posed.cameras.size(); ++i)
    CHECK(std::memcmp(&posed.cameras[i].to_world, &loaded.cameras[i].to_world, sizeof(glm::mat4)) ==
          0);
  CHECK(posed.cameras_from_file == loaded.cameras_from_file);
  CHECK(same_bytes(posed.view_bounds.lo, loaded.view_bounds.lo));
  CHECK(same_bytes(posed.view_bounds.hi, loaded.view_bounds.hi));
  REQUIRE(posed.lights.size() == loaded.lights.size());
  for (size_t i = 0; i < posed.lights.size(); ++i) {
    CHECK(same_bytes(posed.lights[i].position, loaded.lights[i].position));
    CHECK(same_bytes(posed.lights[i].direction, loaded.lights[i].direction));
  }
}

int floats(GltfWriter& w, const std::vector<float>& v, const char* type, size_t per) {
  return w.add_accessor(w.add_view(v.data(), v.size() * 4), kFloat, v.size() / per, type);
}

// Node 0: a skinned 3 × 2 grid (4 triangles; joints nodes 1 and 2, joint 2 animated) with NORMAL,
// TEXCOORD_0, COLOR_0 and two morph targets (POSITION and NORMAL) whose animated weights reach
// (1, 1) at t = 1, where target 1 puts vertex 1 on vertex 0 (triangle 0 has no area then); its
// material has a normal map, so tangents are generated. Node 3: 40 vertices on a circle of which
// a triangle strip (one triangle repeating an index) uses 5, with NORMAL, TANGENT and TEXCOORD_0,
// scaled in x from 1 to -1 over [0, 2] (flat at t = 1, mirrored after). Node 4: a camera, moving,
// and node 5 under it a point light. `rest_weights`: the mesh's morph weights (the rest pose's);
// `weight_keys`: the animated weights at t = 0, 1 and 2.
std::string posed_file(const TempDir& dir, const char* name,
                       const std::vector<double>& rest_weights = {0.25, 0.5},
                       const std::vector<float>& weight_keys = {0.25f, 0.5f, 1, 1, 0, 0.2f}) {
  GltfWriter w;
  const int texture = add_texture(w, png8(2, 2, 4, kTexels));
  w.add_material({{"normalTexture", {{"index", texture}}},
                  {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", texture}}}}}});
  w.add_material({{"normalTexture", {{"index", texture}}}});

  std::vector<glm::vec3> grid, up(6, glm::vec3(0, 0, 1)), lift(6), shift(6, glm::vec3(0.2f, 0, 0));
  std::vector<float> uv, colors, weights;
  std::vector<uint8_t> joints;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      grid.push_back(glm::vec3(float(x), float(y), 0));
      uv.insert(uv.end(), {float(x) / 2, float(y)});
      colors.insert(colors.end(), {float(x) / 2, float(y), 0.5f, 1});
      joints.insert(joints.end(), {0, 1, 0, 0});
      weights.insert(weights.end(), {1 - float(y), float(y), 0, 0});  // by row: v0, v1 alike
      if (x == 2) lift.back() = glm::vec3(0, 0, 0.3f);
    }
  std::vector<glm::vec3> collapse(6);
  collapse[1] = glm::vec3(-1, 0, 0);  // vertex 1 onto vertex 0 at weight 1
  json grid_attributes = {{"POSITION", w.add_vec3(grid)},
                          {"NORMAL", w.add_vec3(up, false)},
                          {"TEXCOORD_0", floats(w, uv, "VEC2", 2)},
                          {"COLOR_0", floats(w, colors, "VEC4", 4)},
                          {"JOINTS_0", w.add_accessor(w.add_view(joints.data(), joints.size()),
                                                      kUnsignedByte, 6, "VEC4")},
                          {"WEIGHTS_0", floats(w, weights, "VEC4", 4)}};
  const json targets = {
      {{"POSITION", w.add_vec3(lift, false)}, {"NORMAL", w.add_vec3(shift, false)}},
      {{"POSITION", w.add_vec3(collapse, false)}}};
  const int grid_mesh = w.add_mesh(
      {{"attributes", grid_attributes},
       {"indices", w.add_indices(std::vector<uint8_t>{0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4})},
       {"material", 0},
       {"targets", targets}});
  w.doc["meshes"][grid_mesh]["weights"] = rest_weights;

  std::vector<glm::vec3> circle, normals(40, glm::vec3(0, 0, 1));
  std::vector<float> tangents, circle_uv;
  for (int i = 0; i < 40; ++i) {
    const float a = float(i) * 0.157f;
    circle.push_back(glm::vec3(std::cos(a), std::sin(a), 0.1f * float(i % 3)));
    tangents.insert(tangents.end(), {1, 0, 0, i % 2 ? 1.f : -1.f});
    circle_uv.insert(circle_uv.end(), {float(i) / 40, 0.5f});
  }
  const int strip_mesh =
      w.add_mesh({{"attributes",
                   {{"POSITION", w.add_vec3(circle)},
                    {"NORMAL", w.add_vec3(normals, false)},
                    {"TANGENT", floats(w, tangents, "VEC4", 4)},
                    {"TEXCOORD_0", floats(w, circle_uv, "VEC2", 2)}}},
                  {"indices", w.add_indices(std::vector<uint16_t>{3, 17, 29, 29, 8, 35, 12})},
                  {"mode", 5},
                  {"material", 1}});

  glm::mat4 ibm[2] = {glm::mat4(1.f), glm::mat4(1.f)};
  ibm[1][3] = glm::vec4(0, -1, 0, 1);
  w.add_node({{"mesh", grid_mesh}, {"skin", 0}});
  w.add_node({{"children", {2}}});
  w.add_node({{"translation", {0, 1, 0}}});
  w.add_node({{"mesh", strip_mesh}, {"translation", {4, 0, 0}}});
  w.add_node({{"camera", 0}, {"translation", {1, 1, 6}}, {"children", {5}}});
  w.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  w.doc["skins"] = {
      {{"joints", {1, 2}},
       {"inverseBindMatrices", w.add_accessor(w.add_view(ibm, sizeof ibm), kFloat, 2, "MAT4")}}};
  w.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.01}}}}};
  w.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  w.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 5}}};
  w.set_scene({0, 1, 3, 4});

  json samplers = json::array(), channels = json::array();
  auto channel = [&](int node, const char* path, const std::vector<float>& values, const char* type,
                     size_t per) {
    samplers.push_back(
        {{"input", floats(w, {0, 1, 2}, "SCALAR", 1)}, {"output", floats(w, values, type, per)}});
    channels.push_back(
        {{"sampler", samplers.size() - 1}, {"target", {{"node", node}, {"path", path}}}});
  };
  channel(0, "weights", weight_keys, "SCALAR", 1);
  channel(2, "translation", {0, 1, 0, 0.5f, 1.5f, 0.2f, -0.3f, 1, 0}, "VEC3", 3);
  channel(2, "rotation", {0, 0, 0, 1, 0, 0, 0.3827f, 0.9239f, 0.5f, 0.5f, 0.5f, 0.5f}, "VEC4", 4);
  channel(3, "scale", {1, 1, 1, 0, 1, 1, -1, 1, 1}, "VEC3", 3);
  channel(4, "translation", {1, 1, 6, 2, 1, 5, 0, 2, 7}, "VEC3", 3);
  w.doc["animations"] = {{{"samplers", samplers}, {"channels", channels}}};
  return w.write_gltf(dir / name);
}

Scene load_at(const std::string& path, double t) {
  GltfOptions at;
  at.time = t;
  return load_gltf(path, at);
}

const fs::path kSamples = fs::path(DACRT_SOURCE_DIR) / "../shared/khronos-samples";

}  // namespace

TEST_CASE("glTF pose: a pose is bit for bit the scene a fresh load at that time makes") {
  TempDir dir;
  const std::string path = posed_file(dir, "posed.gltf");
  const GltfAnimation file(path);
  Scene scene = file.load();
  check_same(scene, load_gltf(path));
  // Forwards, through the flat and mirrored strip and the collapsed triangle, back, past the end.
  for (double t : {0.0, 0.25, 1.0, 1.5, 2.0, 0.5, 7.0, 1.0}) {
    INFO("t = " << t);
    file.pose(t, scene);
    const Scene fresh = load_at(path, t);
    check_same(scene, fresh);
    if (t == 1.0) CHECK(scene.degenerate_triangles > 0);  // the collapse and the flat strip
  }
  CHECK(!scene.tangents.empty());
  CHECK(!scene.colors.empty());
}

TEST_CASE("glTF pose: the Khronos samples' poses equal fresh loads bit for bit") {
  size_t compared = 0;
  for (const char* name : {"CesiumMan", "BrainStem", "AnimatedMorphCube", "RiggedFigure"}) {
    const fs::path glb = kSamples / name / "glTF-Binary" / (std::string(name) + ".glb");
    if (!fs::exists(glb)) continue;
    INFO(name);
    const GltfAnimation file(glb.string());
    Scene scene = file.load();
    for (double t : {0.4, 1.25}) {
      INFO("t = " << t);
      file.pose(t, scene);
      check_same(scene, load_at(glb.string(), t));
    }
    ++compared;
  }
  if (compared == 0) MESSAGE("skipped: the Khronos samples are not at " << kSamples.string());
}

TEST_CASE(
    "glTF pose: the file is decoded once, and a pose reads no accessor and decompresses nothing") {
  TempDir dir;
  const fs::path seeds = fs::path(DACRT_SOURCE_DIR) / "fuzz" / "seeds-gltf";
  for (const std::string& path :
       {posed_file(dir, "posed.gltf"), (seeds / "seed-meshopt-indices-animation.glb").string(),
        (seeds / "seed-draco-edgebreaker.glb").string(),
        (seeds / "seed-meshopt-attributes.glb").string()}) {
    INFO(path);
    const GltfAnimation file(path);
    Scene scene = file.load();
    const uint64_t loaded = file.decodes();
    CHECK(loaded > 0);
    for (double t : {0.3, 1.0, 1.7, 0.0}) {
      file.pose(t, scene);
      CHECK(file.decodes() == loaded);
    }
    // The counter sees reads: a file kept for one load only reads its accessors again to pose
    // (its decompressed bufferViews and primitives are kept all the same).
    const GltfAnimation once(path, {}, false);
    Scene other = once.load();
    const uint64_t before = once.decodes();
    once.pose(0.5, other);
    CHECK(once.decodes() > before);
    check_same(other, load_at(path, 0.5));
  }
}

TEST_CASE("glTF pose: a morph target of weight 0 so far is read the first time a pose weighs it") {
  TempDir dir;
  // Target 0 weighs 0 at rest and at t = 0, 0.5 at t = 1; target 1 weighs 0.5 throughout.
  const std::string path =
      posed_file(dir, "zero.gltf", {0.0, 0.5}, {0, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f});
  const GltfAnimation file(path);
  Scene scene = file.load();
  const uint64_t loaded = file.decodes();
  file.pose(0.0, scene);
  CHECK(file.decodes() == loaded);  // still weight 0: not read
  file.pose(1.0, scene);
  CHECK(file.decodes() == loaded + 2);  // target 0's POSITION and NORMAL deltas, once
  check_same(scene, load_at(path, 1.0));
  file.pose(1.5, scene);
  CHECK(file.decodes() == loaded + 2);
  check_same(scene, load_at(path, 1.5));
}
