// glTF animation: node TRS channels (STEP, LINEAR with slerp, CUBICSPLINE), skins and morph
// targets evaluated at a time, checked against hand-computed values both on the samplers and on
// rendered images (where a small quad lands); default morph weights at rest; the errors a
// malformed animation or skin gives, naming the element.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

#include "captured_stderr.h"
#include "gltf_writer.h"
#include "dacrt/io/gltf.h"
#include "dacrt/io/gltf/internal.h"
#include "render_check.h"
#include "temp_dir.h"
#include "test_geometry.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

// A square of side 0.3 centred on the origin in the z = 0 plane, facing +Z.
const std::vector<glm::vec3> kQuad = {{-0.15f, -0.15f, 0}, {0.15f, -0.15f, 0}, {0.15f, 0.15f, 0},
                                      {-0.15f, -0.15f, 0}, {0.15f, 0.15f, 0},  {-0.15f, 0.15f, 0}};

int floats(GltfWriter& w, const std::vector<float>& v, const char* type, size_t per) {
  return w.add_accessor(w.add_view(v.data(), v.size() * 4), kFloat, v.size() / per, type);
}

// Adds an animation of one channel: node `node`'s `path` by a sampler of `times` and `values`.
void animate(GltfWriter& w, int node, const char* path, const char* interpolation,
             const std::vector<float>& times, const std::vector<float>& values, const char* type,
             size_t per) {
  const int in = floats(w, times, "SCALAR", 1), out = floats(w, values, type, per);
  w.doc["animations"].push_back(
      {{"samplers", {{{"input", in}, {"output", out}, {"interpolation", interpolation}}}},
       {"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}}}}});
}

// Where the quad lands: the centroid of the pixels it covers in a 40 × 40 albedo render of
// [-1, 1]² seen straight down -Z by an orthographic camera (a pixel is 0.05 wide).
glm::vec2 centroid(Scene scene) {
  Camera cam = looking_at(glm::vec3(0, 0, 3), glm::vec3(0), 1.f);
  cam.orthographic = true;
  cam.ymag = 1.f;
  scene.cameras = {cam};
  RenderSettings s;
  s.width = s.height = 40, s.spp = 1, s.max_depth = 0;
  Result r = render(scene, s, "dacrt", "albedo");
  glm::dvec2 sum(0.0);
  int n = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x)
      if (r.film.mean_and_error(size_t(y) * 40 + size_t(x)).x > 0.5)
        sum += glm::dvec2((x + 0.5) / 20.0 - 1.0, 1.0 - (y + 0.5) / 20.0), ++n;
  REQUIRE(n > 0);
  return glm::vec2(sum / double(n));
}

Scene at(const std::string& path, std::optional<double> t) {
  GltfOptions o;
  o.time = t;
  return load_gltf(path, o);
}

void check_lands(const std::string& path, std::optional<double> t, glm::vec2 expected) {
  INFO("t = " << (t ? *t : -1.0) << ", expected " << expected.x << ", " << expected.y);
  const glm::vec2 c = centroid(at(path, t));
  INFO("landed at " << c.x << ", " << c.y);
  CHECK(std::abs(c.x - expected.x) < 0.03f);
  CHECK(std::abs(c.y - expected.y) < 0.03f);
}

gltf::AnimationSampler sampler(gltf::Interpolation i, std::vector<float> in,
                               std::vector<float> out, size_t components) {
  gltf::AnimationSampler s;
  s.interpolation = i;
  s.input = std::move(in);
  s.output = std::move(out);
  s.components = components;
  return s;
}

float value_at(const gltf::AnimationSampler& s, double t) {
  float v[4];
  gltf::sample(s, t, false, v);
  return v[0];
}

}  // namespace

TEST_CASE("animation samplers: STEP, LINEAR and CUBICSPLINE give the spec's values") {
  using gltf::Interpolation;
  const auto step = sampler(Interpolation::step, {1, 2, 4}, {10, 20, 40}, 1);
  CHECK(value_at(step, 0.0) == 10.f);  // before the first keyframe: held
  CHECK(value_at(step, 1.5) == 10.f);
  CHECK(value_at(step, 2.0) == 20.f);
  CHECK(value_at(step, 3.99) == 20.f);
  CHECK(value_at(step, 9.0) == 40.f);  // after the last: held
  const auto linear = sampler(Interpolation::linear, {1, 2, 4}, {10, 20, 40}, 1);
  CHECK(value_at(linear, 1.25) == doctest::Approx(12.5));
  CHECK(value_at(linear, 3.0) == doctest::Approx(30.0));
  CHECK(value_at(linear, 0.5) == 10.f);
  // Cubic: (a_k, v_k, b_k) per keyframe; on [0, 2] from v 0 (out-tangent 3) to v 4 (in-tangent
  // -1): at s = 0.25, td = 2: h00 0.84375, h10 0.140625, h01 0.15625, h11 -0.046875:
  // 0 + 0.140625·2·3 + 0.15625·4 + -0.046875·2·(-1) = 0.84375 + 0.625 + 0.09375 = 1.5625.
  const auto cubic = sampler(Interpolation::cubic, {0, 2}, {9, 0, 3, -1, 4, 9}, 1);
  CHECK(value_at(cubic, 0.5) == doctest::Approx(1.5625));
  CHECK(value_at(cubic, 0.0) == 0.f);
  CHECK(value_at(cubic, 2.0) == 4.f);
  CHECK(value_at(cubic, 3.0) == 4.f);
  // Rotations: slerp along the shorter arc, a quarter of the way from 0 to 180° about Z is 45°
  // (a normalised lerp would give 36.9°); q and -q are the same rotation.
  const float h = std::sqrt(0.5f);
  const auto turn = sampler(Interpolation::linear, {0, 1}, {0, 0, 0, 1, 0, 0, 1, 0}, 4);
  float q[4];
  gltf::sample(turn, 0.25, true, q);
  CHECK(q[2] == doctest::Approx(std::sin(M_PI / 8)));
  CHECK(q[3] == doctest::Approx(std::cos(M_PI / 8)));
  const auto shorter = sampler(Interpolation::linear, {0, 1}, {0, 0, 0, 1, 0, 0, -h, -h}, 4);
  gltf::sample(shorter, 0.5, true, q);  // 0 to 90° (given as its negation): 45°, not -135°
  CHECK(q[2] * q[3] > 0.f);
  CHECK(std::abs(q[2]) == doctest::Approx(std::sin(M_PI / 8)));
  // A cubic rotation comes out normalised.
  const auto cubic_turn =
      sampler(Interpolation::cubic, {0, 1}, {0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                             h, h, 0, 0, 0, 0},
              4);
  gltf::sample(cubic_turn, 0.5, true, q);
  CHECK(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] == doctest::Approx(1.0));
}

