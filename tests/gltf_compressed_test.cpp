// glTF as the optimisers publish it: KHR_mesh_quantization, EXT_meshopt_compression and
// KHR_draco_mesh_compression. Files made by gltfpack and glTF-Transform (tests/published/) render
// like their original; small files encoded here by the same libraries load exactly; broken
// streams and sizes are one Error line naming the element, refused before they are allocated.
#include <doctest/doctest.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "dacrt/io/gltf.h"
#include "dacrt/render/render_job.h"
#include "tests/allocations.h"
#include "tests/gltf_check.h"
#include "tests/gltf_writer.h"
#include "tests/png.h"
#include "tests/temp_dir.h"
#include "tests/texture_fixtures.h"
#include "dacrt/util/error.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

constexpr int kByte = 5120, kShort = 5122;

std::vector<unsigned char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The image of `scene` (its first camera, 48 × 48, 16 samples, seed 1), as pixel means.
std::vector<double> image(const Scene& scene) {
  RenderSettings s;
  s.width = s.height = 48, s.spp = 16, s.seed = 1;
  auto backend = Backend::create("dacrt", scene.geometry);
  RenderJob job(scene, *backend, s);
  Film film = job.film();
  Progress quiet("test", 1, false);
  job.run(film, 0, uint32_t(s.spp), quiet);
  std::vector<double> means(film.pixels());
  for (size_t p = 0; p < film.pixels(); ++p) means[p] = film.mean_and_error(p).x;
  return means;
}

// Σ |a − b| / Σ |b|.
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0.0, sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) diff += std::abs(a[i] - b[i]), sum += std::abs(b[i]);
  return diff / sum;
}

// A quad (two triangles) as it should load: for comparing files whose encoders may reorder.
const std::vector<glm::vec3> kQuad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
const std::vector<uint16_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

// The loaded scene's corners, sorted, against the quad's.
void check_quad(const Scene& scene) {
  REQUIRE(scene.geometry.size() == 2);
  std::vector<std::array<float, 3>> got, want;
  for (size_t t = 0; t < 2; ++t)
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 v = scene.geometry.vertex(t, k);
      got.push_back({v.x, v.y, v.z});
      const glm::vec3 w = kQuad[kQuadIndices[t * 3 + size_t(k)]];
      want.push_back({w.x, w.y, w.z});
    }
  std::sort(got.begin(), got.end());
  std::sort(want.begin(), want.end());
  CHECK(got == want);
  CHECK(scene.geometry.area(0) + scene.geometry.area(1) == doctest::Approx(1.0));
}

// A writer whose file uses KHR_mesh_quantization (and `more` extensions), all required.
GltfWriter quantized(std::vector<std::string> more = {}) {
  GltfWriter w;
  more.push_back("KHR_mesh_quantization");
  w.doc["extensionsUsed"] = more;
  w.doc["extensionsRequired"] = more;
  return w;
}

}  // namespace

TEST_CASE("published glTF: gltfpack and glTF-Transform's Cornell boxes render like the original") {
  const Scene original = load_gltf(DACRT_SOURCE_DIR "/scenes/cornell-box.gltf");
  const std::vector<double> reference = image(original);
  for (const char* name : {"gltfpack", "gltfpack-c", "meshopt", "draco"}) {
    INFO(std::string(name));
    const Scene scene =
        load_gltf(std::string(DACRT_SOURCE_DIR "/tests/published/cornell-box.") + name + ".glb");
    CHECK(scene.geometry.size() == original.geometry.size());
    const glm::vec3 lo = scene.bounds().lo, hi = scene.bounds().hi;
    const glm::vec3 olo = original.bounds().lo, ohi = original.bounds().hi;
    for (int c = 0; c < 3; ++c) {
      CHECK(lo[c] == doctest::Approx(olo[c]).epsilon(2e-3).scale(1.0));
      CHECK(hi[c] == doctest::Approx(ohi[c]).epsilon(2e-3).scale(1.0));
    }
    // Per pixel, within the noise of 16 samples (Draco reorders the triangles, so the emitters'
    // alias table maps the same numbers elsewhere); over the image, within 1 %.
    const std::vector<double> got = image(scene);
    const double d = relative_difference(got, reference);
    double sum = 0.0, want = 0.0;
    for (size_t p = 0; p < got.size(); ++p) sum += got[p], want += reference[p];
    MESSAGE(name << ": relative difference " << d << ", image mean " << sum / want);
    CHECK(d < 0.06);
    CHECK(sum / want == doctest::Approx(1.0).epsilon(0.01));
  }
}

