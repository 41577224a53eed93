// Hostile glTF files against the loader's bounds (issue 31): reads bounded by what the file says it
// needs (a buffer file far longer than its byteLength, images no material uses), work that follows
// the scene's size and not a product of its counts (a big accessor, a few indices, many nodes),
// numbers that are finite in the JSON but not as float, and node scales float cannot square.
// Files are generated here; what must not be read is made costly to read (sparse files of many
// MiB, FIFOs) and the peak allocation is measured (tests/allocations.h).
#include <doctest/doctest.h>
#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>

#include "dacrt/io/gltf.h"
#include "tests/address_space.h"
#include "tests/allocations.h"
#include "tests/gltf_check.h"
#include "tests/gltf_triangle.h"
#include "tests/gltf_writer.h"
#include "tests/png.h"
#include "dacrt/util/error.h"
#include "dacrt/util/memory.h"

using dacrt::Error;
using dacrt::GltfOptions;
using dacrt::load_gltf;
using dacrt::Scene;
using dacrt::test::AddressSpaceRoom;
using dacrt::test::AllocationWatch;
using dacrt::test::check_error;
using dacrt::test::GltfWriter;
using dacrt::test::kFloat;
using dacrt::test::kTriangle;
using dacrt::test::TempDir;
using nlohmann::json;

namespace {

constexpr uint64_t kMiB = uint64_t(1) << 20;

bool near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) {
  return glm::all(glm::lessThanEqual(glm::abs(a - b), glm::vec3(eps)));
}

// Grows `path` to `size` bytes without writing them (a sparse file): costly only to a reader.
bool grow(const std::string& path, uint64_t size) {
  std::error_code ec;
  std::filesystem::resize_file(path, size, ec);
  return !ec;
}

// A triangle with TEXCOORD_0 whose material 0 shows texture 0 (image 0) as its base colour.
GltfWriter textured_triangle() {
  GltfWriter w;
  const std::vector<glm::vec2> uv = {{0, 0}, {1, 0}, {0, 1}};
  const int uv_accessor =
      w.add_accessor(w.add_view(uv.data(), sizeof(glm::vec2) * uv.size()), kFloat, 3, "VEC2");
  w.add_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  w.add_triangles(kTriangle, {{"material", 0}});
  w.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv_accessor;
  w.doc["textures"] = {{{"source", 0}}};
  return w;
}

// "<prefix><n>.gltf" (built so that GCC 12 sees no overlapping copy in it).
std::string numbered(const char* prefix, int n) {
  std::string name = std::to_string(n);
  name.insert(0, prefix);
  return name + ".gltf";
}

