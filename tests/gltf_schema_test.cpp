// Tests for io/gltf/schema: a valid file that uses every element the schema check looks at, broken
// one way at a time; each error must be one dacrt::Error line naming the file and the JSON pointer
// of the element at fault. Valid content the loader does not support loads, with a warning.
#include <doctest/doctest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "dacrt/io/gltf.h"
#include "dacrt/io/gltf/schema.h"
#include "tests/captured_stderr.h"
#include "tests/gltf_check.h"
#include "tests/gltf_triangle.h"
#include "tests/gltf_writer.h"
#include "dacrt/util/error.h"

using dacrt::Error;
using dacrt::load_gltf;
using dacrt::Scene;
using dacrt::test::check_error;
using dacrt::test::GltfWriter;
using dacrt::test::kTriangle;
using dacrt::test::stderr_of;
using dacrt::test::TempDir;
using nlohmann::json;

namespace {

// A valid file with one of nearly everything the check looks at: an indexed triangle with a used
// material, an unused textured material (its image is never decoded), two cameras, a spot light,
// a node hierarchy with TRS and matrix nodes, a skin, a sparse accessor and three extensions.
GltfWriter rich_file() {
  GltfWriter w;
  int position = w.add_vec3(kTriangle);
  int indices = w.add_indices(std::vector<uint16_t>{0, 1, 2});
  const unsigned char image_bytes[4] = {1, 2, 3, 4};
  int image_view = w.add_view(image_bytes, 4);
  std::vector<uint16_t> sparse_indices = {1, 2};
  std::vector<glm::vec3> sparse_values = {{2, 0, 0}, {0, 2, 0}};
  int sparse_index_view = w.add_view(sparse_indices.data(), 4);
  int sparse_value_view = w.add_view(sparse_values.data(), 24);
  // Accessor 2: zeros (no bufferView) with two vertices replaced (the second primitive's
  // POSITION: a triangle with an area, which the loader keeps).
  int sparse = w.add_accessor(-1, dacrt::test::kFloat, 3, "VEC3");
  w.doc["accessors"][sparse]["sparse"] = {
      {"count", 2},
      {"indices",
       {{"bufferView", sparse_index_view}, {"componentType", dacrt::test::kUnsignedShort}}},
      {"values", {{"bufferView", sparse_value_view}}}};
  w.doc["extensionsUsed"] = {"KHR_lights_punctual", "KHR_texture_transform",
                             "KHR_materials_emissive_strength"};
  w.doc["images"] = {{{"bufferView", image_view}, {"mimeType", "image/png"}}};
  w.doc["samplers"] = {
      {{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 33071}}};
  w.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
  w.add_material({{"name", "used"},
                  {"pbrMetallicRoughness",
                   {{"baseColorFactor", {1, 0.5, 0.25, 1}},
                    {"metallicFactor", 0.5},
                    {"roughnessFactor", 0.5}}},
                  {"emissiveFactor", {0, 0, 0}},
                  {"alphaMode", "OPAQUE"},
                  {"alphaCutoff", 0.5},
                  {"doubleSided", true}});
  json transform = {{"offset", {0, 0}}, {"rotation", 0}, {"scale", {1, 1}}, {"texCoord", 0}};
  w.add_material(
      {{"pbrMetallicRoughness",
        {{"baseColorTexture",
          {{"index", 0}, {"texCoord", 0}, {"extensions", {{"KHR_texture_transform", transform}}}}},
         {"metallicRoughnessTexture", {{"index", 0}}}}},
       {"normalTexture", {{"index", 0}, {"scale", 1}}},
       {"occlusionTexture", {{"index", 0}, {"strength", 1}}},
       {"emissiveTexture", {{"index", 0}}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 2}}}}}});
  w.add_mesh({GltfWriter::primitive(position, {{"indices", indices}, {"material", 0}, {"mode", 4}}),
              GltfWriter::primitive(sparse)});
  w.doc["cameras"] = {
      {{"type", "perspective"},
       {"perspective", {{"yfov", 0.8}, {"znear", 0.1}, {"zfar", 100}, {"aspectRatio", 1.5}}}},
      {{"type", "orthographic"},
       {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0}, {"zfar", 10}}}}};
  w.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "spot"},
       {"color", {1, 1, 1}},
       {"intensity", 2},
       {"range", 10},
       {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}}};
  // Node 0: the mesh with TRS and children 1 and 2; node 1: a camera with a matrix; node 2: the
  // light; node 3: a joint of the skin.
  w.add_node({{"mesh", 0},
              {"translation", {0, 0, -1}},
              {"rotation", {0, 0, 0, 1}},
              {"scale", {1, 1, 1}},
              {"children", {1, 2}}});
  w.add_node({{"camera", 0}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1}}});
  w.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  w.add_node({{"name", "joint"}});
  w.doc["skins"] = {{{"joints", {3}}}};
  w.set_scene({0, 3});
  w.doc["asset"]["generator"] = "tests/gltf_schema_test.cpp";
  return w;
}

// A mutation's value that removes the member instead.
const json kRemove = json(json::value_t::discarded);

// `doc` with the value at `pointer` replaced (or removed).
json mutated(json doc, const std::string& pointer, const json& value) {
  const json::json_pointer p(pointer);
  if (value.is_discarded())
    doc[p.parent_pointer()].erase(p.back());
  else
    doc[p] = value;
  return doc;
}

json read_json(const std::string& path) {
  std::ifstream in(path);
  return json::parse(in);
}

// The warnings of the schema check on file `path` (what a load writes to stderr).
std::vector<std::string> warnings(const std::string& path) {
  return dacrt::check_gltf_schema(path, read_json(path)).warnings;
}

}  // namespace

TEST_CASE("gltf schema: the rich file is valid and loads without warnings") {
  TempDir dir("schema-rich");
  GltfWriter w = rich_file();
  std::string path = w.write_gltf(dir / "rich.gltf");
  std::string err = stderr_of([&] {
    Scene scene = load_gltf(path);
    CHECK(scene.geometry.size() == 2);
    CHECK(scene.cameras_from_file == 1);
    CHECK(scene.lights.size() == 1);
  });
  CHECK(err.empty());
  CHECK(warnings(path).empty());
  CHECK(stderr_of([&] { load_gltf(w.write_glb(dir / "rich.glb")); }).empty());
}

