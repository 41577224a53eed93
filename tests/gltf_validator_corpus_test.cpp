// The Khronos glTF-Validator's own test corpus (../shared/gltf-validator-tests: ~370 files, each
// with the validator's expected report) through the loader. Skipped, with a message, when ../shared
// is absent.
//
// Most corpus files hold meshes without a scene (the validator checks them all; a renderer reads
// what a scene draws), so each .gltf with meshes is loaded twice: as it is, and with every mesh
// placed by a new node in a new default scene with every root node ("instanced"), which makes
// the loader read them.
// What is checked:
// - every file loads or is refused with one line naming the file, in both forms: no crash (the
//   sanitizer build runs this too), no hang (ctest's timeout);
// - every valid file loads in both forms, but for the refusals listed in kValidRefused;
// - an invalid file listed in kLoadsDespiteErrors (with why) loads; any other invalid file is
//   refused (in one form at least), the line naming the element. Files of features not
//   read yet (kUnread) are only checked not to crash.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "dacrt/io/gltf.h"
#include "tests/captured_stderr.h"
#include "dacrt/util/error.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kCorpus = DACRT_SOURCE_DIR "/../shared/gltf-validator-tests";

// Invalid files that load, by why: their errors concern what the loader does not read, or reads as
// meant, or data it reads only when the render uses it (images of sampled textures, buffer views
// of drawn accessors), which these files do not use (other tests check those refusals).
const std::vector<std::pair<std::string, std::vector<std::string>>> kLoadsDespiteErrors = {
    {"accessor min/max are not used: bounds come from the data",
     {"base/data/accessor_data/out_of_range_elements_float.gltf",
      "base/data/accessor_data/out_of_range_elements_sint16.gltf",
      "base/data/accessor_data/out_of_range_elements_sint8.gltf",
      "base/data/accessor_data/out_of_range_elements_uint16.gltf",
      "base/data/accessor_data/out_of_range_elements_uint32.gltf",
      "base/data/accessor_data/out_of_range_elements_uint8.gltf",
      "base/data/mesh/position_accessor_no_bounds.gltf"}},
    {"normals and tangents are normalised, a tangent's w read by its sign",
     {"base/data/mesh_data/normals_tangents_non_unit_invalid_sign.gltf"}},
    {"normals and tangents are generated when absent",
     {"ext/KHR_materials_anisotropy/data/material/no_tangent_space.gltf",
      "ext/KHR_materials_clearcoat/data/material/no_tangent_space.gltf"}},
    {"attributes the loader does not read (custom, unknown names)",
     {"base/data/mesh/accessor_attribute_uint32.gltf", "base/data/mesh/invalid_attribute.gltf",
      "base/data/mesh/invalid_attribute_escaped_name.gltf"}},
    {"a node's matrix is used as it is", {"base/data/node/matrix_indecomposable.gltf"}},
    {"GLB and JSON framing read leniently: a UTF-8 byte-order mark skipped, unaligned chunk "
     "lengths read as given, a second BIN chunk not read",
     {"base/data/glb/bom.glb", "base/data/json/bom.gltf", "base/data/glb/unaligned_chunk.glb",
      "base/data/glb/json_and_two_buffers.glb"}},
    {"extensions are read whether extensionsUsed/Required list them or not, and not read where "
     "they do not belong",
     {"base/data/root/extensions_undeclared_wrong_pointer.gltf",
      "ext/EXT_texture_webp/data/texture/undeclared_extension.gltf",
      "ext/EXT_texture_webp/data/texture/unexpected_extension.gltf",
      "ext/KHR_lights_punctual/data/node/unexpected_extension.gltf",
      "ext/KHR_materials_anisotropy/data/material/unexpected_extension.gltf",
      "ext/KHR_materials_clearcoat/data/material/unexpected_extension.gltf",
      "ext/KHR_materials_dispersion/data/material/unexpected_extension.gltf",
      "ext/KHR_materials_emissive_strength/data/material/unexpected_extension.gltf",
      "ext/KHR_materials_ior/data/material/unexpected_extension.gltf",
      "ext/KHR_materials_iridescence/data/material/unexpected_extension.gltf",
      "ext/KHR_materials_pbrSpecularGlossiness/data/material/unexpected_extension.gltf",
      "ext/KHR_materials_sheen/data/material/unexpected_extension.gltf",
      "ext/KHR_materials_specular/data/material/unexpected_extension.gltf",
      "ext/KHR_materials_transmission/data/material/unexpected_extension.gltf",
      "ext/KHR_materials_unlit/data/material/unexpected_extension.gltf",
      "ext/KHR_materials_variants/data/primitive/unexpected_extension.gltf",
      "ext/KHR_materials_volume/data/material/unexpected_extension.gltf",
      "ext/KHR_mesh_quantization/data/primitive/non_required.gltf",
      "ext/KHR_mesh_quantization/data/primitive/unexpected_extension.gltf",
      "ext/KHR_node_visibility/data/node/unexpected_extension.gltf",
      "ext/KHR_texture_transform/data/textureInfo/unexpected_extension.gltf"}},
    {"textures without a source image are not sampled (with a warning), so the TEXCOORD set "
     "they name is not needed",
     {"base/data/mesh/uv.gltf", "ext/KHR_texture_transform/data/textureInfo/uv_sets.gltf"}},
    {"unused: accessors, buffer views and images no drawn primitive or sampled texture reads",
     {"base/data/accessor_data/invalid_elements_float.gltf",
      "base/data/buffer_view/invalid_length.gltf",
      "base/data/buffer_view/invalid_stride_too_big.gltf",
      "base/data/buffer_view/invalid_stride_wrong_target.gltf",
      "base/data/image/invalid_data_uri_mime_type.gltf", "base/data/image/invalid_image_data.gltf",
      "base/data/image/invalid_uri_scheme.gltf", "base/data/image/not_found.gltf",
      "base/data/image/png_eos.gltf", "ext/EXT_texture_webp/data/image/undeclared_extension.gltf",
      "ext/EXT_texture_webp/data/texture/invalid_image_mime_type.gltf"}},
};