// A 1 × 1 PNG of grey `value`.
std::vector<unsigned char> grey_png(uint8_t value) {
  return dacrt::test::png8(1, 1, 1, {value});
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// 6. A buffer file is read only as far as its byteLength.

TEST_CASE("gltf untrusted: a buffer file longer than its byteLength is read only to byteLength") {
  TempDir dir("long-buffer");
  GltfWriter w;
  w.add_triangles(kTriangle);
  const std::string path = w.write_gltf(dir / "long.gltf", /*embed=*/false);
  // The spec: the file MUST hold at least byteLength bytes, so a longer one is valid. 256 MiB
  // of holes cost nothing to make and 256 MiB to read.
  REQUIRE(grow(dir / "long.bin", 256 * kMiB));
  AllocationWatch watch;
  const Scene scene = load_gltf(path);
  CHECK(watch.peak() < 4 * kMiB);
  REQUIRE(scene.geometry.size() == 1);
  CHECK(scene.geometry.vertex(0, 1) == kTriangle[1]);
  REQUIRE(scene.files.size() == 1);
  CHECK(scene.files[0].path.find("long.bin") != std::string::npos);
  CHECK(scene.files[0].bytes == w.bin.size());  // what the render's fingerprint covers

  // Two buffers naming the same file with different lengths each get theirs.
  json doc = w.doc;
  GltfWriter two = w;
  const std::string twice = two.write_gltf(dir / "twice.gltf", false);
  json j = json::parse(std::ifstream(twice));
  j["buffers"].push_back({{"byteLength", 4}, {"uri", "twice.bin"}});
  j["bufferViews"].push_back({{"buffer", 1}, {"byteLength", 4}});
  dacrt::test::write_text(twice, j.dump());
  CHECK(load_gltf(twice).geometry.size() == 1);
}

TEST_CASE("gltf untrusted: a URI longer than any path is refused from the JSON, not copied") {
  TempDir dir("long-uri");
  // 10 MB of file name: no file can have it (PATH_MAX is 4096). Refused by the schema check, the
  // first reader of the JSON, before the loader's paths and tinygltf's second parse copy it.
  for (const char* element : {"buffers", "images"}) {
    CAPTURE(element);
    GltfWriter w = dacrt::test::triangle_file();
    const std::string name = std::string(10000000, 'a') + ".bin";
    if (std::string(element) == "buffers")
      w.more_buffers = {{{"byteLength", 4}, {"uri", name}}};
    else
      w.doc["images"] = json::array({{{"uri", name}}});
    const std::string path = w.write_gltf(dir / "long.gltf");
    AllocationWatch watch;
    check_error(path, {std::string("/") + element + (element[0] == 'b' ? "/1/uri" : "/0/uri"),
                       "is a file name of 10000004 bytes, longer than any path can be (4096)"});
    CHECK(watch.peak() < 60 * kMiB);  // the file, its JSON and nothing more (was over 200)
  }
  // A data URI of the same size is a buffer: decoded by tinygltf from the text it parses, not
  // first copied into paths, names and a second JSON value (the peak was 8 times the file).
  {
    GltfWriter w = dacrt::test::triangle_file();
    w.bin.resize(7500000, 0);
    const std::string path = w.write_gltf(dir / "data.gltf");
    const uint64_t file = std::filesystem::file_size(path);
    AllocationWatch watch;
    CHECK(load_gltf(path).geometry.size() == 1);
    CHECK(watch.peak() < 6 * file);
  }
  // A path of 4096 bytes is still looked for (and here not found).
  GltfWriter w = dacrt::test::triangle_file();
  w.more_buffers = {{{"byteLength", 4}, {"uri", std::string(4096, 'b')}}};
  check_error(w.write_gltf(dir / "path.gltf"), {"buffer 1"});
}

TEST_CASE("gltf untrusted: a buffer file shorter than its byteLength is refused before reading") {
  TempDir dir("short-buffer");
  GltfWriter w;
  w.add_triangles(kTriangle);
  const std::string path = w.write_gltf(dir / "short.gltf", /*embed=*/false);
  json j = json::parse(std::ifstream(path));
  j["buffers"][0]["byteLength"] = 1000;
  dacrt::test::write_text(path, j.dump());
  check_error(path, {"buffer 0 (short.bin)", "fewer than its byteLength 1000"});

  // A byteLength (and a file) beyond the memory available: refused, not allocated.
  const uint64_t huge = std::max<uint64_t>(dacrt::available_memory(), 1ull << 36) + kMiB;
  if (huge < (uint64_t(1) << 44) && grow(dir / "short.bin", huge)) {
    j["buffers"][0]["byteLength"] = huge;
    dacrt::test::write_text(path, j.dump());
    AllocationWatch watch;
    check_error(path, {"buffer 0 (short.bin)", "memory"});
    CHECK(watch.peak() < 4 * kMiB);
  } else {
    MESSAGE("no sparse file of " << huge << " bytes here: the memory bound is not tested");
  }
}

TEST_CASE(
    "gltf untrusted: a buffer is looked for beside the file only, not in the working directory") {
  TempDir scene_dir("beside"), cwd("cwd");
  GltfWriter w;
  w.add_triangles(kTriangle);
  const std::string path = w.write_gltf(scene_dir / "a.gltf", /*embed=*/false);
  std::filesystem::rename(scene_dir / "a.bin", cwd / "a.bin");  // some file of the user's
  const std::filesystem::path saved = std::filesystem::current_path();
  std::filesystem::current_path(cwd.path());
  try {
    check_error(path, {"buffer 0", "a.bin"});
  } catch (...) {
    std::filesystem::current_path(saved);
    throw;
  }
  std::filesystem::current_path(saved);
}

// ---------------------------------------------------------------------------------------------
// 7. Images the render does not use are not read.

TEST_CASE("gltf untrusted: images no used material shows are never read, used ones still load") {
  TempDir dir("unused-images");
  GltfWriter w = textured_triangle();
  const std::vector<unsigned char> png = grey_png(200);
  dacrt::test::write_bytes(dir / "used.png", png.data(), png.size());
  // Image 1: a FIFO (blocks a reader forever); 2: 2 GiB of holes; 3: garbage; 4: missing. Each
  // is shown by a texture of a material no primitive uses, or of an unused slot (occlusion).
  REQUIRE(mkfifo((dir / "fifo.png").c_str(), 0600) == 0);
  dacrt::test::write_text(dir / "huge.png", "");
  REQUIRE(grow(dir / "huge.png", 2048 * kMiB));
  dacrt::test::write_text(dir / "garbage.png", "not an image at all");
  w.doc["images"] = {{{"uri", "used.png"}},
                     {{"uri", "fifo.png"}},
                     {{"uri", "huge.png"}},
                     {{"uri", "garbage.png"}},
                     {{"uri", "missing.png"}}};
  w.doc["textures"] = {
      {{"source", 0}}, {{"source", 1}}, {{"source", 2}}, {{"source", 3}}, {{"source", 4}}};
  w.add_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}},
                  {"normalTexture", {{"index", 2}}}});         // material 1: no primitive uses it
  w.doc["materials"][0]["occlusionTexture"] = {{"index", 3}};  // a slot the loader ignores
  // Emissive texture with emissiveFactor 0 (the default) is never sampled either.
  w.doc["materials"][0]["emissiveTexture"] = {{"index", 4}};
  const std::string path = w.write_gltf(dir / "unused.gltf");
  AllocationWatch watch;
  const Scene scene = load_gltf(path);
  CHECK(watch.peak() < 16 * kMiB);
  REQUIRE(scene.images.size() == 5);
  CHECK(scene.images[0].width == 1);
  CHECK(scene.images[2].width == 0);  // never decoded
  REQUIRE(scene.materials.size() == 2);
  CHECK(scene.materials[0].base_color_texture.texture == 0);

  // The same unused image shown by a used material is read: the garbage is then an error.
  w.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 3;
  check_error(w.write_gltf(dir / "used-garbage.gltf"), {"image 3 (garbage.png)"});
  // ... and the 2 GiB one is refused from its size (over 1 GiB), not read.
  w.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 2;
  {
    AllocationWatch big;
    check_error(w.write_gltf(dir / "used-huge.gltf"), {"image 2 (huge.png)", "2.0 GiB"});
    CHECK(big.peak() < 16 * kMiB);
  }
}