// ---------------------------------------------------------------------------------------------
// The cases of issue 11 (each exited 0 before and rendered something other than the file says).

TEST_CASE("gltf schema: a negative byteOffset") {
  TempDir dir("schema-offset");
  GltfWriter w = rich_file();
  w.doc["accessors"][0]["byteOffset"] = -8;
  check_error(w.write_gltf(dir / "offset.gltf"),
              {"/accessors/0/byteOffset: -8 is not an integer >= 0"});
  w.doc["bufferViews"][0]["byteOffset"] = -8;
  w.doc["accessors"][0].erase("byteOffset");
  check_error(w.write_gltf(dir / "view-offset.gltf"),
              {"/bufferViews/0/byteOffset: -8 is not an integer >= 0"});
}

TEST_CASE("gltf schema: a mesh index of 2^64 (which nlohmann reads as a double)") {
  TempDir dir("schema-big");
  GltfWriter w;
  int position = w.add_vec3(kTriangle);
  for (int m = 0; m < 5; ++m) w.add_mesh(GltfWriter::primitive(position));
  for (int n = 0; n < 4; ++n) w.add_node({{"mesh", n}});
  w.doc["nodes"][3]["mesh"] = "@BIG@";
  w.set_scene({0, 1, 2, 3});
  const std::string path = dir / "scene.gltf";
  w.write_gltf(path);
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("\"@BIG@\""), 7, "18446744073709551616");
  dacrt::test::write_text(path, text);
  try {
    load_gltf(path);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(std::string(e.what()) == path +
                                       ": /nodes/3/mesh: 18446744073709551616 is not an index (an "
                                       "integer from 0 to 4 for the 5 meshes)");
  }
  // Just past int64 and uint64 as integer literals too.
  for (const char* big : {"9223372036854775808", "18446744073709551615", "-9223372036854775809"}) {
    CAPTURE(big);
    std::string t = text;
    t.replace(t.find("18446744073709551616"), 20, big);
    dacrt::test::write_text(path, t);
    check_error(path, {"/nodes/3/mesh: ", "is not an index"});
  }
}

TEST_CASE("gltf schema: a scene's node index of 0.5, and 1.0 written as a float") {
  TempDir dir("schema-half");
  GltfWriter w = rich_file();
  const json original = w.doc["scenes"][0]["nodes"][1];
  const size_t triangles = dacrt::load_gltf(w.write_gltf(dir / "int.gltf")).geometry.size();
  w.doc["scenes"][0]["nodes"][1] = 0.5;
  check_error(w.write_gltf(dir / "half.gltf"), {"/scenes/0/nodes/1: 0.5 is not an index"});
  // JSON's 2.0 is the integer 2 (so says the validator), which tinygltf would ignore (the scene
  // would lose the node, the mesh its triangles): the loader rewrites them, in a .gltf and in a
  // GLB's JSON chunk.
  w.doc["scenes"][0]["nodes"][1] = original.get<double>();
  for (json& node : w.doc["nodes"])
    if (node.contains("mesh")) node["mesh"] = node["mesh"].get<double>();
  for (json& view : w.doc["bufferViews"]) view["byteLength"] = view["byteLength"].get<double>();
  for (json& accessor : w.doc["accessors"]) accessor["count"] = accessor["count"].get<double>();
  REQUIRE(w.doc.dump().find(".0") != std::string::npos);
  CHECK(dacrt::load_gltf(w.write_gltf(dir / "float.gltf")).geometry.size() == triangles);
  CHECK(dacrt::load_gltf(w.write_glb(dir / "float.glb")).geometry.size() == triangles);
  w.doc["scenes"][0]["nodes"][1] = 1e300;
  check_error(w.write_gltf(dir / "huge.gltf"), {"/scenes/0/nodes/1: 1e+300 is not an index"});
}

TEST_CASE("gltf schema: baseColorFactor of 3 numbers, or of strings") {
  TempDir dir("schema-base");
  GltfWriter w = rich_file();
  w.doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1};
  check_error(
      w.write_gltf(dir / "three.gltf"),
      {"/materials/0/pbrMetallicRoughness/baseColorFactor: has 3 elements", "4 numbers in [0, 1]"});
  w.doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {"1", "1", "1", "1"};
  check_error(w.write_gltf(dir / "strings.gltf"),
              {"/materials/0/pbrMetallicRoughness/baseColorFactor/0: \"1\" is not a number"});
  w.doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 2, 1};
  check_error(w.write_gltf(dir / "range.gltf"),
              {"/materials/0/pbrMetallicRoughness/baseColorFactor/2: 2 is not a number in [0, 1]"});
}

