// Decoding that a test on normals or translations alone cannot see wrong: normalized BYTE and
// SHORT texture coordinates at their extremes (max(c / 127, −1), max(c / 32767, −1): exactly 1
// and −1, which c / 128 would miss); EXT_meshopt_compression animation outputs under the
// QUATERNION and EXPONENTIAL filters (encoded here by meshoptimizer); and a skin whose joint
// turns as well as moves, where jointMatrix = globalTransform(joint) × inverseBindMatrix, in that
// order, and the skinned mesh's own node transform is ignored.
#include <doctest/doctest.h>
#include <meshoptimizer.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "dacrt/io/gltf.h"
#include "dacrt/io/gltf/file.h"
#include "dacrt/io/gltf/internal.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

constexpr int kByte = 5120, kShort = 5122;

int floats(GltfWriter& w, const std::vector<float>& v, const char* type, size_t per) {
  return w.add_accessor(w.add_view(v.data(), v.size() * 4), kFloat, v.size() / per, type);
}

// The unit quad (texture_fixtures.h) with TEXCOORD_0 given as normalized `type` integers `uv` (two
// a vertex, padded to 4-byte elements), under KHR_mesh_quantization.
template <class T>
Scene quad_with_uv(const TempDir& dir, int type, const std::vector<T>& uv, const char* name) {
  GltfWriter w = quad_file({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  w.doc["extensionsUsed"] = w.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  add_texture(w, png8(2, 2, 4, kTexels));
  std::vector<T> padded;
  for (size_t v = 0; v < 4; ++v) {
    padded.push_back(uv[2 * v]), padded.push_back(uv[2 * v + 1]);
    while (padded.size() * sizeof(T) % 4) padded.push_back(0);
  }
  const size_t stride = padded.size() * sizeof(T) / 4;
  const int accessor = w.add_accessor(
      w.add_view(padded.data(), padded.size() * sizeof(T), int(stride)), type, 4, "VEC2");
  w.doc["accessors"][accessor]["normalized"] = true;
  w.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = accessor;
  return load_gltf(w.write_glb(dir / name));
}

}  // namespace

TEST_CASE("normalized BYTE and SHORT texture coordinates: 127 and 32767 are 1, -127 and -128 -1") {
  TempDir dir("gltf-normalized-uv");
  // Vertices 0..3 of triangles (0, 1, 2) and (0, 2, 3): corners 0, 1, 2 are vertices 0, 1, 2
  // and corner 5 is vertex 3.
  const Scene bytes =
      quad_with_uv<int8_t>(dir, kByte, {127, -127, -128, 127, 0, -128, 64, 1}, "byte.glb");
  REQUIRE(bytes.texcoords[0].size() == 6);
  CHECK(bytes.texcoords[0][0] == glm::vec2(1.f, -1.f));
  CHECK(bytes.texcoords[0][1] == glm::vec2(-1.f, 1.f));
  CHECK(bytes.texcoords[0][2] == glm::vec2(0.f, -1.f));
  CHECK(bytes.texcoords[0][5] == glm::vec2(64.f / 127.f, 1.f / 127.f));
  const Scene shorts = quad_with_uv<int16_t>(
      dir, kShort, {32767, -32767, -32768, 32767, 0, -32768, 16384, 1}, "short.glb");
  REQUIRE(shorts.texcoords[0].size() == 6);
  CHECK(shorts.texcoords[0][0] == glm::vec2(1.f, -1.f));
  CHECK(shorts.texcoords[0][1] == glm::vec2(-1.f, 1.f));
  CHECK(shorts.texcoords[0][2] == glm::vec2(0.f, -1.f));
  CHECK(shorts.texcoords[0][5] == glm::vec2(16384.f / 32767.f, 1.f / 32767.f));
}

namespace {

// A triangle at (0.6, 0, 0) whose node is animated over [0, 1] by two meshopt-compressed
// channels: a rotation of 0 to 90° about Z (normalized SHORT quaternions, QUATERNION filter,
// `bits` bits) and a translation between `moves` (FLOAT VEC3, EXPONENTIAL filter, 24 bits).
std::string meshopt_animation(const TempDir& dir, int bits, const std::vector<float>& moves) {
  GltfWriter w;
  w.doc["extensionsUsed"] = w.doc["extensionsRequired"] = {"EXT_meshopt_compression"};
  const int node = w.add_triangles({{0.6f, 0.f, 0.f}, {0.7f, 0.f, 0.f}, {0.6f, 0.1f, 0.f}});
  const int times = floats(w, {0, 1}, "SCALAR", 1);
  const float h = std::sqrt(0.5f);
  const std::vector<float> turns = {0, 0, 0, 1, 0, 0, h, h};
  std::vector<unsigned char> quats(16), exps(24);
  meshopt_encodeFilterQuat(quats.data(), 2, 8, bits, turns.data());
  meshopt_encodeFilterExp(exps.data(), 2, 12, 24, moves.data());
  // Each filtered stream compressed as ATTRIBUTES into buffer 0; its bufferView is in buffer 1,
  // the fallback that has no data.
  json& views = w.doc["bufferViews"];
  uint64_t fallback = 0;
  auto compressed = [&](const std::vector<unsigned char>& raw, size_t stride, const char* filter) {
    std::vector<unsigned char> out(meshopt_encodeVertexBufferBound(2, stride));
    out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), raw.data(), 2, stride));
    REQUIRE(!out.empty());
    const int view = w.add_view(out.data(), out.size());
    const json ext = {{"buffer", 0},
                      {"byteOffset", views[view]["byteOffset"]},
                      {"byteLength", out.size()},
                      {"byteStride", stride},
                      {"count", 2},
                      {"mode", "ATTRIBUTES"},
                      {"filter", filter}};
    views[view] = {{"buffer", 1},
                   {"byteOffset", fallback},
                   {"byteLength", 2 * stride},
                   {"extensions", {{"EXT_meshopt_compression", ext}}}};
    fallback += 2 * stride;
    return view;
  };
  const int rotation = w.add_accessor(compressed(quats, 8, "QUATERNION"), kShort, 2, "VEC4");
  w.doc["accessors"][rotation]["normalized"] = true;
  const int translation = w.add_accessor(compressed(exps, 12, "EXPONENTIAL"), kFloat, 2, "VEC3");
  w.doc["animations"] = {
      {{"samplers",
        {{{"input", times}, {"output", rotation}}, {{"input", times}, {"output", translation}}}},
       {"channels",
        {{{"sampler", 0}, {"target", {{"node", node}, {"path", "rotation"}}}},
         {{"sampler", 1}, {"target", {{"node", node}, {"path", "translation"}}}}}}}};
  w.more_buffers = {{{"byteLength", fallback},
                     {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
  return w.write_glb(dir / ("meshopt-" + std::to_string(bits) + ".glb"));
}

}  // namespace

TEST_CASE("EXT_meshopt_compression: QUATERNION and EXPONENTIAL filtered animation channels") {
  TempDir dir("gltf-meshopt-animation");
  // Exactly representable in 24-bit mantissas under one exponent a vector: decoded exactly.
  const std::vector<float> moves = {0.25f, -3.5f, 10.f, -0.5f, 1.75f, 0.125f};
  for (const int bits : {8, 12, 16}) {
    INFO(bits << "-bit quaternions");
    const std::string path = meshopt_animation(dir, bits, moves);
    const tinygltf::Model model = read_gltf_model(path);
    const gltf::Gltf file(path, model);
    const std::vector<gltf::Animation> animations = gltf::read_animations(file);
    REQUIRE(animations.size() == 1);
    // The quaternion filter's precision: its components within 1 / (2^(bits-1) - 1) of √½.
    const double step = 1.0 / ((1 << (bits - 1)) - 1);
    float q[4];
    gltf::sample(animations[0].samplers[0], 1.0, true, q);
    CHECK(std::abs(q[0]) < step);
    CHECK(std::abs(q[1]) < step);
    CHECK(q[2] == doctest::Approx(std::sqrt(0.5)).epsilon(step));
    CHECK(q[3] == doctest::Approx(std::sqrt(0.5)).epsilon(step));
    gltf::sample(animations[0].samplers[0], 0.0, true, q);
    CHECK(q[3] == doctest::Approx(1.0).epsilon(step));
    // Halfway, slerp gives 45°: the angle 2·atan2(|xyz|, w).
    gltf::sample(animations[0].samplers[0], 0.5, true, q);
    const double angle = 2.0 * std::atan2(std::hypot(q[0], q[1], q[2]), double(q[3]));
    CHECK(angle == doctest::Approx(M_PI / 4).epsilon(4 * step));
    // The exponential filter's values come back exactly.
    CHECK(animations[0].samplers[1].output == moves);

    // Posed at t = 0.5: (0.6, 0, 0) turned by 45° and moved by the midpoint of the moves.
    GltfOptions at;
    at.time = 0.5;
    const Scene scene = load_gltf(path, at);
    REQUIRE(scene.geometry.size() == 1);
    const glm::vec3 p = scene.geometry.vertex(0, 0);
    const double r = 0.6 * std::sqrt(0.5);
    CHECK(p.x == doctest::Approx(r + (0.25 - 0.5) / 2).epsilon(4 * step));
    CHECK(p.y == doctest::Approx(r + (-3.5 + 1.75) / 2).epsilon(4 * step));
    CHECK(p.z == doctest::Approx((10 + 0.125) / 2).epsilon(1e-6));
  }
}

TEST_CASE("skins: a turned and moved joint places its vertices by global(joint) × inverse bind") {
  TempDir dir("gltf-skin-order");
  // Joint 0 is node 1 (a root, turned 30° about Z and moved), joint 1 its child node 2 (moved
  // along its parent's X); the inverse bind matrices are the inverses of their rest transforms.
  // At t = 1 node 2 is turned 90° about Z and moved to (0.3, 0.1, 0): rotation and translation do
  // not commute, so the product's order shows. Every vertex weighs joint 0 by 0.25, joint 1 by
  // 0.75. The skinned mesh's node (0) has a transform the spec says to ignore.
  const glm::dquat turn30 = glm::angleAxis(glm::radians(30.0), glm::dvec3(0, 0, 1));
  const glm::dquat turn90 = glm::angleAxis(glm::radians(90.0), glm::dvec3(0, 0, 1));
  auto trs = [](glm::dvec3 t, glm::dquat r) {
    return glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(r);
  };
  const glm::dmat4 rest1 = trs({0.1, 0.2, 0}, turn30);
  const glm::dmat4 rest2 = rest1 * trs({0.2, 0, 0}, glm::dquat(1, 0, 0, 0));
  const glm::dmat4 posed2 = rest1 * trs({0.3, 0.1, 0}, turn90);
  const std::vector<glm::vec3> triangle = {{0.5f, 0.f, 0.f}, {0.6f, 0.f, 0.f}, {0.5f, 0.1f, 0.f}};

  GltfWriter w;
  const std::vector<uint8_t> joints = {0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
  const std::vector<float> weights = {0.25f, 0.75f, 0, 0, 0.25f, 0.75f, 0, 0, 0.25f, 0.75f, 0, 0};
  const int mesh =
      w.add_mesh(json{{"attributes",
                       {{"POSITION", w.add_vec3(triangle)},
                        {"JOINTS_0", w.add_accessor(w.add_view(joints.data(), joints.size()),
                                                    kUnsignedByte, 3, "VEC4")},
                        {"WEIGHTS_0", floats(w, weights, "VEC4", 4)}}}});
  const glm::mat4 ibm[2] = {glm::mat4(glm::inverse(rest1)), glm::mat4(glm::inverse(rest2))};
  const int ibm_accessor = w.add_accessor(w.add_view(ibm, sizeof ibm), kFloat, 2, "MAT4");
  const glm::dquat q30 = turn30;
  w.add_node(
      {{"mesh", mesh}, {"skin", 0}, {"translation", {5, 5, 0}}, {"rotation", {0, 0.6, 0, 0.8}}});
  w.add_node({{"children", {2}},
              {"translation", {0.1, 0.2, 0}},
              {"rotation", {q30.x, q30.y, q30.z, q30.w}}});
  w.add_node({{"translation", {0.2, 0, 0}}});
  w.doc["skins"] = {{{"joints", {1, 2}}, {"inverseBindMatrices", ibm_accessor}}};
  w.set_scene({0, 1});
  const float h = std::sqrt(0.5f);
  const int times = floats(w, {0, 1}, "SCALAR", 1);
  w.doc["animations"] = {
      {{"samplers",
        {{{"input", times}, {"output", floats(w, {0, 0, 0, 1, 0, 0, h, h}, "VEC4", 4)}},
         {{"input", times}, {"output", floats(w, {0.2f, 0, 0, 0.3f, 0.1f, 0}, "VEC3", 3)}}}},
       {"channels",
        {{{"sampler", 0}, {"target", {{"node", 2}, {"path", "rotation"}}}},
         {{"sampler", 1}, {"target", {{"node", 2}, {"path", "translation"}}}}}}}};
  const std::string path = w.write_gltf(dir / "skin.gltf");

  auto check = [&](std::optional<double> t, const glm::dmat4& joint2) {
    INFO("t = " << (t ? *t : -1.0));
    GltfOptions o;
    o.time = t;
    const Scene scene = load_gltf(path, o);
    REQUIRE(scene.geometry.size() == 1);
    const glm::dmat4 j0 = rest1 * glm::inverse(rest1), j1 = joint2 * glm::inverse(rest2);
    const glm::dmat4 wrong = glm::inverse(rest2) * joint2;  // the product the other way
    for (int k = 0; k < 3; ++k) {
      const glm::dvec4 v(triangle[size_t(k)], 1.0);
      const glm::dvec3 expected = glm::dvec3(0.25 * (j0 * v) + 0.75 * (j1 * v));
      const glm::dvec3 other = glm::dvec3(0.25 * (j0 * v) + 0.75 * (wrong * v));
      const glm::dvec3 got(scene.geometry.vertex(0, k));
      INFO("vertex " << k << ": got " << got.x << ", " << got.y << ", expected " << expected.x
                     << ", " << expected.y);
      CHECK(glm::length(got - expected) < 1e-5);
      if (t) CHECK(glm::length(other - expected) > 0.05);  // the test can tell the orders apart
    }
  };
  check(std::nullopt, rest2);  // the bind pose: the mesh as it is
  check(1.0, posed2);
}