TEST_CASE("gltf untrusted: an image only another scene shows is read only for that scene") {
  TempDir dir("scene-images");
  GltfWriter w = textured_triangle();
  const std::vector<unsigned char> png = grey_png(10);
  dacrt::test::write_bytes(dir / "used.png", png.data(), png.size());
  // Costly to read: 2 GiB of holes, which a reader refuses by its size (over 1 GiB).
  dacrt::test::write_text(dir / "broken.png", "");
  REQUIRE(grow(dir / "broken.png", 2048 * kMiB));
  w.doc["images"] = {{{"uri", "used.png"}}, {{"uri", "broken.png"}}};
  w.doc["textures"] = {{{"source", 0}}, {{"source", 1}}};
  // Scene 1: a second node with its own mesh and material showing the broken image.
  w.add_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}});
  json other = w.doc["meshes"][0];
  other["primitives"][0]["material"] = 1;
  w.doc["meshes"].push_back(other);
  w.doc["nodes"].push_back({{"mesh", 1}});
  w.doc["scenes"].push_back({{"nodes", {1}}});
  const std::string path = w.write_gltf(dir / "scenes.gltf");
  CHECK(load_gltf(path).images[0].width == 1);  // the default scene, 0
  check_error(path, {"image 1 (broken.png)", "2.0 GiB"}, GltfOptions{1});
}

// ---------------------------------------------------------------------------------------------
// 9. Work follows the scene's size, not accessor size × instances.