TEST_CASE("animation: a node's translation lands the quad where STEP, LINEAR and CUBICSPLINE say") {
  TempDir dir;
  // x from 0 at t = 0 to 0.8 at t = 1; cubic with out-tangent 2.4 and in-tangent 0: at t = 0.5,
  // 0.5·0 + 0.125·2.4 + 0.5·0.8 = 0.7; linear 0.4; step 0.
  struct Case {
    const char* interpolation;
    std::vector<float> values;
    float at_half;
  };
  for (const Case& c : {Case{"STEP", {0, 0, 0, 0.8f, 0, 0}, 0.f},
                        Case{"LINEAR", {0, 0, 0, 0.8f, 0, 0}, 0.4f},
                        Case{"CUBICSPLINE", {0, 0, 0, 0, 0, 0, 2.4f, 0, 0,  //
                                             0, 0, 0, 0.8f, 0, 0, 0, 0, 0},
                             0.7f}}) {
    INFO(c.interpolation);
    GltfWriter w;
    const int node = w.add_triangles(kQuad);
    w.doc["nodes"][node]["translation"] = {-0.5, 0.25, 0};  // replaced by the channel
    animate(w, node, "translation", c.interpolation, {0, 1}, c.values, "VEC3", 3);
    const std::string path = w.write_gltf(dir / (std::string(c.interpolation) + ".gltf"));
    check_lands(path, std::nullopt, {-0.5f, 0.25f});  // rest: the node's own
    check_lands(path, 0.5, {c.at_half, 0.f});
    check_lands(path, 1.0, {0.8f, 0.f});
    check_lands(path, 7.0, {0.8f, 0.f});  // held after the end
  }
}

TEST_CASE("animation: rotation slerps and scale scales, about the node's origin") {
  TempDir dir;
  GltfWriter w;
  // The quad sits 0.6 along +X in its mesh; its node turns it 0 to 180° about Z over [0, 1].
  std::vector<glm::vec3> moved = kQuad;
  for (glm::vec3& p : moved) p.x += 0.6f;
  const int node = w.add_triangles(moved);
  animate(w, node, "rotation", "LINEAR", {0, 1}, {0, 0, 0, 1, 0, 0, 1, 0}, "VEC4", 4);
  const std::string path = w.write_gltf(dir / "turn.gltf");
  const float r = 0.6f;
  check_lands(path, 0.0, {r, 0.f});
  check_lands(path, 0.25, {r * std::cos(float(M_PI) / 4), r * std::sin(float(M_PI) / 4)});
  check_lands(path, 0.5, {0.f, r});

  GltfWriter s;
  const int scaled = s.add_triangles(moved);
  animate(s, scaled, "scale", "LINEAR", {0, 2}, {1, 1, 1, 0.5f, 2, 1}, "VEC3", 3);
  const std::string spath = s.write_gltf(dir / "scale.gltf");
  check_lands(spath, 1.0, {0.6f * 0.75f, 0.f});  // scale (0.75, 1.5): centre x 0.45
}

