// The glTF 2.0 schema check (io/gltf/schema.h). Only known properties are descended into, so the
// recursion is as deep as the schema, whatever the file's nesting. Unknown properties pass (the
// spec allows them), and so do extensions a file only uses; animations and the content of extras
// (which the spec lets be any JSON value) are not looked at. This file runs the check and checks
// the root's members; the Checker and the files that check each element kind are named in
// schema_checker.h.
//
// Where this is stricter than the glTF-Validator, and why:
// - Integers must be written as integer literals. JSON Schema (draft 2020-12, the dialect of the
//   glTF 2.0.1 schemas) counts 3.0 as an integer, and the validator accepts it since it dropped
//   INTEGER_WRITTEN_AS_FLOAT; but tinygltf reads integers only from integer literals and treats an
//   optional "mesh": 1.0 as absent, so such a file would render other than it says.
// - Enum values outside the schema's lists (a primitive mode of 99, an unknown componentType,
//   alphaMode, wrap mode...) are errors. The schema leaves room for values that extensions define,
//   and the validator only warns about them (VALUE_NOT_IN_LIST), but no extension the loader reads
//   defines any, so the loader could only guess. Image MIME types are the exception: extensions
//   add some, with a PNG or JPEG fallback; types other than PNG, JPEG, WebP (EXT_texture_webp,
//   read) and KTX2 (KHR_texture_basisu, whose fallback the loader uses and warns about) warn.
// - Integers are bounded by what tinygltf stores them in (int, or 2^53 where it keeps size_t).
#include "dacrt/io/gltf/schema.h"

#include <algorithm>
#include <iterator>
#include <utility>

#include "dacrt/io/gltf/schema_checker.h"

namespace dacrt::gltf::schema {
namespace {

// "major.minor", each a few digits.
bool version(const json& v, int& major, int& minor) {
  if (!v.is_string()) return false;
  const std::string& s = v.get_ref<const std::string&>();
  const size_t dot = s.find('.');
  auto digits = [](std::string_view d, int& out) {
    if (d.empty() || d.size() > 6) return false;
    out = 0;
    for (char c : d) {
      if (c < '0' || c > '9') return false;
      out = out * 10 + (c - '0');
    }
    return true;
  };
  return dot != std::string::npos && digits(std::string_view(s).substr(0, dot), major) &&
         digits(std::string_view(s).substr(dot + 1), minor);
}

}  // namespace

SchemaCheck Checker::run() {
  if (!root_.is_object())
    throw Error(path_ + ": the JSON is " + describe(root_) + ", not an object");
  const Pointer top;
  property(root_, top);
  asset(top);
  extension_lists(top);
  // The root arrays first: the index checks need their sizes.
  for (const Kind& k : kKinds) {
    if (std::string_view(k.array) == "lights") continue;
    if (const json* a = has(root_, top, k.array)) {
      array(*a, top / k.array, "an array of objects");
      for (size_t i = 0; i < a->size(); ++i) child_of_root((*a)[i], top / k.array / i);
    }
  }
  if (const json* lights = light_list()) light_count_ = lights->size();
  if (const json* x = extension(root_, top, "KHR_materials_variants")) {
    const Pointer at = top / "extensions" / "KHR_materials_variants";
    const json& variants = array(need(*x, at, "variants"), at / "variants", "an array of objects");
    for (size_t i = 0; i < variants.size(); ++i) {
      property(variants[i], at / "variants" / i);
      string(need(variants[i], at / "variants" / i, "name"), at / "variants" / i / "name");
    }
    variant_count_ = variants.size();
  }
  index_member(root_, top, "scene", "scenes");

  each("buffers", &Checker::buffer);
  each("bufferViews", &Checker::buffer_view);
  each("accessors", &Checker::accessor);
  each("images", &Checker::image);
  each("samplers", &Checker::sampler);
  each("textures", &Checker::texture);
  each("materials", &Checker::material);
  each("cameras", &Checker::camera);
  each("meshes", &Checker::mesh);
  each("skins", &Checker::skin);
  each("nodes", &Checker::node);
  each("scenes", &Checker::scene);
  if (const json* lights = light_list())
    for (size_t i = 0; i < lights->size(); ++i)
      light((*lights)[i], top / "extensions" / "KHR_lights_punctual" / "lights" / i);
  hierarchy();
  return {std::move(warnings_), whole_floats_};
}

// ---- the root's members

void Checker::asset(const Pointer& top) {
  const Pointer at = top / "asset";
  const json& a = property(need(root_, top, "asset"), at);
  for (const char* key : {"copyright", "generator"})
    if (const json* v = has(a, at, key)) string(*v, at / key);
  int major = 0, minor = 0;
  const json& v = need(a, at, "version");
  if (!version(v, major, minor))
    fail(at / "version", describe(v) + " is not a glTF version (\"major.minor\", as \"2.0\")");
  if (major != 2) fail(at / "version", "glTF " + v.get<std::string>() + " is not glTF 2.x");
  if (const json* m = has(a, at, "minVersion")) {
    int min_major = 0, min_minor = 0;
    if (!version(*m, min_major, min_minor))
      fail(at / "minVersion", describe(*m) + " is not a glTF version (\"major.minor\")");
    if (std::pair(min_major, min_minor) > std::pair(major, minor))
      fail(at / "minVersion",
           m->get<std::string>() + " is greater than the version " + v.get<std::string>());
    if (std::pair(min_major, min_minor) > std::pair(2, 0))
      fail(at / "minVersion",
           "the file needs a glTF " + m->get<std::string>() + " reader; this one reads glTF 2.0");
  }
  if (minor > 0)
    warn(at / "version", "glTF " + v.get<std::string>() + " is newer than 2.0; read as 2.0");
}

void Checker::extension_lists(const Pointer& top) const {
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    const json* list = has(root_, top, key);
    if (!list) continue;
    const Pointer at = top / key;
    array(*list, at, "an array of extension names");
    for (size_t i = 0; i < list->size(); ++i) {
      const json& name = (*list)[i];
      if (!name.is_string()) fail(at / i, describe(name) + " is not an extension name (a string)");
      for (size_t j = 0; j < i; ++j)
        if ((*list)[j] == name) fail(at / i, describe(name) + " is listed twice");
    }
  }
  const json* required = has(root_, top, "extensionsRequired");
  if (!required) return;
  const json* used = has(root_, top, "extensionsUsed");
  for (size_t i = 0; i < required->size(); ++i) {
    const std::string& name = (*required)[i].get_ref<const std::string&>();
    if (!used || std::find(used->begin(), used->end(), (*required)[i]) == used->end())
      fail(top / "extensionsRequired" / i,
           describe((*required)[i]) + " is required but not listed in extensionsUsed");
    if (!gltf_extension_supported(name))
      fail(top / "extensionsRequired" / i,
           "requires extension " + describe((*required)[i]) + ", which is not supported" +
               (name == "KHR_texture_basisu"
                    ? " (its images are KTX2, and this version has no KTX2 decoder)"
                    : ""));
  }
}