namespace {

// One mesh whose POSITION accessor has `vertices` vertices (all zeros but for a triangle
// patched at vertices 7, 8 and 9 by a sparse accessor: no bufferView, so the file is small), of
// which the 3 indices use only the triangle, placed by `nodes` nodes at x = 0, 1, 2, ...
GltfWriter many_instances_of_few_indices(size_t vertices, int nodes) {
  GltfWriter w;
  const std::vector<uint32_t> patched = {7, 8, 9};
  const int index_view = w.add_view(patched.data(), 12);
  const int value_view = w.add_view(kTriangle.data(), 36);
  const int position = w.add_accessor(-1, kFloat, vertices, "VEC3");
  w.doc["accessors"][position]["min"] = {0, 0, 0};
  w.doc["accessors"][position]["max"] = {1, 1, 0};
  w.doc["accessors"][position]["sparse"] = {
      {"count", 3},
      {"indices", {{"bufferView", index_view}, {"componentType", dacrt::test::kUnsignedInt}}},
      {"values", {{"bufferView", value_view}}}};
  const int indices = w.add_indices(patched);
  const int mesh = w.add_mesh(GltfWriter::primitive(position, {{"indices", indices}}));
  std::vector<int> roots;
  for (int n = 0; n < nodes; ++n)
    roots.push_back(w.add_node({{"mesh", mesh}, {"translation", {n, 0, 0}}}));
  w.set_scene(roots);
  return w;
}

}  // namespace

TEST_CASE("gltf untrusted: a few indices into millions of vertices, placed by a thousand nodes") {
  TempDir dir("instances");
  // 4 M vertices of 12 bytes: a reader that materialised or copied the accessor per instance
  // would allocate 48 MiB at a time (and take minutes over the thousand nodes).
  GltfWriter w = many_instances_of_few_indices(4000000, 1000);
  const std::string path = w.write_gltf(dir / "instances.gltf");
  CHECK(std::filesystem::file_size(path) < 100000);
  AllocationWatch watch;
  const Scene scene = load_gltf(path);
  CHECK(watch.peak() < 4 * kMiB);
  REQUIRE(scene.geometry.size() == 1000);
  for (size_t n : {size_t(0), size_t(1), size_t(999)})
    for (int k = 0; k < 3; ++k)
      CHECK(scene.geometry.vertex(n, k) == kTriangle[size_t(k)] + glm::vec3(float(n), 0, 0));
  CHECK(scene.mesh_count == 1);
  CHECK(scene.node_count == 1000);
}

TEST_CASE(
    "gltf untrusted: only the used vertices are read, with the attributes that go with them") {
  TempDir dir("used-vertices");
  // 100 vertices (so that reading only the used ones applies), NORMAL and COLOR_0 on each;
  // indices use vertices 90, 40, 70: their positions, normals and colours must stay together.
  GltfWriter w;
  std::vector<glm::vec3> p(100), n(100);
  std::vector<glm::vec4> c(100);
  for (size_t i = 0; i < 100; ++i)
    p[i] = glm::vec3(float(i), float(i % 7), 0), n[i] = glm::vec3(0, 0, 1),
    c[i] = glm::vec4(float(i) / 100.f, 0, 0, 1);
  p[3] = glm::vec3(NAN);  // unused: never read, so not an error
  const int position = w.add_vec3(p);
  w.doc["accessors"][position]["min"] = {0, 0, 0};
  const int normal = w.add_vec3(n, false);
  const int color = w.add_accessor(w.add_view(c.data(), c.size() * 16), kFloat, 100, "VEC4");
  const int indices = w.add_indices(std::vector<uint8_t>{90, 40, 70});
  w.set_scene({w.add_node(
      {{"mesh", w.add_mesh(json{{"attributes",
                                 {{"POSITION", position}, {"NORMAL", normal}, {"COLOR_0", color}}},
                                {"indices", indices}})}})});
  const Scene scene = load_gltf(w.write_gltf(dir / "used.gltf"));
  REQUIRE(scene.geometry.size() == 1);
  const uint32_t used[3] = {90, 40, 70};
  REQUIRE(scene.colors.size() == 3);
  for (int k = 0; k < 3; ++k) {
    CHECK(scene.geometry.vertex(0, k) == p[used[k]]);
    CHECK(scene.colors[size_t(k)].x == doctest::Approx(c[used[k]].x));
  }
  // A used vertex that is not finite is still an error, named by its number in the file.
  w.doc["meshes"][0]["primitives"][0]["indices"] = w.add_indices(std::vector<uint8_t>{90, 3, 70});
  check_error(w.write_gltf(dir / "nan.gltf"), {"vertex 3 ", "not finite"});
}