std::string loads_despite_errors(const std::string& name) {
  for (const auto& [why, files] : kLoadsDespiteErrors)
    if (std::find(files.begin(), files.end(), name) != files.end()) return why;
  return "";
}

// Valid files that are refused, with a word of the refusal: buffers that have no data here
// (placeholders without a uri, http:// URIs, a data URI that is not base64), an accessor type the
// spec does not define (the validator only warns; tinygltf cannot read the file), and a glTF 2.1
// asset that requires a 2.1 reader.
const std::map<std::string, std::string> kValidRefused = {
    {"base/data/accessor/valid.gltf", "buffer 0"},
    {"base/data/buffer/custom_property.gltf", "buffer 0"},
    {"base/data/root/named_objects.gltf", "buffer 0"},
    {"base/data/root/unused_objects.gltf", "buffer 0"},
    {"base/data/json/integer_written_as_float.gltf", "buffer 0"},
    {"base/data/buffer/valid_placeholder.glb", "buffer 1"},
    {"base/data/buffer/non_relative_uri.gltf", "http://"},
    {"base/data/buffer/data_uri.glb", "buffer 0"},
    {"base/data/accessor/unknown_type.gltf", "/accessors/0/type"},
    {"base/data/asset/min_version_valid.gltf", "2.1"},
};

// Files of features checked elsewhere or not read yet, only checked not to crash here: animation,
// skins and morph targets (tests/animation_corpus_test.cpp holds their exceptions).
const std::vector<std::string> kUnread = {
    "base/data/animation",       "base/data/skin",
    "ext/KHR_animation_pointer",
    "base/data/mesh/morph_",     "base/data/node/node_weights_invalid",
    "base/data/node/node_skin_",  "base/data/mesh/unequal_joints",
    "base/data/mesh_data/joints_", "base/data/mesh/invalid_indexed_attribute",
};

struct Case {
  fs::path file;
  std::string name;  // relative to the corpus
  std::set<std::string> errors;  // the validator's error codes (severity 0)
};

std::vector<Case> corpus() {
  std::vector<Case> cases;
  for (const auto& entry : fs::recursive_directory_iterator(kCorpus)) {
    const std::string report = entry.path().string();
    const std::string suffix = ".report.json";
    if (report.size() <= suffix.size() || !report.ends_with(suffix)) continue;
    Case c;
    c.file = report.substr(0, report.size() - suffix.size());
    c.name = fs::relative(c.file, kCorpus).generic_string();
    std::ifstream in(entry.path());
    const json r = json::parse(in);
    for (const json& m : r.at("issues").at("messages"))
      if (m.at("severity") == 0) c.errors.insert(m.at("code").get<std::string>());
    CHECK(c.errors.size() <= r.at("issues").at("numErrors").get<size_t>());
    cases.push_back(std::move(c));
  }
  std::sort(cases.begin(), cases.end(), [](const Case& a, const Case& b) { return a.name < b.name; });
  return cases;
}

std::vector<unsigned char> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The .gltf with a new default scene of its root nodes (those no node lists as a child) and of
// each mesh placed by a new node, or nothing (a GLB, JSON that does not parse, no meshes or
// nodes).
std::optional<std::vector<unsigned char>> instanced(const fs::path& file) {
  if (file.extension() != ".gltf") return std::nullopt;
  const std::vector<unsigned char> bytes = read_bytes(file);
  json doc = json::parse(bytes.begin(), bytes.end(), nullptr, false);
  if (!doc.is_object()) return std::nullopt;
  const json none = json::array();
  const json& meshes = doc.contains("meshes") ? doc["meshes"] : none;
  if (!meshes.is_array() || (meshes.empty() && !doc.contains("nodes"))) return std::nullopt;
  for (const char* array : {"nodes", "scenes"})
    if (!doc.contains(array)) doc[array] = json::array();
  if (!doc["nodes"].is_array() || !doc["scenes"].is_array()) return std::nullopt;
  std::set<json> children;
  for (const json& node : doc["nodes"])
    if (node.is_object() && node.contains("children") && node["children"].is_array())
      children.insert(node["children"].begin(), node["children"].end());
  json roots = json::array();
  for (size_t n = 0; n < doc["nodes"].size(); ++n)
    if (!children.count(json(n))) roots.push_back(n);
  for (size_t m = 0; m < meshes.size(); ++m) {
    roots.push_back(doc["nodes"].size());
    doc["nodes"].push_back({{"mesh", m}});
  }
  doc["scenes"].push_back({{"nodes", roots}});
  doc["scene"] = doc["scenes"].size() - 1;
  const std::string text = doc.dump();
  return std::vector<unsigned char>(text.begin(), text.end());
}