TEST_CASE("KHR_mesh_quantization: integer positions and normals, scaled back by the node") {
  TempDir dir("gltf-quantized");
  // Elements padded to 4-byte strides, as the extension asks.
  const std::vector<int16_t> p = {0, 0, 0, 0, 100, 0, 0, 0, 0, 200, 0, 0};
  const std::vector<int8_t> n = {0, 0, 127, 0, 0, 0, 127, 0, 0, 0, -127, 0};
  auto file = [&](bool uses_extension, bool normalized) {
    GltfWriter w = uses_extension ? quantized() : GltfWriter();
    const int position = w.add_accessor(w.add_view(p.data(), 24, 8), kShort, 3, "VEC3");
    w.doc["accessors"][position]["min"] = {0, 0, 0};
    w.doc["accessors"][position]["max"] = {100, 200, 0};
    if (normalized) w.doc["accessors"][position]["normalized"] = true;
    const int normal = w.add_accessor(w.add_view(n.data(), 12, 4), kByte, 3, "VEC3");
    w.doc["accessors"][normal]["normalized"] = true;
    const int mesh = w.add_mesh(json{{"attributes", {{"POSITION", position}, {"NORMAL", normal}}}});
    w.set_scene({w.add_node({{"mesh", mesh}, {"scale", {0.01, 0.01, 0.01}}})});
    return w.write_glb(dir / (std::string(uses_extension ? "q" : "plain") +
                              (normalized ? "-normalized" : "") + ".glb"));
  };
  SUBCASE("SHORT positions as integers") {
    const Scene scene = load_gltf(file(true, false));
    REQUIRE(scene.geometry.size() == 1);
    CHECK(scene.geometry.vertex(0, 0) == glm::vec3(0.f));
    CHECK(scene.geometry.vertex(0, 1) == glm::vec3(1.f, 0.f, 0.f));
    CHECK(scene.geometry.vertex(0, 2) == glm::vec3(0.f, 2.f, 0.f));
    REQUIRE(scene.normals.size() == 3);
    CHECK(scene.normals[0] == glm::vec3(0.f, 0.f, 1.f));
    CHECK(scene.normals[2] == glm::vec3(0.f, 0.f, -1.f));
  }
  SUBCASE("normalized SHORT positions: c / 32767") {
    const Scene scene = load_gltf(file(true, true));
    REQUIRE(scene.geometry.size() == 1);
    CHECK(scene.geometry.vertex(0, 1).x == doctest::Approx(0.01 * 100.0 / 32767.0));
    CHECK(scene.geometry.vertex(0, 2).y == doctest::Approx(0.01 * 200.0 / 32767.0));
  }
  SUBCASE("without the extension, integer positions are an error") {
    check_error(file(false, false), {"accessor 0", "POSITION", "must be FLOAT VEC3"});
  }
}