TEST_CASE("gltf untrusted: triangles of zero area are dropped, with their corners' attributes") {
  TempDir dir("zero-area");
  // Four triangles: one with an area, one of three points on a line, one of one point, another
  // with an area; each corner with its own colour, so that a kept triangle must keep its own.
  GltfWriter w;
  const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},    // kept
                                    {0, 0, 0}, {1, 1, 1}, {2, 2, 2},    // on a line
                                    {5, 5, 5}, {5, 5, 5}, {5, 5, 5},    // one point
                                    {0, 0, 3}, {0, 2, 3}, {2, 0, 3}};   // kept
  std::vector<glm::vec4> c(p.size());
  for (size_t i = 0; i < c.size(); ++i) c[i] = glm::vec4(float(i) / 16.f, 0, 0, 1);
  const int color = w.add_accessor(w.add_view(c.data(), c.size() * 16), kFloat, c.size(), "VEC4");
  w.set_scene({w.add_node({{"mesh", w.add_mesh(json{{"attributes",
                                                     {{"POSITION", w.add_vec3(p)},
                                                      {"NORMAL", w.add_vec3(std::vector<glm::vec3>(
                                                                     p.size(), {0, 0, 1}), false)},
                                                      {"COLOR_0", color}}}})}})});
  const Scene scene = load_gltf(w.write_gltf(dir / "zero.gltf"));
  REQUIRE(scene.geometry.size() == 2);
  CHECK(scene.degenerate_triangles == 2);
  REQUIRE(scene.colors.size() == 6);
  REQUIRE(scene.normals.size() == 6);
  for (size_t t = 0; t < 2; ++t)
    for (int k = 0; k < 3; ++k) {
      const size_t from = (t == 0 ? 0 : 9) + size_t(k);
      CHECK(scene.geometry.vertex(t, k) == p[from]);
      CHECK(scene.colors[3 * t + size_t(k)].x == doctest::Approx(c[from].x));
    }

  // 3 M zero vertices from an accessor without a bufferView (valid: all zeros), 1 M triangles at
  // one point: none is kept, so no ray meets them.
  GltfWriter zeros;
  const int position = zeros.add_accessor(-1, kFloat, 3000000, "VEC3");
  zeros.doc["accessors"][position]["min"] = zeros.doc["accessors"][position]["max"] = {0, 0, 0};
  zeros.set_scene({zeros.add_node({{"mesh", zeros.add_mesh(GltfWriter::primitive(position))}})});
  const Scene none = load_gltf(zeros.write_gltf(dir / "zeros.gltf"));
  CHECK(none.geometry.size() == 0);
  CHECK(none.degenerate_triangles == 1000000);
}

TEST_CASE("gltf untrusted: degenerate instances count as work and are bounded before it is done") {
  TempDir dir("degenerate-work");
  // A strip of 2 M indices, all 0: 2 M triangles asked for, none drawn, placed by nodes enough
  // to ask for more than memory can hold (256 MiB here). Without a bound counting them, such a
  // file is 2 M index reads per node, however many nodes.
  const uint64_t per_instance = 2000000;
  GltfWriter w;
  const int position = w.add_vec3(kTriangle);
  const int indices = w.add_indices(std::vector<uint8_t>(per_instance, 0));
  const int mesh = w.add_mesh(GltfWriter::primitive(position, {{"indices", indices}, {"mode", 5}}));
  std::vector<int> roots;
  for (int n = 0; n < 200; ++n) roots.push_back(w.add_node({{"mesh", mesh}}));
  w.set_scene(roots);
  const std::string path = w.write_gltf(dir / "strips.gltf", /*embed=*/false);
  AddressSpaceRoom room(256 * kMiB);
  REQUIRE(room.ok());
  check_error(path, {"mesh 0 primitive 0", "triangles", "memory"});
}