struct Outcome {
  bool loaded = false;
  std::string message;  // the refusal
};

Outcome load(const fs::path& file, const std::vector<unsigned char>& bytes) {
  Outcome out;
  dacrt::test::CapturedStderr quiet;  // the loader's warnings
  try {
    dacrt::load_gltf_memory(file.string(), bytes.data(), bytes.size());
    out.loaded = true;
  } catch (const dacrt::Error& e) {
    out.message = e.what();
  }
  return out;
}

bool starts_with_any(const std::string& name, const std::vector<std::string>& prefixes) {
  return std::any_of(prefixes.begin(), prefixes.end(),
                     [&](const std::string& p) { return name.starts_with(p); });
}

// A refusal is one line: the file, then the element at fault.
void check_refusal(const Case& c, const Outcome& o) {
  CAPTURE(o.message);
  CHECK(o.message.find('\n') == std::string::npos);
  CHECK(o.message.starts_with(c.file.string() + ": "));
  CHECK(o.message.size() > c.file.string().size() + 8);
}

}  // namespace

TEST_CASE("gltf validator corpus: valid files load, invalid ones touching what is read refused") {
  if (!fs::exists(kCorpus)) {
    MESSAGE("../shared/gltf-validator-tests is absent: skipped");
    return;
  }
  const std::vector<Case> cases = corpus();
  REQUIRE(cases.size() > 300);
  size_t valid_loaded = 0, refused = 0, tolerated = 0, unread = 0;
  std::set<std::string> codes_refused;
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const Outcome as_is = load(c.file, read_bytes(c.file));
    std::optional<Outcome> placed;
    if (auto bytes = instanced(c.file)) placed = load(c.file, *bytes);
    if (!as_is.loaded) check_refusal(c, as_is);
    if (placed && !placed->loaded) check_refusal(c, *placed);
    const bool loaded = as_is.loaded && (!placed || placed->loaded);
    const std::string message = !as_is.loaded ? as_is.message : placed ? placed->message : "";
    CAPTURE(message);

    if (starts_with_any(c.name, kUnread)) {
      ++unread;
      continue;
    }
    if (c.errors.empty()) {
      if (auto it = kValidRefused.find(c.name); it != kValidRefused.end()) {
        CHECK_FALSE(loaded);
        CHECK(message.find(it->second) != std::string::npos);
      } else {
        CHECK(loaded);
        valid_loaded += loaded;
      }
      continue;
    }
    if (const std::string why = loads_despite_errors(c.name); !why.empty()) {
      CAPTURE(why);
      CHECK(loaded);
      tolerated += loaded;
    } else {
      CHECK_FALSE(loaded);
      refused += !loaded;
      if (!loaded) codes_refused.insert(c.errors.begin(), c.errors.end());
    }
  }
  MESSAGE(valid_loaded << " valid files load, " << refused << " invalid ones are refused, "
                       << tolerated << " load with tolerated errors, " << unread
                       << " concern features not read (not crashing)");
  // The refusals cover the errors that matter most for what is read.
  for (const char* code : {"ACCESSOR_INDEX_OOB", "ACCESSOR_INDEX_PRIMITIVE_RESTART",
                           "ACCESSOR_NON_CLAMPED", "MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT",
                           "KHR_MATERIALS_VARIANTS_NON_UNIQUE_VARIANT", "ROTATION_NON_UNIT",
                           "ACCESSOR_TOO_LONG", "NODE_LOOP", "GLB_LENGTH_MISMATCH"}) {
    CAPTURE(code);
    CHECK(codes_refused.count(code));
  }
}

TEST_CASE("gltf validator corpus: the lists of exceptions name corpus files of the right kind") {
  if (!fs::exists(kCorpus)) {
    MESSAGE("../shared/gltf-validator-tests is absent: skipped");
    return;
  }
  std::set<std::string> valid, invalid;
  for (const Case& c : corpus()) (c.errors.empty() ? valid : invalid).insert(c.name);
  for (const auto& [why, files] : kLoadsDespiteErrors)
    for (const std::string& name : files) {
      CAPTURE(name);
      CHECK(invalid.count(name));
    }
  for (const auto& [name, word] : kValidRefused) {
    CAPTURE(name);
    CHECK(valid.count(name));
  }
}