const json* Checker::light_list() const {
  const Pointer top;
  const json* x = extension(root_, top, "KHR_lights_punctual");
  if (!x) return nullptr;
  const Pointer at = top / "extensions" / "KHR_lights_punctual";
  const json& lights = array(need(*x, at, "lights"), at / "lights", "an array of objects");
  for (size_t i = 0; i < lights.size(); ++i) child_of_root(lights[i], at / "lights" / i);
  return &lights;
}

}  // namespace dacrt::gltf::schema

namespace dacrt {
namespace {

// The extensions the loader (io/gltf/) reads.
constexpr std::string_view kSupportedExtensions[] = {
    "EXT_mesh_gpu_instancing",    "EXT_meshopt_compression", "EXT_texture_webp",
    "KHR_draco_mesh_compression", "KHR_lights_punctual",     "KHR_materials_anisotropy",
    "KHR_materials_clearcoat",
    "KHR_materials_dispersion",   "KHR_materials_emissive_strength",
    "KHR_materials_ior",          "KHR_materials_iridescence",
    "KHR_materials_sheen",        "KHR_materials_specular",
    "KHR_materials_transmission", "KHR_materials_unlit",     "KHR_materials_variants",
    "KHR_materials_volume",       "KHR_mesh_quantization",   "KHR_texture_transform"};

}  // namespace

bool gltf_extension_supported(std::string_view name) {
  return std::find(std::begin(kSupportedExtensions), std::end(kSupportedExtensions), name) !=
         std::end(kSupportedExtensions);
}

SchemaCheck check_gltf_schema(const std::string& path, const nlohmann::json& doc) {
  return gltf::schema::Checker(path, doc).run();
}

}  // namespace dacrt