TEST_CASE("gltf untrusted: instances read are bounded too, even of a mesh that draws nothing") {
  TempDir dir("instance-work");
  // 1 M instances (a TRANSLATION accessor of zeros, no bufferView) of a mesh of points, placed
  // by 200 nodes: 200 M instances to read for nothing drawn, more than 256 MiB allow.
  GltfWriter w;
  const int mesh = w.add_mesh(GltfWriter::primitive(w.add_vec3(kTriangle), {{"mode", 0}}));
  const int translation = w.add_accessor(-1, kFloat, 1000000, "VEC3");
  std::vector<int> roots;
  for (int n = 0; n < 200; ++n)
    roots.push_back(w.add_node(
        {{"mesh", mesh},
         {"extensions",
          {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", translation}}}}}}}}));
  w.set_scene(roots);
  w.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  const std::string path = w.write_gltf(dir / "instances.gltf");
  AddressSpaceRoom room(256 * kMiB);
  REQUIRE(room.ok());
  check_error(path, {"EXT_mesh_gpu_instancing", "memory"});
}

// ---------------------------------------------------------------------------------------------
// 10. Numbers finite in the JSON but infinite as float.

TEST_CASE("gltf untrusted: KHR_lights_punctual numbers that overflow float are refused") {
  TempDir dir("light-overflow");
  auto file = [&](const json& light) {
    GltfWriter w;
    w.add_triangles(kTriangle);
    w.doc["extensions"]["KHR_lights_punctual"]["lights"] = {light};
    w.doc["scenes"][0]["nodes"].push_back(
        w.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}));
    static int count = 0;
    return w.write_gltf(dir / numbered("light", count++));
  };
  check_error(file({{"type", "point"}, {"intensity", 1e39}}), {"light 0", "intensity 1e+39"});
  // (color is bounded to [0, 1] by the schema: color × intensity cannot overflow.)
  check_error(file({{"type", "spot"}, {"spot", json::object()}, {"range", 1e39}}),
              {"light 0", "range 1e+39"});
  // The largest float is still a light; a range too small for float stays a range.
  Scene big = load_gltf(file({{"type", "point"}, {"intensity", 3e38}}));
  REQUIRE(big.lights.size() == 1);
  CHECK(big.lights[0].intensity.x == doctest::Approx(3e38));
  Scene tiny = load_gltf(file({{"type", "point"}, {"range", 1e-50}}));
  REQUIRE(tiny.lights.size() == 1);
  CHECK(tiny.lights[0].range > 0.f);  // not 0, which would mean unlimited
}

TEST_CASE("gltf untrusted: material and camera numbers that overflow float are refused") {
  TempDir dir("material-overflow");
  int count = 0;
  auto file = [&](const json& material) {
    GltfWriter w;
    const std::vector<unsigned char> png = grey_png(1);
    w.doc["images"] = {{{"uri", "data:image/png;base64," + dacrt::test::base64(png)}}};
    w.doc["textures"] = {{{"source", 0}}};
    w.add_material(material);
    w.add_triangles(kTriangle, {{"material", 0}});
    return w.write_gltf(dir / numbered("m", count++));
  };
  check_error(file({{"normalTexture", {{"index", 0}, {"scale", 1e39}}}}),
              {"material 0", "normalTexture.scale 1e+39"});
  check_error(
      file({{"extensions", {{"KHR_materials_specular", {{"specularColorFactor", {1, 1e39, 1}}}}}}}),
      {"material 0", "specularColorFactor"});
  check_error(file({{"pbrMetallicRoughness",
                     {{"baseColorTexture",
                       {{"index", 0},
                        {"extensions", {{"KHR_texture_transform", {{"rotation", 1e39}}}}}}}}}}),
              {"material 0 baseColorTexture KHR_texture_transform", "rotation"});

  auto camera = [&](const json& ortho) {
    GltfWriter w;
    w.add_triangles(kTriangle);
    w.doc["cameras"] = {{{"type", "orthographic"}, {"orthographic", ortho}}};
    w.doc["scenes"][0]["nodes"].push_back(w.add_node({{"camera", 0}}));
    return w.write_gltf(dir / numbered("c", count++));
  };
  check_error(camera({{"xmag", 1e39}, {"ymag", 1e39}, {"znear", 0}, {"zfar", 1}}),
              {"camera 0", "beyond float"});
  check_error(camera({{"xmag", 1e-50}, {"ymag", 1}, {"znear", 0}, {"zfar", 1}}),
              {"camera 0", "beyond float"});
}

// ---------------------------------------------------------------------------------------------
// 11. Scales float cannot square: the rotation is still there.

namespace {

// A perspective camera and a spot light (each turned 90° about +Y: looking down -X) under a
// root node of uniform scale `s` (given `depth` times, one node inside the other), translated so
// that they sit at (1, 2, 3).
GltfWriter scaled_camera(double s, int depth = 1) {
  GltfWriter w;
  w.add_triangles(kTriangle);
  w.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
  w.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "spot"}, {"spot", json::object()}}};
  const float r = std::sqrt(0.5f);
  const double inverse = std::pow(s, -depth);
  int child = w.add_node({{"camera", 0},
                          {"rotation", {0, r, 0, r}},
                          {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}},
                          {"translation", {inverse * 1, inverse * 2, inverse * 3}}});
  for (int d = 0; d < depth; ++d) child = w.add_node({{"scale", {s, s, s}}, {"children", {child}}});
  w.doc["scenes"][0]["nodes"].push_back(child);
  return w;
}

}  // namespace