TEST_CASE("morph targets: default weights apply at rest, node weights win, animated weights at t") {
  TempDir dir;
  GltfWriter w;
  const int position = w.add_vec3(kQuad);
  const int delta = w.add_vec3(std::vector<glm::vec3>(6, glm::vec3(0.6f, 0, 0)), false);
  const int mesh = w.add_mesh(
      GltfWriter::primitive(position, {{"targets", {{{"POSITION", delta}}}}}));
  w.doc["meshes"][mesh]["weights"] = {1.0};
  const int node = w.add_node({{"mesh", mesh}});
  w.set_scene({node});
  const std::string rest = w.write_gltf(dir / "rest.gltf");
  // The mesh's default weight 1 moves the quad by the whole delta, with or without --time.
  check_lands(rest, std::nullopt, {0.6f, 0.f});
  check_lands(rest, 3.0, {0.6f, 0.f});
  // The node's weights replace the mesh's.
  w.doc["nodes"][node]["weights"] = {0.5};
  const std::string half = w.write_gltf(dir / "half.gltf");
  check_lands(half, std::nullopt, {0.3f, 0.f});
  // An animated weight, 0 to 1 over [0, 1].
  animate(w, node, "weights", "LINEAR", {0, 1}, {0, 1}, "SCALAR", 1);
  const std::string animated = w.write_gltf(dir / "animated.gltf");
  check_lands(animated, std::nullopt, {0.3f, 0.f});  // rest: the node's 0.5
  check_lands(animated, 0.25, {0.15f, 0.f});
  check_lands(animated, 0.75, {0.45f, 0.f});
  CHECK(at(animated, std::nullopt).ignored.unmorphed_primitives == 0);
}

TEST_CASE("morph targets of TEXCOORD or COLOR are not read, and the loader says so") {
  TempDir dir;
  GltfWriter w;
  const int position = w.add_vec3(kQuad);
  const int delta = w.add_vec3(std::vector<glm::vec3>(6, glm::vec3(0.6f, 0, 0)), false);
  const std::vector<float> uv(12, 0.5f);
  const int uvs = floats(w, uv, "VEC2", 2);
  const int mesh = w.add_mesh(GltfWriter::primitive(
      position, {{"targets", {{{"POSITION", delta}, {"TEXCOORD_0", uvs}}}}}));
  w.doc["meshes"][mesh]["primitives"][0]["attributes"]["TEXCOORD_0"] = uvs;
  w.doc["meshes"][mesh]["weights"] = {1.0};
  w.set_scene({w.add_node({{"mesh", mesh}})});
  const std::string path = w.write_gltf(dir / "uv-morph.gltf");
  CapturedStderr err;
  const Scene scene = at(path, std::nullopt);
  check_lands(path, std::nullopt, {0.6f, 0.f});  // POSITION still morphs
  const std::string text = err.text();
  CHECK(scene.ignored.unmorphed_primitives == 1);
  CHECK(text.find("1 primitives whose morph targets move TEXCOORD or COLOR") != std::string::npos);
}

namespace {

// A skinned quad: joint 0 (node 1) at the origin, joint 1 (node 2) bound at (0.2, 0, 0) and
// animated to (0.7, 0.3, 0) at t = 1; every vertex weighs joint 0 by 1 - w1 and joint 1 by w1.
// The skinned node (0) has a translation the spec says to ignore.
std::string skinned(const TempDir& dir, float w1, const char* name, json edit = json::object()) {
  GltfWriter w;
  const int position = w.add_vec3(kQuad);
  const std::vector<uint8_t> joints(6 * 4, 0);
  std::vector<uint8_t> j = joints;
  std::vector<float> weights;
  for (int v = 0; v < 6; ++v) {
    j[size_t(4 * v + 1)] = 1;
    weights.insert(weights.end(), {1 - w1, w1, 0, 0});
  }
  const int ja = w.add_accessor(w.add_view(j.data(), j.size()), kUnsignedByte, 6, "VEC4");
  const int wa = floats(w, weights, "VEC4", 4);
  const int mesh = w.add_mesh(json{{"attributes", {{"POSITION", position}, {"JOINTS_0", ja},
                                                   {"WEIGHTS_0", wa}}}});
  glm::mat4 ibm[2] = {glm::mat4(1.f), glm::mat4(1.f)};
  ibm[1][3] = glm::vec4(-0.2f, 0, 0, 1);
  const int ibm_accessor = w.add_accessor(w.add_view(ibm, sizeof ibm), kFloat, 2, "MAT4");
  w.add_node({{"mesh", mesh}, {"skin", 0}, {"translation", {5, 5, 0}}});
  w.add_node({{"children", {2}}});
  w.add_node({{"translation", {0.2, 0, 0}}});
  w.doc["skins"] = {{{"joints", {1, 2}}, {"inverseBindMatrices", ibm_accessor}}};
  w.set_scene({0, 1});
  animate(w, 2, "translation", "LINEAR", {0, 1}, {0.2f, 0, 0, 0.7f, 0.3f, 0}, "VEC3", 3);
  w.doc.merge_patch(edit);
  return w.write_gltf(dir / name);
}

}  // namespace