TEST_CASE("gltf schema: KHR_texture_transform as an array") {
  TempDir dir("schema-transform");
  GltfWriter w = rich_file();
  w.doc["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]
       ["KHR_texture_transform"] = {1, 2};
  check_error(w.write_gltf(dir / "array.gltf"),
              {"/materials/1/pbrMetallicRoughness/baseColorTexture/extensions/"
               "KHR_texture_transform: an array is not an object"});
}

TEST_CASE("gltf schema: primitive mode 99 is an error, points and lines still warn") {
  TempDir dir("schema-mode");
  GltfWriter w = rich_file();
  w.doc["meshes"][0]["primitives"][0]["mode"] = 99;
  check_error(w.write_gltf(dir / "mode.gltf"),
              {"/meshes/0/primitives/0/mode: 99 is not one of 0, 1, 2, 3, 4, 5 or 6"});
  for (int mode : {0, 1, 2, 3}) {
    CAPTURE(mode);
    w.doc["meshes"][0]["primitives"][0]["mode"] = mode;
    const std::string path = w.write_gltf(dir / "points.gltf");
    const std::string err = stderr_of([&] { CHECK(load_gltf(path).geometry.size() == 1); });
    CHECK(err == "warning: " + path + ": skipped 1 point and line primitives\n");
  }
  // A file name with a line break in it still makes one warning line.
  const std::string odd = w.write_gltf(dir / "two\nlines.gltf");
  const std::string err = stderr_of([&] { CHECK(load_gltf(odd).geometry.size() == 1); });
  CHECK(err == "warning: " + dir / "two lines.gltf" + ": skipped 1 point and line primitives\n");
}

TEST_CASE("gltf schema: extensionsRequired") {
  TempDir dir("schema-required");
  GltfWriter w = rich_file();
  // An unknown extension that is required (Khronos Asset Generator, Compatibility 05).
  w.doc["extensionsUsed"].push_back("EXT_unknown_future");
  w.doc["extensionsRequired"] = {"KHR_texture_transform", "EXT_unknown_future"};
  check_error(w.write_gltf(dir / "unknown.gltf"),
              {"/extensionsRequired/1: requires extension \"EXT_unknown_future\", which is not "
               "supported"});
  // Khronos' successor of EXT_meshopt_compression (its codec's second version), not read yet.
  w.doc["extensionsUsed"] = {"KHR_meshopt_compression"};
  w.doc["extensionsRequired"] = {"KHR_meshopt_compression"};
  check_error(w.write_gltf(dir / "compressed.gltf"),
              {"/extensionsRequired/0", "KHR_meshopt_compression", "not supported"});
  w.doc["extensionsUsed"] = {"KHR_texture_basisu"};
  w.doc["extensionsRequired"] = {"KHR_texture_basisu"};
  check_error(w.write_gltf(dir / "ktx2.gltf"),
              {"/extensionsRequired/0: requires extension \"KHR_texture_basisu\", which is not "
               "supported (its images are KTX2, and this version has no KTX2 decoder)"});
  w.doc["extensionsUsed"] = {"KHR_texture_transform"};
  w.doc["extensionsRequired"] = {"KHR_lights_punctual"};  // supported, but not listed as used
  check_error(w.write_gltf(dir / "not-used.gltf"),
              {"/extensionsRequired/0: \"KHR_lights_punctual\" is required but not listed in "
               "extensionsUsed"});
  w.doc["extensionsRequired"] = "KHR_texture_transform";
  check_error(w.write_gltf(dir / "string.gltf"),
              {"/extensionsRequired: \"KHR_texture_transform\" is not an array"});
  w.doc["extensionsRequired"] = {"KHR_texture_transform", 5};
  check_error(w.write_gltf(dir / "number.gltf"),
              {"/extensionsRequired/1: 5 is not an extension name"});
  w.doc["extensionsRequired"] = json::array();
  check_error(w.write_gltf(dir / "empty.gltf"), {"/extensionsRequired: is an empty array"});
  w.doc["extensionsRequired"] = {"KHR_texture_transform", "KHR_texture_transform"};
  check_error(w.write_gltf(dir / "twice.gltf"), {"/extensionsRequired/1", "listed twice"});
  w.doc.erase("extensionsRequired");
  w.doc["extensionsUsed"] = {{{"name", "KHR_texture_transform"}}};
  check_error(w.write_gltf(dir / "used-object.gltf"),
              {"/extensionsUsed/0: an object is not an extension name"});
  w.doc["extensionsUsed"] = 1;
  check_error(w.write_gltf(dir / "used-number.gltf"), {"/extensionsUsed: 1 is not an array"});

  // Supported and required: loads.
  w.doc["extensionsUsed"] = {"KHR_texture_transform", "KHR_lights_punctual"};
  w.doc["extensionsRequired"] = {"KHR_texture_transform", "KHR_lights_punctual"};
  CHECK(load_gltf(w.write_gltf(dir / "supported.gltf")).lights.size() == 1);
}

TEST_CASE("gltf schema: an unknown extension that is only used loads, with one warning") {
  TempDir dir("schema-used");
  GltfWriter w = rich_file();
  w.doc["extensionsUsed"].push_back("EXT_unknown_future");
  w.doc["materials"][0]["extensions"]["EXT_unknown_future"] = {{"anything", {1, "two", nullptr}}};
  w.doc["nodes"][0]["extensions"]["EXT_unknown_future"] = json::object();
  w.doc["extras"] = "extras may be any JSON value";
  w.doc["nodes"][0]["unknownProperty"] = {{"is", "allowed"}};
  const std::string path = w.write_gltf(dir / "used.gltf");
  const std::string err = stderr_of([&] { CHECK(load_gltf(path).geometry.size() == 2); });
  CHECK(std::count(err.begin(), err.end(), '\n') == 1);
  CHECK(err.find("not read in this version (rendered without them): EXT_unknown_future (1 "
                 "material, 1 node)") != std::string::npos);
  // But an extension's value must be an object, known or not.
  w.doc["nodes"][0]["extensions"]["EXT_unknown_future"] = 1;
  check_error(w.write_gltf(dir / "ext-number.gltf"),
              {"/nodes/0/extensions/EXT_unknown_future: 1 is not an object"});
  w.doc["nodes"][0]["extensions"] = {1};
  check_error(w.write_gltf(dir / "extensions-array.gltf"),
              {"/nodes/0/extensions: an array is not an object"});
}

TEST_CASE("gltf schema: asset and its version") {
  TempDir dir("schema-asset");
  GltfWriter w = rich_file();
  auto broken = [&](const char* name, const json& asset, const std::string& words) {
    GltfWriter b = w;
    if (asset.is_null())
      b.doc.erase("asset");
    else
      b.doc["asset"] = asset;
    check_error(b.write_gltf(dir / name), {words});
  };
  broken("none.gltf", nullptr, "/asset: is missing (it is required)");
  broken("string.gltf", "2.0", "/asset: \"2.0\" is not an object");
  broken("no-version.gltf", json::object(), "/asset/version: is missing");
  broken("number.gltf", {{"version", 2.0}}, "/asset/version: 2.0 is not a glTF version");
  broken("patch.gltf", {{"version", "2.0.1"}}, "/asset/version: \"2.0.1\" is not a glTF version");
  broken("one.gltf", {{"version", "1.0"}}, "/asset/version: glTF 1.0 is not glTF 2.x");
  broken("three.gltf", {{"version", "3.0"}}, "/asset/version: glTF 3.0 is not glTF 2.x");
  broken("min-newer.gltf", {{"version", "2.1"}, {"minVersion", "2.1"}},
         "/asset/minVersion: the file needs a glTF 2.1 reader");
  broken("min-above.gltf", {{"version", "2.0"}, {"minVersion", "2.2"}},
         "/asset/minVersion: 2.2 is greater than the version 2.0");
  broken("min-type.gltf", {{"version", "2.0"}, {"minVersion", 2}},
         "/asset/minVersion: 2 is not a glTF version");
  broken("generator.gltf", {{"version", "2.0"}, {"generator", 7}},
         "/asset/generator: 7 is not a string");

  // A newer minor version loads (forward compatible) with a warning; so does minVersion 2.0.
  w.doc["asset"] = {{"version", "2.1"}, {"minVersion", "2.0"}};
  const std::string path = w.write_gltf(dir / "minor.gltf");
  CHECK(warnings(path) == std::vector<std::string>{
                              path + ": /asset/version: glTF 2.1 is newer than 2.0; read as 2.0"});
  CHECK(stderr_of([&] { load_gltf(path); }) ==
        "warning: " + path + ": /asset/version: glTF 2.1 is newer than 2.0; read as 2.0\n");
}

TEST_CASE("gltf schema: the node hierarchy") {
  TempDir dir("schema-hierarchy");
  GltfWriter w = rich_file();
  w.doc["nodes"][3]["children"] = {1};  // node 1 is node 0's child already
  check_error(w.write_gltf(dir / "parents.gltf"),
              {"/nodes/3/children/0: node 1 is already a child of node 0"});
  w.doc["nodes"][3]["children"] = {0};  // node 0 is a root of scene 0
  check_error(w.write_gltf(dir / "root.gltf"),
              {"/scenes/0/nodes/0: node 0 is not a root node (it is a child of node 3)"});
  w.doc["nodes"][3].erase("children");
  w.doc["nodes"][2]["children"] = {0};  // 0 → 2 → 0, in no scene's way first
  w.doc["scenes"][0]["nodes"] = {3};
  check_error(w.write_gltf(dir / "cycle.gltf"), {"/nodes/", "is its own ancestor (a cycle)"});
  w.doc["nodes"][0]["children"] = {1};
  w.doc["nodes"][2]["children"] = {2};
  check_error(w.write_gltf(dir / "self.gltf"),
              {"/nodes/2/children/0: node 2 is its own ancestor (a cycle)"});
  w.doc["nodes"][0]["children"] = {1, 2, 1};
  check_error(w.write_gltf(dir / "twice.gltf"), {"/nodes/0/children/2: 1 is listed twice"});
  w.doc["nodes"][0]["children"] = json::array();
  check_error(w.write_gltf(dir / "empty.gltf"), {"/nodes/0/children: is an empty array"});
}

TEST_CASE("gltf schema: images, and a MIME type this version does not decode warns") {
  TempDir dir("schema-images");
  GltfWriter w = rich_file();
  w.doc["images"][0]["mimeType"] = "image/gif";
  const std::string path = w.write_gltf(dir / "gif.gltf");
  CHECK(warnings(path) == std::vector<std::string>{
                              path + ": /images/0/mimeType: \"image/gif\" is not image/png, "
                                     "image/jpeg or image/webp, the types this version decodes"});
  CHECK(stderr_of([&] { load_gltf(path); }).find("warning: " + path + ": /images/0/mimeType") == 0);
  // WebP is decoded; KTX2 never is, which the loader says of each texture that has one.
  for (const char* type : {"image/png", "image/jpeg", "image/webp", "image/ktx2"}) {
    w.doc["images"][0]["mimeType"] = type;
    CHECK(warnings(w.write_gltf(dir / "typed.gltf")).empty());
  }
  w.doc["images"][0].erase("mimeType");
  check_error(w.write_gltf(dir / "no-mime.gltf"),
              {"/images/0/mimeType: is missing (it is required with a bufferView)"});
  w.doc["images"][0]["mimeType"] = "image/png";
  w.doc["images"][0]["uri"] = "x.png";
  check_error(w.write_gltf(dir / "both.gltf"), {"/images/0: has both a uri and a bufferView"});
  w.doc["images"][0] = {{"mimeType", "image/png"}};
  check_error(w.write_gltf(dir / "neither.gltf"),
              {"/images/0: has neither a uri nor a bufferView"});
}

// ---------------------------------------------------------------------------------------------
// One valid file, broken in many ways: each must be refused naming the element's JSON pointer.

TEST_CASE("gltf schema: every rule, one mutation each") {
  TempDir dir("schema-table");
  // As written: the buffer (a data URI) is in the JSON too.
  const json base = read_json(rich_file().write_gltf(dir / "rich.gltf"));
  struct Mutation {
    const char* pointer;   // what is changed
    json value;            // the new value, or kRemove
    const char* expected;  // the start of the message after "<file>: "; nullptr: still valid
  };
  const Mutation mutations[] = {
      // Root arrays and the default scene.
      {"/nodes", json::array(), "/nodes: is an empty array"},
      {"/meshes", json::object(), "/meshes: an object is not an array of objects"},
      {"/materials/0", 1, "/materials/0: 1 is not an object"},
      {"/materials/0/name", 5, "/materials/0/name: 5 is not a string"},
      {"/scene", 1, "/scene: 1 is not an index (an integer from 0 to 0 for the 1 scene)"},
      {"/scene", -1, "/scene: -1 is not an index"},
      {"/scenes/0/nodes", 0, "/scenes/0/nodes: 0 is not an array of indices"},
      {"/scenes/0/nodes/0", 9, "/scenes/0/nodes/0: 9 is not an index (an integer from 0 to 3"},
      {"/extensions", json::array({1}), "/extensions: an array is not an object"},
      // Buffers and bufferViews.
      {"/buffers/0/byteLength", 0, "/buffers/0/byteLength: 0 is not an integer >= 1"},
      {"/buffers/0/byteLength", kRemove, "/buffers/0/byteLength: is missing"},
      {"/buffers/0/uri", 3, "/buffers/0/uri: 3 is not a string"},
      {"/bufferViews/0/buffer", 1, "/bufferViews/0/buffer: 1 is not an index"},
      {"/bufferViews/0/buffer", kRemove, "/bufferViews/0/buffer: is missing"},
      {"/bufferViews/0/byteLength", 0, "/bufferViews/0/byteLength: 0 is not an integer >= 1"},
      {"/bufferViews/0/byteLength", 36.5, "/bufferViews/0/byteLength: 36.5 is not an integer"},
      {"/bufferViews/0/byteStride", 2,
       "/bufferViews/0/byteStride: 2 is not an integer from 4 to 252"},
      {"/bufferViews/0/byteStride", 256, "/bufferViews/0/byteStride: 256 is not an integer from 4"},
      {"/bufferViews/0/byteStride", 14, "/bufferViews/0/byteStride: 14 is not a multiple of 4"},
      {"/bufferViews/0/target", 34961, "/bufferViews/0/target: 34961 is not one of 34962 or 34963"},
      // Accessors.
      {"/accessors/0/bufferView", "0", "/accessors/0/bufferView: \"0\" is not an index"},
      {"/accessors/0/componentType", 5124, "/accessors/0/componentType: 5124 is not one of"},
      {"/accessors/0/componentType", kRemove, "/accessors/0/componentType: is missing"},
      {"/accessors/0/count", 0, "/accessors/0/count: 0 is not an integer >= 1"},
      {"/accessors/0/count", "3", "/accessors/0/count: \"3\" is not an integer >= 1"},
      {"/accessors/0/type", "VEC5", "/accessors/0/type: \"VEC5\" is not \"SCALAR\", \"VEC2\""},
      {"/accessors/0/type", 3, "/accessors/0/type: 3 is not \"SCALAR\""},
      {"/accessors/0/normalized", 1, "/accessors/0/normalized: 1 is not true or false"},
      {"/accessors/0/normalized", true, "/accessors/0/normalized: is true for a FLOAT"},
      {"/accessors/0/min", {0, 0}, "/accessors/0/min: has 2 elements, where 3 numbers"},
      {"/accessors/0/max/2", "1", "/accessors/0/max/2: \"1\" is not a number"},
      {"/accessors/1/min", {0}, nullptr},  // SCALAR: one number is right (a valid mutation)
      {"/accessors/2/byteOffset", 0, "/accessors/2/byteOffset: is given without a bufferView"},
      {"/accessors/2/sparse/count", 4, "/accessors/2/sparse/count: 4 is more than the accessor's"},
      {"/accessors/2/sparse/count", 0, "/accessors/2/sparse/count: 0 is not an integer >= 1"},
      {"/accessors/2/sparse/indices/componentType", 5126,
       "/accessors/2/sparse/indices/componentType: 5126 is not one of 5121, 5123 or 5125"},
      {"/accessors/2/sparse/indices/bufferView", kRemove,
       "/accessors/2/sparse/indices/bufferView: is missing"},
      {"/accessors/2/sparse/values", kRemove, "/accessors/2/sparse/values: is missing"},
      {"/accessors/2/sparse/values/byteOffset", -4,
       "/accessors/2/sparse/values/byteOffset: -4 is not an integer >= 0"},
      // Images, samplers, textures.
      {"/images/0/bufferView", 9, "/images/0/bufferView: 9 is not an index"},
      {"/images/0/mimeType", 1, "/images/0/mimeType: 1 is not a string"},
      {"/samplers/0/magFilter", 9986, "/samplers/0/magFilter: 9986 is not one of 9728 or 9729"},
      {"/samplers/0/minFilter", 9730, "/samplers/0/minFilter: 9730 is not one of"},
      {"/samplers/0/wrapT", 10496, "/samplers/0/wrapT: 10496 is not one of 33071, 33648 or 10497"},
      {"/textures/0/sampler", 1, "/textures/0/sampler: 1 is not an index"},
      {"/textures/0/source", true, "/textures/0/source: true is not an index"},
      {"/textures/0/extensions",
       {{"EXT_texture_webp", {{"source", 1}}}},
       "/textures/0/extensions/EXT_texture_webp/source: 1 is not an index"},
      {"/textures/0/extensions", {{"EXT_texture_webp", json::object()}}, nullptr},
      {"/textures/0/extensions",
       {{"KHR_texture_basisu", {{"source", 0.5}}}},
       "/textures/0/extensions/KHR_texture_basisu/source: 0.5 is not an index"},
      // Materials and texture infos.
      {"/materials/0/pbrMetallicRoughness",
       {1},
       "/materials/0/pbrMetallicRoughness: an array is not an object"},
      {"/materials/0/pbrMetallicRoughness/metallicFactor", 1.5,
       "/materials/0/pbrMetallicRoughness/metallicFactor: 1.5 is not a number in [0, 1]"},
      {"/materials/0/pbrMetallicRoughness/roughnessFactor", "rough",
       "/materials/0/pbrMetallicRoughness/roughnessFactor: \"rough\" is not a number in [0, 1]"},
      {"/materials/0/emissiveFactor", {1, 1, 1, 1}, "/materials/0/emissiveFactor: has 4 elements"},
      {"/materials/0/emissiveFactor/0", -0.5,
       "/materials/0/emissiveFactor/0: -0.5 is not a number in [0, 1]"},
      {"/materials/0/alphaMode", "opaque", "/materials/0/alphaMode: \"opaque\" is not \"OPAQUE\""},
      {"/materials/0/alphaCutoff", -1, "/materials/0/alphaCutoff: -1 is not a number >= 0"},
      {"/materials/0/doubleSided", "yes", "/materials/0/doubleSided: \"yes\" is not true or false"},
      {"/materials/1/normalTexture/scale",
       {1},
       "/materials/1/normalTexture/scale: an array is not a number"},
      {"/materials/1/occlusionTexture/strength", 2,
       "/materials/1/occlusionTexture/strength: 2 is not a number in [0, 1]"},
      {"/materials/1/emissiveTexture/index", 1,
       "/materials/1/emissiveTexture/index: 1 is not an index (an integer from 0 to 0 for the 1 "
       "texture)"},
      {"/materials/1/emissiveTexture/index", kRemove,
       "/materials/1/emissiveTexture/index: is missing"},
      {"/materials/1/pbrMetallicRoughness/metallicRoughnessTexture/texCoord", -1,
       "/materials/1/pbrMetallicRoughness/metallicRoughnessTexture/texCoord: -1 is not an integer "
       ">= 0"},
      {"/materials/1/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/offset",
       {0, 0, 0},
       "/materials/1/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/"
       "offset: has 3"},
      {"/materials/1/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/"
       "rotation",
       "90",
       "/materials/1/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/"
       "rotation: \"90\" is not a number"},
      {"/materials/1/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/scale/"
       "1",
       nullptr,
       "/materials/1/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/scale/"
       "1: null is not a number"},
      {"/materials/1/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/"
       "texCoord",
       0.5,
       "/materials/1/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/"
       "texCoord: 0.5 is not an integer >= 0"},
      {"/materials/1/extensions/KHR_materials_emissive_strength/emissiveStrength", -2,
       "/materials/1/extensions/KHR_materials_emissive_strength/emissiveStrength: -2 is not a "
       "number >= 0"},
      {"/materials/1/extensions/KHR_materials_ior",
       {{"ior", 0.9}},
       "/materials/1/extensions/KHR_materials_ior/ior: 0.9 is not a number >= 1 or 0"},
      {"/materials/1/extensions/KHR_materials_specular",
       {{"specularFactor", 1.1}},
       "/materials/1/extensions/KHR_materials_specular/specularFactor: 1.1 is not a number in [0, "
       "1]"},
      {"/materials/1/extensions/KHR_materials_specular",
       {{"specularColorTexture", {{"index", -1}}}},
       "/materials/1/extensions/KHR_materials_specular/specularColorTexture/index: -1 is not an "
       "index"},
      {"/materials/1/extensions/KHR_materials_transmission",
       {{"transmissionFactor", true}},
       "/materials/1/extensions/KHR_materials_transmission/transmissionFactor: true is not a "
       "number in [0, 1]"},
      {"/materials/1/extensions/KHR_materials_clearcoat",
       {{"clearcoatFactor", 1.5}},
       "/materials/1/extensions/KHR_materials_clearcoat/clearcoatFactor: 1.5 is not a number in "
       "[0, 1]"},
      {"/materials/1/extensions/KHR_materials_clearcoat",
       {{"clearcoatRoughnessFactor", -0.1}},
       "/materials/1/extensions/KHR_materials_clearcoat/clearcoatRoughnessFactor: -0.1 is not a "
       "number in [0, 1]"},
      {"/materials/1/extensions/KHR_materials_clearcoat",
       {{"clearcoatNormalTexture", {{"index", 0}, {"scale", "2"}}}},
       "/materials/1/extensions/KHR_materials_clearcoat/clearcoatNormalTexture/scale: \"2\" is "
       "not a number"},
      {"/materials/1/extensions/KHR_materials_clearcoat",
       {{"clearcoatRoughnessTexture", {{"index", 7}}}},
       "/materials/1/extensions/KHR_materials_clearcoat/clearcoatRoughnessTexture/index: 7 is not "
       "an index"},
      {"/materials/1/extensions/KHR_materials_sheen",
       {{"sheenColorFactor", {1, 2, 0}}},
       "/materials/1/extensions/KHR_materials_sheen/sheenColorFactor/1: 2 is not a number in [0, "
       "1]"},
      {"/materials/1/extensions/KHR_materials_sheen",
       {{"sheenRoughnessFactor", 2}},
       "/materials/1/extensions/KHR_materials_sheen/sheenRoughnessFactor: 2 is not a number in [0, "
       "1]"},
      {"/materials/1/extensions/KHR_materials_sheen",
       {{"sheenColorTexture", {{"index", 0}, {"texCoord", -1}}}},
       "/materials/1/extensions/KHR_materials_sheen/sheenColorTexture/texCoord: -1 is not an "
       "integer >= 0"},
      {"/materials/1/extensions/KHR_materials_iridescence",
       {{"iridescenceFactor", 1.2}},
       "/materials/1/extensions/KHR_materials_iridescence/iridescenceFactor: 1.2 is not a number "
       "in [0, 1]"},
      {"/materials/1/extensions/KHR_materials_iridescence",
       {{"iridescenceIor", 0.5}},
       "/materials/1/extensions/KHR_materials_iridescence/iridescenceIor: 0.5 is not a number >= "
       "1"},
      {"/materials/1/extensions/KHR_materials_iridescence",
       {{"iridescenceThicknessMinimum", -10}},
       "/materials/1/extensions/KHR_materials_iridescence/iridescenceThicknessMinimum: -10 is not "
       "a number >= 0"},
      {"/materials/1/extensions/KHR_materials_iridescence",
       {{"iridescenceThicknessTexture", {{"index", 9}}}},
       "/materials/1/extensions/KHR_materials_iridescence/iridescenceThicknessTexture/index: 9 is "
       "not an index"},
      {"/materials/1/extensions/KHR_materials_unlit", 1,
       "/materials/1/extensions/KHR_materials_unlit: 1 is not an object"},
      {"/materials/1/extensions/KHR_materials_volume",
       {{"thicknessFactor", -1}},
       "/materials/1/extensions/KHR_materials_volume/thicknessFactor: -1 is not a number >= 0"},
      {"/materials/1/extensions/KHR_materials_volume",
       {{"attenuationDistance", 0}},
       "/materials/1/extensions/KHR_materials_volume/attenuationDistance: 0 is not a number > 0"},
      {"/materials/1/extensions/KHR_materials_volume",
       {{"attenuationColor", {1, 1}}},
       "/materials/1/extensions/KHR_materials_volume/attenuationColor: has 2 elements"},
      {"/materials/1/extensions/KHR_materials_volume",
       {{"attenuationColor", {1, 1.5, 1}}},
       "/materials/1/extensions/KHR_materials_volume/attenuationColor/1: 1.5 is not a number in "
       "[0, 1]"},
      {"/materials/1/extensions/KHR_materials_anisotropy",
       {{"anisotropyStrength", 1.5}},
       "/materials/1/extensions/KHR_materials_anisotropy/anisotropyStrength: 1.5 is not a number "
       "in [0, 1]"},
      {"/materials/1/extensions/KHR_materials_anisotropy",
       {{"anisotropyRotation", nullptr}},
       "/materials/1/extensions/KHR_materials_anisotropy/anisotropyRotation: null is not a "
       "number"},
      {"/materials/1/extensions/KHR_materials_anisotropy",
       {{"anisotropyTexture", {{"index", 7}}}},
       "/materials/1/extensions/KHR_materials_anisotropy/anisotropyTexture/index: 7 is not an "
       "index"},
      {"/materials/1/extensions/KHR_materials_dispersion",
       {{"dispersion", -0.1}},
       "/materials/1/extensions/KHR_materials_dispersion/dispersion: -0.1 is not a number >= 0"},
      // Cameras.
      {"/cameras/0/type", "fisheye",
       "/cameras/0/type: \"fisheye\" is not \"perspective\" or \"orthographic\""},
      {"/cameras/0/type", kRemove, "/cameras/0/type: is missing"},
      {"/cameras/0/type", "orthographic", "/cameras/0/orthographic: is missing"},
      {"/cameras/0/orthographic",
       {{"xmag", 1}, {"ymag", 1}, {"znear", 0}, {"zfar", 1}},
       "/cameras/0: has both perspective and orthographic"},
      {"/cameras/0/perspective/yfov", 0, "/cameras/0/perspective/yfov: 0 is not a number > 0"},
      {"/cameras/0/perspective/yfov", kRemove, "/cameras/0/perspective/yfov: is missing"},
      {"/cameras/0/perspective/znear", 0, "/cameras/0/perspective/znear: 0 is not a number > 0"},
      {"/cameras/0/perspective/zfar", 0.05,
       "/cameras/0/perspective/zfar: 0.05 is not greater than znear 0.1"},
      {"/cameras/0/perspective/aspectRatio", -1.5,
       "/cameras/0/perspective/aspectRatio: -1.5 is not a number > 0"},
      {"/cameras/1/orthographic/xmag", 0, "/cameras/1/orthographic/xmag: is 0"},
      {"/cameras/1/orthographic/ymag", "1", "/cameras/1/orthographic/ymag: \"1\" is not a number"},
      {"/cameras/1/orthographic/znear", -1,
       "/cameras/1/orthographic/znear: -1 is not a number >= 0"},
      {"/cameras/1/orthographic/zfar", kRemove, "/cameras/1/orthographic/zfar: is missing"},
      {"/cameras/1/orthographic/zfar", 0, "/cameras/1/orthographic/zfar: 0 is not a number > 0"},
      // Meshes and primitives.
      {"/meshes/0/primitives", json::array(), "/meshes/0/primitives: is an empty array"},
      {"/meshes/0/primitives/0/attributes", json::object(),
       "/meshes/0/primitives/0/attributes: is an empty object"},
      {"/meshes/0/primitives/0/attributes", kRemove,
       "/meshes/0/primitives/0/attributes: is missing"},
      {"/meshes/0/primitives/0/attributes/NORMAL", 7,
       "/meshes/0/primitives/0/attributes/NORMAL: 7 is not an index (an integer from 0 to 2 for "
       "the 3 accessors)"},
      {"/meshes/0/primitives/0/indices", 1.5,
       "/meshes/0/primitives/0/indices: 1.5 is not an index"},
      {"/meshes/0/primitives/0/material", 2, "/meshes/0/primitives/0/material: 2 is not an index"},
      {"/meshes/0/primitives/0/mode", -1, "/meshes/0/primitives/0/mode: -1 is not one of"},
      {"/meshes/0/primitives/0/mode", "TRIANGLES",
       "/meshes/0/primitives/0/mode: \"TRIANGLES\" is not one of"},
      {"/meshes/0/primitives/0/targets", json::array(),
       "/meshes/0/primitives/0/targets: is an empty array"},
      {"/meshes/0/primitives/0/targets",
       {{{"POSITION", 9}}},
       "/meshes/0/primitives/0/targets/0/POSITION: 9 is not an index"},
      {"/meshes/0/weights", {"a"}, "/meshes/0/weights/0: \"a\" is not a number"},
      // Nodes and skins.
      {"/nodes/0/mesh", 1,
       "/nodes/0/mesh: 1 is not an index (an integer from 0 to 0 for the 1 mesh)"},
      {"/nodes/1/camera", 2,
       "/nodes/1/camera: 2 is not an index (an integer from 0 to 1 for the 2 cameras)"},
      {"/nodes/0/skin", 1, "/nodes/0/skin: 1 is not an index"},
      {"/nodes/3/skin", 0, "/nodes/3/skin: is given without a mesh"},
      {"/nodes/0/children/0", 4, "/nodes/0/children/0: 4 is not an index"},
      {"/nodes/1/matrix",
       {1, 0, 0, 0},
       "/nodes/1/matrix: has 4 elements, where 16 numbers are required"},
      {"/nodes/1/translation", {0, 0, 0}, "/nodes/1/matrix: is given with translation"},
      {"/nodes/0/translation", {0, 0}, "/nodes/0/translation: has 2 elements, where 3 numbers"},
      {"/nodes/0/rotation",
       {0, 0, 1},
       "/nodes/0/rotation: has 3 elements, where 4 numbers in [-1, 1]"},
      {"/nodes/0/rotation/3", 1.5, "/nodes/0/rotation/3: 1.5 is not a number in [-1, 1]"},
      {"/nodes/0/scale", "1", "/nodes/0/scale: \"1\" is not an array of 3 numbers"},
      {"/nodes/0/weights", json::array(), "/nodes/0/weights: is an empty array"},
      {"/nodes/2/extensions/KHR_lights_punctual/light", 1,
       "/nodes/2/extensions/KHR_lights_punctual/light: 1 is not an index (an integer from 0 to 0 "
       "for the 1 light)"},
      {"/nodes/2/extensions/KHR_lights_punctual", json::object(),
       "/nodes/2/extensions/KHR_lights_punctual/light: is missing"},
      {"/nodes/0/extensions",
       {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", -1}}}}}},
       "/nodes/0/extensions/EXT_mesh_gpu_instancing/attributes/TRANSLATION: -1 is not an index"},
      {"/nodes/0/extensions",
       {{"EXT_mesh_gpu_instancing", json::object()}},
       "/nodes/0/extensions/EXT_mesh_gpu_instancing/attributes: is missing"},
      {"/skins/0/joints", json::array(), "/skins/0/joints: is an empty array"},
      {"/skins/0/joints/0", 4, "/skins/0/joints/0: 4 is not an index"},
      {"/skins/0/inverseBindMatrices", 4, "/skins/0/inverseBindMatrices: 4 is not an index"},
      {"/skins/0/skeleton", "3", "/skins/0/skeleton: \"3\" is not an index"},
      // KHR_lights_punctual.
      {"/extensions/KHR_lights_punctual/lights", json::array(),
       "/extensions/KHR_lights_punctual/lights: is an empty array"},
      {"/extensions/KHR_lights_punctual", json::object(),
       "/extensions/KHR_lights_punctual/lights: is missing"},
      {"/extensions/KHR_lights_punctual/lights/0/type", 7,
       "/extensions/KHR_lights_punctual/lights/0/type: 7 is not \"directional\", \"point\" "
       "or \"spot\""},
      // A type string the extension does not define: valid (the validator warns), the light is
      // skipped with a warning (gltf_errors_test).
      {"/extensions/KHR_lights_punctual/lights/0/type", "area", nullptr},
      {"/extensions/KHR_lights_punctual/lights/0/color",
       {1, 1, 1, 1},
       "/extensions/KHR_lights_punctual/lights/0/color: has 4 elements, where 3 numbers in [0, 1]"},
      {"/extensions/KHR_lights_punctual/lights/0/color/1", 2,
       "/extensions/KHR_lights_punctual/lights/0/color/1: 2 is not a number in [0, 1]"},
      {"/extensions/KHR_lights_punctual/lights/0/intensity", -1,
       "/extensions/KHR_lights_punctual/lights/0/intensity: -1 is not a number >= 0"},
      {"/extensions/KHR_lights_punctual/lights/0/range", 0,
       "/extensions/KHR_lights_punctual/lights/0/range: 0 is not a number > 0"},
      {"/extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle", 1.6,
       "/extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle: 1.6 is not a number in (0, "
       "pi/2]"},
      {"/extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle", 0,
       "/extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle: 0 is not a number in (0, "
       "pi/2]"},
      {"/extensions/KHR_lights_punctual/lights/0/spot/innerConeAngle", -0.1,
       "/extensions/KHR_lights_punctual/lights/0/spot/innerConeAngle: -0.1 is not a number in [0, "
       "pi/2]"},
      {"/extensions/KHR_lights_punctual/lights/0/spot/innerConeAngle", 0.5,
       "/extensions/KHR_lights_punctual/lights/0/spot/innerConeAngle: is not less than "
       "outerConeAngle"},
      {"/extensions/KHR_lights_punctual/lights/0/spot",
       {{"innerConeAngle", 0.8}},  // outer π/4
       "/extensions/KHR_lights_punctual/lights/0/spot/innerConeAngle: is not less than "
       "outerConeAngle"},
  };
  size_t refused = 0;
  for (const Mutation& m : mutations) {
    CAPTURE(m.pointer);
    const std::string path = dir / "mutated.gltf";
    dacrt::test::write_text(path, mutated(base, m.pointer, m.value).dump(1));
    if (!m.expected) {
      CHECK(load_gltf(path).geometry.size() == 2);
      continue;
    }
    check_error(path, {std::string(": ") + m.expected});
    ++refused;
  }
  CHECK(refused > 100);
}

TEST_CASE("gltf schema: extensions used but not read are named in one warning, with counts") {
  TempDir dir("schema-unread");
  GltfWriter w = rich_file();
  w.doc["extensionsUsed"].push_back("KHR_materials_diffuse_transmission");
  w.doc["extensionsUsed"].push_back("EXT_listed_only");
  w.doc["materials"][0]["extensions"]["KHR_materials_diffuse_transmission"] = {{"diffuseTransmissionFactor", 1.0}};
  w.doc["materials"][1]["extensions"]["KHR_materials_diffuse_transmission"] = {{"diffuseTransmissionFactor", 0.5}};
  w.doc["nodes"][0]["extensions"]["EXT_vendor_thing"] = json::object();
  w.doc["materials"][0]["occlusionTexture"] = {{"index", 0}};
  // Metadata (KHR_xmp_json_ld, and the older KHR_xmp) has nothing to render: not named.
  w.doc["extensionsUsed"].push_back("KHR_xmp_json_ld");
  w.doc["extensionsUsed"].push_back("KHR_xmp");
  w.doc["extensions"]["KHR_xmp_json_ld"] = {{"packets", json::array({json::object()})}};
  w.doc["nodes"][0]["extensions"]["KHR_xmp_json_ld"] = {{"packet", 0}};
  w.doc["extensions"]["KHR_xmp"] = json::object();
  const std::string path = w.write_gltf(dir / "unread.gltf");
  Scene scene;
  const std::string err = stderr_of([&] { scene = load_gltf(path); });
  INFO(err);
  CHECK(std::count(err.begin(), err.end(), '\n') == 1);
  CHECK(err.find("warning: " + path +
                 ": extensions not read in this version (rendered without "
                 "them): EXT_listed_only (listed in extensionsUsed), EXT_vendor_thing (1 node), "
                 "KHR_materials_diffuse_transmission (2 materials)") != std::string::npos);
  CHECK(scene.ignored.extensions.at("KHR_materials_diffuse_transmission").at("material") == 2);
  CHECK(scene.ignored.occlusion_textures == 2);  // and the rich file's textured material
  // Extensions that are read are not named; nothing unread, no warning.
  CHECK(scene.ignored.extensions.count("KHR_texture_transform") == 0);
  CHECK(err.find("KHR_xmp") == std::string::npos);
  CHECK(scene.ignored.extensions.count("KHR_xmp_json_ld") == 0);
}