TEST_CASE("gltf untrusted: cameras and lights under scales of 1e20 and 1e-25 keep their rotation") {
  TempDir dir("camera-scale");
  int count = 0;
  for (const auto& [s, depth] :
       {std::pair{1e20, 1}, {1e-25, 1}, {1e20, 2}, {1e-25, 2}, {1e-40, 1}, {3e38, 1}}) {
    INFO("scale " << s << ", " << depth << " deep");
    const Scene scene = load_gltf(scaled_camera(s, depth).write_gltf(dir / numbered("s", count++)));
    REQUIRE(scene.cameras_from_file == 1);
    const dacrt::Camera& c = scene.cameras[0];
    CHECK(near(glm::vec3(c.to_world * glm::vec4(0, 0, -1, 0)), {-1, 0, 0}));
    CHECK(near(glm::vec3(c.to_world[1]), {0, 1, 0}));
    CHECK(near(c.position(), {1, 2, 3}, 1e-4f));
    REQUIRE(scene.lights.size() == 1);
    CHECK(near(scene.lights[0].direction, {-1, 0, 0}));
    CHECK(near(scene.lights[0].position, {1, 2, 3}, 1e-4f));
  }
}

TEST_CASE("gltf untrusted: a true zero scale or a degenerate shear is refused, saying which") {
  TempDir dir("camera-zero");
  {
    GltfWriter w = scaled_camera(1.0);
    w.doc["nodes"][1]["scale"] = {1, 1, 0};  // the viewing axis
    w.doc["nodes"][1]["extensions"] = json::object();
    check_error(w.write_gltf(dir / "zero-z.gltf"), {"node 1", "camera 0", "zero scale", "Z"});
    w.doc["nodes"][1]["scale"] = {1, 0, 1};
    check_error(w.write_gltf(dir / "zero-y.gltf"), {"node 1", "camera 0", "zero scale", "Y"});
  }
  {
    GltfWriter w = scaled_camera(1.0);
    // Y and Z the same column: no up direction, whatever the scale.
    w.doc["nodes"][1].erase("translation");
    w.doc["nodes"][1].erase("rotation");
    w.doc["nodes"][1]["matrix"] = {1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1};
    w.doc["nodes"][1]["extensions"] = json::object();
    check_error(w.write_gltf(dir / "shear.gltf"), {"node 1", "camera 0", "along its viewing axis"});
  }
  {
    GltfWriter w = scaled_camera(1.0);
    w.doc["nodes"][1]["scale"] = {1, 1, 0};
    w.doc["nodes"][1].erase("camera");
    check_error(w.write_gltf(dir / "zero-light.gltf"), {"node 1", "light 0", "zero scale"});
  }
  {
    GltfWriter w = scaled_camera(1.0);
    w.doc["nodes"][1]["translation"] = {1e39, 0, 0};  // finite in double, not as float
    w.doc["nodes"][1]["extensions"] = json::object();
    check_error(w.write_gltf(dir / "far.gltf"), {"node 1", "camera 0", "beyond float"});
  }
}

TEST_CASE("gltf untrusted: node numbers beyond float that compose to a float-sized transform") {
  TempDir dir("node-double");
  GltfWriter w;
  const int mesh = w.add_mesh(GltfWriter::primitive(w.add_vec3(kTriangle)));
  // Scale 1e39 then 1e-39: 1 in all, though the first is infinite as float. (Rotations are
  // bounded to [-1, 1] by the schema.)
  const int inner = w.add_node({{"mesh", mesh}, {"scale", {1e-39, 1e-39, 1e-39}}});
  const int outer = w.add_node({{"scale", {1e39, 1e39, 1e39}}, {"children", {inner}}});
  w.set_scene({outer});
  const Scene scene = load_gltf(w.write_gltf(dir / "double.gltf"));
  REQUIRE(scene.geometry.size() == 1);
  for (int k = 0; k < 3; ++k) CHECK(near(scene.geometry.vertex(0, k), kTriangle[size_t(k)], 1e-5f));
}