TEST_CASE("skins: vertices follow their joints by their weights, the mesh node's transform ignored") {
  TempDir dir;
  const std::string whole = skinned(dir, 1.f, "whole.gltf");
  check_lands(whole, std::nullopt, {0.f, 0.f});  // at the bind pose: where the mesh says
  check_lands(whole, 1.0, {0.5f, 0.3f});        // joint 1 moved by (0.5, 0.3)
  check_lands(whole, 0.5, {0.25f, 0.15f});
  // Weights 0.75 and 0.25: a quarter of joint 1's move (equal weights would give half).
  const std::string quarter = skinned(dir, 0.25f, "quarter.gltf");
  check_lands(quarter, 1.0, {0.125f, 0.075f});
}

TEST_CASE("skins and animations: malformed ones are refused, naming the element") {
  TempDir dir;
  auto refused = [&](const std::string& path, const std::string& needle) {
    INFO(path);
    try {
      load_gltf(path);
      FAIL("loaded");
    } catch (const Error& e) {
      const std::string what = e.what();
      INFO(what);
      CHECK(what.find(needle) != std::string::npos);
      CHECK(what.find('\n') == std::string::npos);
    }
  };
  refused(skinned(dir, 1.f, "joint.gltf", {{"skins", {{{"joints", {1, 9}}}}}}),
          "/skins/0/joints/1: 9 is not an index");
  refused(skinned(dir, 1.f, "path.gltf",
                  {{"animations", {{{"channels", {{{"sampler", 0},
                                                   {"target", {{"node", 2}, {"path", "x"}}}}}}}}}}),
          "animations[0].channels[0].target.path");
  refused(skinned(dir, 1.f, "sampler.gltf",
                  {{"animations", {{{"channels", {{{"sampler", 3},
                                                   {"target", {{"node", 2}, {"path", "scale"}}}}}}}}}}),
          "animations[0].channels[0].sampler");
  // Times must increase: both keyframes at 0.
  {
    GltfWriter w;
    const int node = w.add_triangles(kQuad);
    animate(w, node, "translation", "LINEAR", {0, 0}, {0, 0, 0, 1, 0, 0}, "VEC3", 3);
    refused(w.write_gltf(dir / "times.gltf"), "animations[0].samplers[0].input: time 1");
  }
  // Output count: 2 keyframes need 2 VEC3s (6 for CUBICSPLINE).
  {
    GltfWriter w;
    const int node = w.add_triangles(kQuad);
    animate(w, node, "translation", "CUBICSPLINE", {0, 1}, {0, 0, 0, 1, 0, 0}, "VEC3", 3);
    refused(w.write_gltf(dir / "count.gltf"), "animations[0].samplers[0].output");
  }
  // Rotation output must be VEC4.
  {
    GltfWriter w;
    const int node = w.add_triangles(kQuad);
    animate(w, node, "rotation", "LINEAR", {0, 1}, {0, 0, 0, 1, 0, 0}, "VEC3", 3);
    refused(w.write_gltf(dir / "vec4.gltf"), "animations[0].samplers[0].output");
  }
  // A joint index past the skin's joints.
  {
    const std::string path = skinned(dir, 1.f, "index.gltf", {{"skins", {{{"joints", {1}}}}}});
    refused(path, "names joint 1, but the skin has 1");
  }
  // Keyframes are bounded before they are read: 2^27 times without a bufferView (zeros).
  {
    GltfWriter w;
    const int node = w.add_triangles(kQuad);
    animate(w, node, "translation", "STEP", {0, 1}, {0, 0, 0, 1, 0, 0}, "VEC3", 3);
    w.doc["accessors"][1] = {{"componentType", kFloat}, {"count", 1 << 27}, {"type", "SCALAR"}};
    refused(w.write_gltf(dir / "huge.gltf"),
            "animations[0].samplers[0] brings the file's keyframes to more than");
  }
  // Weights for a mesh without targets.
  {
    GltfWriter w;
    const int node = w.add_triangles(kQuad);
    animate(w, node, "weights", "LINEAR", {0, 1}, {0, 1}, "SCALAR", 1);
    refused(w.write_gltf(dir / "weights.gltf"), "animations[0].channels[0].target.node");
  }
}