TEST_CASE("KHR_mesh_quantization: texture coordinates as integers or normalized integers") {
  TempDir dir("gltf-quantized-uv");
  for (const bool normalized : {false, true}) {
    INFO("normalized " << normalized);
    GltfWriter w = quad_file({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    w.doc["extensionsUsed"] = w.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
    add_texture(w, png8(2, 2, 4, kTexels));
    // The uv square's corners as 0 or 3 (unnormalized: the texture repeated three times), or as
    // 0 or 65535 (normalized: 0 or 1).
    const uint16_t one = normalized ? 65535 : 3;
    const std::vector<uint16_t> uv = {0, one, one, one, one, 0, 0, 0};
    const int accessor = w.add_accessor(w.add_view(uv.data(), 16), kUnsignedShort, 4, "VEC2");
    if (normalized) w.doc["accessors"][accessor]["normalized"] = true;
    w.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = accessor;
    const Scene scene = load_gltf(w.write_glb(dir / "uv.glb"));
    REQUIRE(scene.texcoords[0].size() == 6);
    const float expected = normalized ? 1.f : 3.f;
    CHECK(scene.texcoords[0][0] == glm::vec2(0.f, expected));  // triangle (0, 1, 2), corner 0
    CHECK(scene.texcoords[0][1] == glm::vec2(expected, expected));
    CHECK(scene.texcoords[0][2] == glm::vec2(expected, 0.f));
  }
}

TEST_CASE("EXT_meshopt_compression: streams encoded by meshoptimizer load exactly") {
  TempDir dir("gltf-meshopt");
  const size_t index_bound = meshopt_encodeIndexBufferBound(kQuadIndices.size(), kQuad.size());
  const size_t vertex_bound = meshopt_encodeVertexBufferBound(kQuad.size(), 12);
  std::vector<unsigned char> vertices(vertex_bound), indices(index_bound);
  vertices.resize(
      meshopt_encodeVertexBuffer(vertices.data(), vertices.size(), kQuad.data(), kQuad.size(), 12));
  const std::vector<unsigned int> wide(kQuadIndices.begin(), kQuadIndices.end());
  indices.resize(
      meshopt_encodeIndexBuffer(indices.data(), indices.size(), wide.data(), wide.size()));
  REQUIRE(!vertices.empty());
  REQUIRE(!indices.empty());
  // Buffer 0 holds the compressed streams; buffer 1 is the fallback, whose data is not in the file.
  uint64_t vertex_view = 48;  // the vertex bufferView's byteLength (the fallback buffer's data)
  auto file = [&](const std::string& name, json vertex_ext, json index_ext) {
    GltfWriter w;
    w.doc["extensionsUsed"] = w.doc["extensionsRequired"] = {"EXT_meshopt_compression"};
    const int vv = w.add_view(vertices.data(), vertices.size());
    const int iv = w.add_view(indices.data(), indices.size());
    json& views = w.doc["bufferViews"];
    vertex_ext.update({{"buffer", 0}, {"byteOffset", views[vv]["byteOffset"]}});
    index_ext.update({{"buffer", 0}, {"byteOffset", views[iv]["byteOffset"]}});
    views[vv] = {{"buffer", 1},
                 {"byteOffset", 0},
                 {"byteLength", vertex_view},
                 {"byteStride", 12},
                 {"extensions", {{"EXT_meshopt_compression", vertex_ext}}}};
    views[iv] = {{"buffer", 1},
                 {"byteOffset", vertex_view},
                 {"byteLength", 12},
                 {"extensions", {{"EXT_meshopt_compression", index_ext}}}};
    const int position = w.add_accessor(vv, kFloat, 4, "VEC3");
    w.doc["accessors"][position]["min"] = {0, 0, 0};
    w.doc["accessors"][position]["max"] = {1, 1, 0};
    const int index = w.add_accessor(iv, kUnsignedShort, 6, "SCALAR");
    w.set_scene({w.add_node(
        {{"mesh", w.add_mesh(GltfWriter::primitive(position, {{"indices", index}}))}})});
    w.more_buffers = {
        {{"byteLength", vertex_view + 12},
         {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
    return w.write_glb(dir / name);
  };
  const json vertex = {
      {"byteLength", vertices.size()}, {"byteStride", 12}, {"count", 4}, {"mode", "ATTRIBUTES"}};
  const json index = {
      {"byteLength", indices.size()}, {"byteStride", 2}, {"count", 6}, {"mode", "TRIANGLES"}};
  SUBCASE("vertices and triangles") {
    check_quad(load_gltf(file("quad.glb", vertex, index)));
  }
  SUBCASE("a truncated stream is one error naming the bufferView") {
    json cut = vertex;
    cut["byteLength"] = vertices.size() / 2;
    check_error(file("cut.glb", cut, index),
                {"bufferView 0's EXT_meshopt_compression", "malformed"});
  }
  SUBCASE("sizes meshoptimizer only asserts are checked first") {
    json odd = vertex;
    odd["byteStride"] = 6;
    check_error(file("stride.glb", odd, index), {"bufferView 0", "divisible by 4"});
    json strip = index;
    strip["count"] = 5;
    check_error(file("count.glb", vertex, strip), {"bufferView 1", "divisible by 3"});
    json mode = index;
    mode["mode"] = "LINES";
    check_error(file("mode.glb", vertex, mode),
                {"/bufferViews/1/extensions/EXT_meshopt_compression/mode", "\"LINES\""});
  }
  SUBCASE("sizes beyond the bufferView or the decoding budget: refused before allocating") {
    json huge = vertex;
    huge["count"] = 1 << 28;  // 3 GiB of vertices for a 48-byte bufferView
    AllocationWatch watch;
    check_error(file("huge.glb", huge, index), {"bufferView 0", "more than the bufferView"});
    CHECK(watch.peak() < (uint64_t(64) << 20));
  }
  SUBCASE("a stream that claims more than its length can decode to: refused before allocating") {
    // 2^26 vertices of 12 bytes (768 MiB, within the bufferView and the budget) from a stream of
    // a few dozen bytes: meshoptimizer would zero-fill it all before it finds the stream short.
    vertex_view = uint64_t(12) << 26;
    json claims = vertex;
    claims["count"] = 1 << 26;
    AllocationWatch watch;
    check_error(file("claims.glb", claims, index),
                {"bufferView 0's EXT_meshopt_compression claims 67108864 elements of 12 bytes",
                 "-byte stream can decode to"});
    CHECK(watch.peak() < (uint64_t(64) << 20));
  }
  SUBCASE("the most compressible stream (all zeros) is within the bound and loads") {
    // 65535 zero vertices: the encoder's smallest output for their size, close to 1/64 of it.
    const std::vector<float> zeros(3 * 65535, 0.f);
    vertices.assign(meshopt_encodeVertexBufferBound(65535, 12), 0);
    vertices.resize(
        meshopt_encodeVertexBuffer(vertices.data(), vertices.size(), zeros.data(), 65535, 12));
    CHECK(vertices.size() * 64 >= 65535 * 12);
    CHECK(vertices.size() * 48 < 65535 * 12);  // the bound is near what the codec reaches
    vertex_view = 12 * 65535;
    json dense = vertex;
    dense["byteLength"] = vertices.size();
    dense["count"] = 65535;
    const Scene scene = load_gltf(file("zeros.glb", dense, index));
    CHECK(scene.geometry.size() == 0);  // the quad's corners are all at one point
    CHECK(scene.degenerate_triangles == 2);
  }
}

TEST_CASE("KHR_draco_mesh_compression: broken streams, attributes and counts are one error each") {
  // The glTF-Transform file, taken apart and broken one way at a time. (Its whole geometry is
  // compared with the original above.)
  TempDir dir("gltf-draco");
  const std::vector<unsigned char> glb =
      read_bytes(DACRT_SOURCE_DIR "/tests/published/cornell-box.draco.glb");
  const uint32_t json_size = uint32_t(glb[12]) | uint32_t(glb[13]) << 8 | uint32_t(glb[14]) << 16 |
                             uint32_t(glb[15]) << 24;
  GltfWriter w;
  w.doc = json::parse(glb.begin() + 20, glb.begin() + 20 + json_size);
  w.doc.erase("buffers");
  w.bin.assign(glb.begin() + 20 + json_size + 8, glb.end());
  const json& draco =
      w.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"];
  const int view = draco["bufferView"].get<int>();
  const size_t offset = w.doc["bufferViews"][view].value("byteOffset", size_t(0));
  const size_t length = w.doc["bufferViews"][view]["byteLength"].get<size_t>();
  const int position = w.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>();
  CHECK_NOTHROW(load_gltf(w.write_glb(dir / "as-is.glb")));
  SUBCASE("garbage in the stream") {
    for (size_t i = offset + length / 3; i < offset + length; ++i) w.bin[i] = uint8_t(i * 37);
    check_error(w.write_glb(dir / "garbage.glb"),
                {"mesh 0 primitive 0's KHR_draco_mesh_compression", "cannot be decoded"});
  }
  SUBCASE("a stream cut short") {
    w.doc["bufferViews"][view]["byteLength"] = length / 2;
    check_error(w.write_glb(dir / "cut.glb"), {"mesh 0 primitive 0's KHR_draco_mesh_compression"});
  }
  SUBCASE("an attribute the stream does not have") {
    w.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]
         ["POSITION"] = 99;
    check_error(w.write_glb(dir / "id.glb"), {"has no attribute 99"});
  }
  SUBCASE("an accessor count that is not the stream's") {
    w.doc["accessors"][position]["count"] = w.doc["accessors"][position]["count"].get<int>() + 1;
    check_error(w.write_glb(dir / "count.glb"),
                {"accessor " + std::to_string(position), "has count"});
  }
}
