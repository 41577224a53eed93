// The glTF 2.0 schema check (io/gltf/schema.h). Only known properties are descended into, so the
// recursion is as deep as the schema, whatever the file's nesting. Unknown properties pass (the
// spec allows them), and so do extensions a file only uses; animations and the content of extras
// (which the spec lets be any JSON value) are not looked at.
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
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <type_traits>

#include "dacrt/util/error.h"

namespace dacrt {

namespace {

using json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
// tinygltf keeps byte offsets, lengths and counts as size_t: bounded where a double is still exact.
constexpr int64_t kMaxSize = int64_t(1) << 53;
// ... and indices, enums, texCoord sets and sparse counts and offsets as int.
constexpr int64_t kMaxInt = std::numeric_limits<int32_t>::max();

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

// The root arrays (each an array of at least one object), and what one element is called.
struct Kind {
  const char* array;
  const char* one;
};
constexpr Kind kKinds[] = {
    {"accessors", "accessor"},     {"animations", "animation"}, {"buffers", "buffer"},
    {"bufferViews", "bufferView"}, {"cameras", "camera"},       {"images", "image"},
    {"materials", "material"},     {"meshes", "mesh"},          {"nodes", "node"},
    {"samplers", "sampler"},       {"scenes", "scene"},         {"skins", "skin"},
    {"textures", "texture"},       {"lights", "light"}};  // KHR_lights_punctual

std::string str(int64_t n) {
  return std::to_string(n);
}

// A JSON Pointer (RFC 6901) to the element being checked, as messages name it.
class Pointer {
 public:
  Pointer operator/(std::string_view key) const {
    Pointer p = *this;
    p.text_ += '/';
    if (key.size() > 64) key = key.substr(0, 64);  // keys come from the file
    for (char c : key) {
      if (c == '~')
        p.text_ += "~0";
      else if (c == '/')
        p.text_ += "~1";
      else
        p.text_ += static_cast<unsigned char>(c) < 0x20 ? '?' : c;  // the message stays one line
    }
    return p;
  }
  Pointer operator/(size_t index) const {
    Pointer p = *this;
    p.text_ += '/' + std::to_string(index);
    return p;
  }
  const std::string& str() const { return text_; }

 private:
  std::string text_;
};

// A value as a message shows it: numbers and short strings as written, containers by kind.
std::string describe(const json& v) {
  switch (v.type()) {
    case json::value_t::number_integer:
      return std::to_string(v.get<int64_t>());
    case json::value_t::number_unsigned:
      return std::to_string(v.get<uint64_t>());
    case json::value_t::number_float: {
      // nlohmann reads integer literals past 2^64 as doubles: shown as the integers they were.
      const double x = v.get<double>();
      if (x != std::floor(x) || std::abs(x) >= 1e21) return v.dump();
      char digits[32];
      std::snprintf(digits, sizeof digits, "%.0f", x);
      return std::string(digits) + (std::abs(x) < 0x1p53 ? ".0" : "");
    }
    case json::value_t::string: {
      std::string s = v.dump();  // quoted, control characters escaped
      if (s.size() <= 66) return s;
      size_t cut = 64;
      while (cut > 1 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;  // UTF-8
      return s.substr(0, cut) + "...\"";
    }
    case json::value_t::boolean:
      return v.get<bool>() ? "true" : "false";
    case json::value_t::null:
      return "null";
    case json::value_t::array:
      return "an array";
    case json::value_t::object:
      return "an object";
    default:
      return "a value";
  }
}

// A range of numbers and how messages say it.
struct Range {
  double lo, hi;
  bool lo_open, hi_open;
  const char* text;
  bool contains(double x) const {
    return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
  }
};
constexpr Range kAnyNumber{-kInf, kInf, false, false, ""};
constexpr Range kUnit{0.0, 1.0, false, false, " in [0, 1]"};
constexpr Range kSignedUnit{-1.0, 1.0, false, false, " in [-1, 1]"};
constexpr Range kNonNegative{0.0, kInf, false, false, " >= 0"};
constexpr Range kPositive{0.0, kInf, true, false, " > 0"};
constexpr Range kInnerCone{0.0, kPi / 2, false, false, " in [0, pi/2]"};
constexpr Range kOuterCone{0.0, kPi / 2, true, false, " in (0, pi/2]"};

template <class T>
std::string one_of(std::initializer_list<T> values) {
  std::string out;
  size_t i = 0;
  for (const T& v : values) {
    if (i++) out += i == values.size() ? " or " : ", ";
    if constexpr (std::is_arithmetic_v<T>)
      out += std::to_string(v);
    else
      out += '"' + std::string(v) + '"';
  }
  return out;
}

class Checker {
 public:
  Checker(const std::string& path, const json& root) : path_(path), root_(root) {}

  SchemaCheck run() {
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
      const json& variants =
          array(need(*x, at, "variants"), at / "variants", "an array of objects");
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

 private:
  [[noreturn]] void fail(const Pointer& at, const std::string& what) const {
    throw Error(path_ + ": " + at.str() + ": " + what);
  }
  void warn(const Pointer& at, const std::string& what) {
    warnings_.push_back(path_ + ": " + at.str() + ": " + what);
  }

  size_t count(std::string_view array) const {
    if (array == "lights") return light_count_;
    if (array == "variants") return variant_count_;
    auto a = root_.find(array);
    return a == root_.end() ? 0 : a->size();  // checked to be an array first
  }
  static const char* singular(std::string_view array) {
    for (const Kind& k : kKinds)
      if (array == k.array) return k.one;
    return "element";
  }

  template <class Check>
  void each(const char* array, Check check) {
    if (const json* a = has(root_, Pointer(), array))
      for (size_t i = 0; i < a->size(); ++i) (this->*check)((*a)[i], Pointer() / array / i);
  }

  // Member `key` of object `o` (at `at`), or nullptr; a `required` one must be there.
  const json* has(const json& o, const Pointer& at, const char* key, bool required = false) const {
    auto it = o.find(key);
    if (it != o.end()) return &*it;
    if (required) fail(at / key, "is missing (it is required)");
    return nullptr;
  }
  const json& need(const json& o, const Pointer& at, const char* key) const {
    return *has(o, at, key, true);
  }

  // ---- values

  const json& object(const json& v, const Pointer& at) const {
    if (!v.is_object()) fail(at, describe(v) + " is not an object");
    return v;
  }
  // A glTF property: an object whose `extensions`, when present, is an object of objects.
  const json& property(const json& v, const Pointer& at) const {
    object(v, at);
    if (const json* e = has(v, at, "extensions")) {
      object(*e, at / "extensions");
      for (auto it = e->begin(); it != e->end(); ++it)
        object(it.value(), at / "extensions" / it.key());
    }
    return v;
  }
  // An element of a root array: a property with an optional string name.
  void child_of_root(const json& v, const Pointer& at) const {
    property(v, at);
    if (const json* name = has(v, at, "name")) string(*name, at / "name");
  }
  // The extension object `name` of property `o`, or nullptr.
  const json* extension(const json& o, const Pointer& at, const char* name) const {
    auto e = o.find("extensions");
    if (e == o.end()) return nullptr;
    auto x = e->find(name);
    if (x == e->end()) return nullptr;
    property(*x, at / "extensions" / name);
    return &*x;
  }

  const json& array(const json& v, const Pointer& at, const std::string& of,
                    size_t min_items = 1) const {
    if (!v.is_array()) fail(at, describe(v) + " is not " + of);
    if (v.size() < min_items) fail(at, "is an empty array (it needs at least 1 element)");
    return v;
  }

  // An integer from `lo` to `hi`, written as an integer literal; `what` says what is expected.
  int64_t integer(const json& v, const Pointer& at, int64_t lo, int64_t hi,
                  const std::string& what) const {
    if (lo <= hi) {
      if (v.is_number_unsigned()) {
        const uint64_t u = v.get<uint64_t>();
        if (hi >= 0 && u <= uint64_t(hi) && int64_t(u) >= lo) return int64_t(u);
      } else if (v.is_number_integer()) {
        const int64_t i = v.get<int64_t>();
        if (i >= lo && i <= hi) return i;
      } else if (v.is_number_float()) {
        const double x = v.get<double>();
        if (x == std::floor(x) && x >= double(lo) && x <= double(hi)) {
          whole_floats_ = true;
          return int64_t(x);
        }
      }
    }
    fail(at, describe(v) + " is not " + what);
  }
  int64_t integer(const json& v, const Pointer& at, int64_t lo, int64_t hi = kMaxSize) const {
    return integer(v, at, lo, hi,
                   hi == kMaxSize || hi == kMaxInt
                       ? "an integer >= " + str(lo) + (hi == kMaxSize ? "" : " (and < 2^31)")
                       : "an integer from " + str(lo) + " to " + str(hi));
  }
  // An index into root array `array` (or into KHR_lights_punctual's lights).
  int64_t index(const json& v, const Pointer& at, const char* array) const {
    const size_t n = count(array);
    const std::string what = n == 0 ? "an index (the file has no " + std::string(array) + ")"
                                    : "an index (an integer from 0 to " + str(int64_t(n) - 1) +
                                          " for the " + str(int64_t(n)) + " " +
                                          (n == 1 ? singular(array) : array) + ")";
    return integer(v, at, 0, int64_t(n) - 1, what);
  }
  // An array of at least one index into `array`, none twice.
  void indices(const json& v, const Pointer& at, const char* array) const {
    this->array(v, at, "an array of indices");
    std::vector<bool> seen(count(array), false);
    for (size_t i = 0; i < v.size(); ++i) {
      const auto k = size_t(index(v[i], at / i, array));
      if (seen[k]) fail(at / i, str(int64_t(k)) + " is listed twice (the indices must be unique)");
      seen[k] = true;
    }
  }

  double number(const json& v, const Pointer& at, const Range& r) const {
    const double x = v.is_number() ? v.get<double>() : 0.0;
    if (!v.is_number() || !std::isfinite(x) || !r.contains(x))
      fail(at, describe(v) + " is not a number" + r.text);
    return x;
  }
  // An array of exactly `n` numbers in `r`.
  void numbers(const json& v, const Pointer& at, size_t n, const Range& r) const {
    const std::string what = std::to_string(n) + " numbers" + r.text;
    if (!v.is_array()) fail(at, describe(v) + " is not an array of " + what);
    if (v.size() != n)
      fail(at, "has " + std::to_string(v.size()) + " elements, where " + what + " are required");
    for (size_t i = 0; i < n; ++i) number(v[i], at / i, r);
  }
  void string(const json& v, const Pointer& at) const {
    if (!v.is_string()) fail(at, describe(v) + " is not a string");
  }
  // A buffer's or image's URI: a data URI, or a path relative to the file, which on Linux has at
  // most PATH_MAX (4096) bytes. A longer one names no file: refused here, before tinygltf parses
  // the JSON again and the loader copies it into paths and messages.
  void uri(const json& v, const Pointer& at) const {
    string(v, at);
    const std::string& text = v.get_ref<const std::string&>();
    constexpr size_t kMaxPath = 4096;
    if (text.size() > kMaxPath && text.rfind("data:", 0) != 0)
      fail(at, "is a file name of " + str(text.size()) + " bytes, longer than any path can be (" +
                   str(kMaxPath) + ")");
  }
  void boolean(const json& v, const Pointer& at) const {
    if (!v.is_boolean()) fail(at, describe(v) + " is not true or false");
  }
  int64_t enum_int(const json& v, const Pointer& at, std::initializer_list<int64_t> values) const {
    const std::string what = "one of " + one_of(values);
    const int64_t x = integer(v, at, *std::min_element(values.begin(), values.end()),
                              *std::max_element(values.begin(), values.end()), what);
    if (std::find(values.begin(), values.end(), x) == values.end())
      fail(at, str(x) + " is not " + what);
    return x;
  }
  std::string enum_string(const json& v, const Pointer& at,
                          std::initializer_list<const char*> values) const {
    if (v.is_string())
      for (const char* s : values)
        if (v.get_ref<const std::string&>() == s) return s;
    fail(at, describe(v) + " is not " + one_of(values));
  }

  // ---- members: each checks `key` of `o` when present (or, `required`, insists on it)

  void index_member(const json& o, const Pointer& at, const char* key, const char* array,
                    bool required = false) const {
    if (const json* v = has(o, at, key, required)) index(*v, at / key, array);
  }
  void number_member(const json& o, const Pointer& at, const char* key, const Range& r) const {
    if (const json* v = has(o, at, key)) number(*v, at / key, r);
  }
  void numbers_member(const json& o, const Pointer& at, const char* key, size_t n,
                      const Range& r) const {
    if (const json* v = has(o, at, key)) numbers(*v, at / key, n, r);
  }
  // An array of at least one number (morph target weights).
  void weights_member(const json& o, const Pointer& at, const char* key) const {
    if (const json* v = has(o, at, key)) {
      array(*v, at / key, "an array of numbers");
      for (size_t i = 0; i < v->size(); ++i) number((*v)[i], at / key / i, kAnyNumber);
    }
  }
  // A textureInfo (with KHR_texture_transform), or nullptr when absent.
  const json* texture_info(const json& o, const Pointer& parent, const char* key) const {
    const json* t = has(o, parent, key);
    if (!t) return nullptr;
    const Pointer at = parent / key;
    property(*t, at);
    index_member(*t, at, "index", "textures", true);
    if (const json* v = has(*t, at, "texCoord")) integer(*v, at / "texCoord", 0, kMaxInt);
    if (const json* x = extension(*t, at, "KHR_texture_transform")) {
      const Pointer xt = at / "extensions" / "KHR_texture_transform";
      numbers_member(*x, xt, "offset", 2, kAnyNumber);
      number_member(*x, xt, "rotation", kAnyNumber);
      numbers_member(*x, xt, "scale", 2, kAnyNumber);
      if (const json* v = has(*x, xt, "texCoord")) integer(*v, xt / "texCoord", 0, kMaxInt);
    }
    return t;
  }
  // An object of accessor indices (primitive attributes, morph targets, instancing attributes).
  void attributes(const json& v, const Pointer& at, bool non_empty) const {
    object(v, at);
    if (non_empty && v.empty()) fail(at, "is an empty object (it needs at least 1 attribute)");
    for (auto it = v.begin(); it != v.end(); ++it) index(it.value(), at / it.key(), "accessors");
  }

  // ---- the root's members

  // "major.minor", each a few digits.
  static bool version(const json& v, int& major, int& minor) {
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

  void asset(const Pointer& top) {
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

  void extension_lists(const Pointer& top) const {
    for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
      const json* list = has(root_, top, key);
      if (!list) continue;
      const Pointer at = top / key;
      array(*list, at, "an array of extension names");
      for (size_t i = 0; i < list->size(); ++i) {
        const json& name = (*list)[i];
        if (!name.is_string())
          fail(at / i, describe(name) + " is not an extension name (a string)");
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

  // KHR_lights_punctual's lights array (shape checked), or nullptr.
  const json* light_list() const {
    const Pointer top;
    const json* x = extension(root_, top, "KHR_lights_punctual");
    if (!x) return nullptr;
    const Pointer at = top / "extensions" / "KHR_lights_punctual";
    const json& lights = array(need(*x, at, "lights"), at / "lights", "an array of objects");
    for (size_t i = 0; i < lights.size(); ++i) child_of_root(lights[i], at / "lights" / i);
    return &lights;
  }

  // ---- the elements

  void buffer(const json& b, const Pointer& at) {
    integer(need(b, at, "byteLength"), at / "byteLength", 1);
    if (const json* u = has(b, at, "uri")) uri(*u, at / "uri");
  }

  void buffer_view(const json& v, const Pointer& at) {
    index_member(v, at, "buffer", "buffers", true);
    if (const json* o = has(v, at, "byteOffset")) integer(*o, at / "byteOffset", 0);
    integer(need(v, at, "byteLength"), at / "byteLength", 1);
    if (const json* s = has(v, at, "byteStride"))
      if (integer(*s, at / "byteStride", 4, 252) % 4 != 0)
        fail(at / "byteStride", describe(*s) + " is not a multiple of 4");
    if (const json* t = has(v, at, "target")) enum_int(*t, at / "target", {34962, 34963});
    // Its sizes as tinygltf keeps them (int), so that the decoder (compression.cpp) reads them
    // as the file says.
    if (const json* x = extension(v, at, "EXT_meshopt_compression")) {
      const Pointer xt = at / "extensions" / "EXT_meshopt_compression";
      index_member(*x, xt, "buffer", "buffers", true);
      if (const json* o = has(*x, xt, "byteOffset")) integer(*o, xt / "byteOffset", 0, kMaxInt);
      integer(need(*x, xt, "byteLength"), xt / "byteLength", 1, kMaxInt);
      integer(need(*x, xt, "byteStride"), xt / "byteStride", 1, 256);
      integer(need(*x, xt, "count"), xt / "count", 1, kMaxInt);
      const json& mode = need(*x, xt, "mode");
      if (mode != "ATTRIBUTES" && mode != "TRIANGLES" && mode != "INDICES")
        fail(xt / "mode", describe(mode) + " is not ATTRIBUTES, TRIANGLES or INDICES");
      if (const json* f = has(*x, xt, "filter"))
        if (*f != "NONE" && *f != "OCTAHEDRAL" && *f != "QUATERNION" && *f != "EXPONENTIAL")
          fail(xt / "filter", describe(*f) + " is not NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL");
    }
  }

  void accessor(const json& a, const Pointer& at) {
    const bool viewed = has(a, at, "bufferView") != nullptr;
    index_member(a, at, "bufferView", "bufferViews");
    if (const json* o = has(a, at, "byteOffset")) {
      integer(*o, at / "byteOffset", 0);
      if (!viewed) fail(at / "byteOffset", "is given without a bufferView");
    }
    const int64_t component = enum_int(need(a, at, "componentType"), at / "componentType",
                                       {5120, 5121, 5122, 5123, 5125, 5126});
    if (const json* n = has(a, at, "normalized")) {
      boolean(*n, at / "normalized");
      if (n->get<bool>() && (component == 5125 || component == 5126))
        fail(at / "normalized", "is true for a FLOAT or UNSIGNED_INT accessor");
    }
    const int64_t count = integer(need(a, at, "count"), at / "count", 1);
    const std::string type =
        enum_string(need(a, at, "type"), at / "type",
                    {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"});
    const size_t components = type == "SCALAR"                   ? 1
                              : type == "VEC2"                   ? 2
                              : type == "VEC3"                   ? 3
                              : type == "VEC4" || type == "MAT2" ? 4
                              : type == "MAT3"                   ? 9
                                                                 : 16;
    numbers_member(a, at, "min", components, kAnyNumber);
    numbers_member(a, at, "max", components, kAnyNumber);
    if (const json* s = has(a, at, "sparse")) {
      const Pointer sp = at / "sparse";
      property(*s, sp);
      const int64_t n = integer(need(*s, sp, "count"), sp / "count", 1, kMaxInt);
      if (n > count)
        fail(sp / "count", str(n) + " is more than the accessor's count " + str(count));
      const Pointer ip = sp / "indices", vp = sp / "values";
      const json& indices = property(need(*s, sp, "indices"), ip);
      index_member(indices, ip, "bufferView", "bufferViews", true);
      if (const json* o = has(indices, ip, "byteOffset"))
        integer(*o, ip / "byteOffset", 0, kMaxInt);
      enum_int(need(indices, ip, "componentType"), ip / "componentType", {5121, 5123, 5125});
      const json& values = property(need(*s, sp, "values"), vp);
      index_member(values, vp, "bufferView", "bufferViews", true);
      if (const json* o = has(values, vp, "byteOffset")) integer(*o, vp / "byteOffset", 0, kMaxInt);
    }
  }

  void image(const json& i, const Pointer& at) {
    const json* uri = has(i, at, "uri");
    const json* view = has(i, at, "bufferView");
    if (uri) this->uri(*uri, at / "uri");
    if (view) index(*view, at / "bufferView", "bufferViews");
    if (uri && view) fail(at, "has both a uri and a bufferView (it must have one)");
    if (!uri && !view) fail(at, "has neither a uri nor a bufferView (it must have one)");
    const json* mime = has(i, at, "mimeType");
    if (view && !mime) fail(at / "mimeType", "is missing (it is required with a bufferView)");
    if (mime) {
      string(*mime, at / "mimeType");
      // KTX2 images are never decoded: the loader says so for each texture that has one.
      if (*mime != "image/png" && *mime != "image/jpeg" && *mime != "image/webp" &&
          *mime != "image/ktx2")
        warn(at / "mimeType", describe(*mime) +
                                  " is not image/png, image/jpeg or image/webp, the types this "
                                  "version decodes");
    }
  }

  void sampler(const json& s, const Pointer& at) {
    if (const json* v = has(s, at, "magFilter")) enum_int(*v, at / "magFilter", {9728, 9729});
    if (const json* v = has(s, at, "minFilter"))
      enum_int(*v, at / "minFilter", {9728, 9729, 9984, 9985, 9986, 9987});
    for (const char* key : {"wrapS", "wrapT"})
      if (const json* v = has(s, at, key)) enum_int(*v, at / key, {33071, 33648, 10497});
  }

  void texture(const json& t, const Pointer& at) {
    index_member(t, at, "sampler", "samplers");
    index_member(t, at, "source", "images");
    // Another image for the texture (the validator allows an empty object, with no source).
    for (const char* name : {"EXT_texture_webp", "KHR_texture_basisu"})
      if (const json* x = extension(t, at, name))
        index_member(*x, at / "extensions" / name, "source", "images");
  }

  void material(const json& m, const Pointer& at) {
    if (const json* pbr = has(m, at, "pbrMetallicRoughness")) {
      const Pointer p = at / "pbrMetallicRoughness";
      property(*pbr, p);
      numbers_member(*pbr, p, "baseColorFactor", 4, kUnit);
      number_member(*pbr, p, "metallicFactor", kUnit);
      number_member(*pbr, p, "roughnessFactor", kUnit);
      texture_info(*pbr, p, "baseColorTexture");
      texture_info(*pbr, p, "metallicRoughnessTexture");
    }
    if (const json* t = texture_info(m, at, "normalTexture"))
      number_member(*t, at / "normalTexture", "scale", kAnyNumber);
    if (const json* t = texture_info(m, at, "occlusionTexture"))
      number_member(*t, at / "occlusionTexture", "strength", kUnit);
    texture_info(m, at, "emissiveTexture");
    numbers_member(m, at, "emissiveFactor", 3, kUnit);
    if (const json* v = has(m, at, "alphaMode"))
      enum_string(*v, at / "alphaMode", {"OPAQUE", "MASK", "BLEND"});
    number_member(m, at, "alphaCutoff", kNonNegative);
    if (const json* v = has(m, at, "doubleSided")) boolean(*v, at / "doubleSided");

    auto ext = [&](const char* name, auto&& check) {
      if (const json* x = extension(m, at, name)) check(*x, at / "extensions" / name);
    };
    ext("KHR_materials_clearcoat", [&](const json& x, const Pointer& p) {
      number_member(x, p, "clearcoatFactor", kUnit);
      texture_info(x, p, "clearcoatTexture");
      number_member(x, p, "clearcoatRoughnessFactor", kUnit);
      texture_info(x, p, "clearcoatRoughnessTexture");
      if (const json* t = texture_info(x, p, "clearcoatNormalTexture"))
        number_member(*t, p / "clearcoatNormalTexture", "scale", kAnyNumber);
    });
    ext("KHR_materials_sheen", [&](const json& x, const Pointer& p) {
      numbers_member(x, p, "sheenColorFactor", 3, kUnit);
      texture_info(x, p, "sheenColorTexture");
      number_member(x, p, "sheenRoughnessFactor", kUnit);
      texture_info(x, p, "sheenRoughnessTexture");
    });
    ext("KHR_materials_anisotropy", [&](const json& x, const Pointer& p) {
      number_member(x, p, "anisotropyStrength", kUnit);
      number_member(x, p, "anisotropyRotation", kAnyNumber);
      texture_info(x, p, "anisotropyTexture");
    });
    ext("KHR_materials_iridescence", [&](const json& x, const Pointer& p) {
      number_member(x, p, "iridescenceFactor", kUnit);
      texture_info(x, p, "iridescenceTexture");
      if (const json* v = has(x, p, "iridescenceIor"))
        if (const double ior = number(*v, p / "iridescenceIor", kAnyNumber); !(ior >= 1.0))
          fail(p / "iridescenceIor", describe(*v) + " is not a number >= 1");
      number_member(x, p, "iridescenceThicknessMinimum", kNonNegative);
      number_member(x, p, "iridescenceThicknessMaximum", kNonNegative);
      texture_info(x, p, "iridescenceThicknessTexture");
    });
    ext("KHR_materials_unlit", [&](const json&, const Pointer&) {});  // an object, no members
    ext("KHR_materials_emissive_strength", [&](const json& x, const Pointer& p) {
      number_member(x, p, "emissiveStrength", kNonNegative);
    });
    ext("KHR_materials_ior", [&](const json& x, const Pointer& p) {
      if (const json* v = has(x, p, "ior"))
        if (const double ior = number(*v, p / "ior", kAnyNumber); !(ior >= 1.0 || ior == 0.0))
          fail(p / "ior", describe(*v) + " is not a number >= 1 or 0");
    });
    ext("KHR_materials_specular", [&](const json& x, const Pointer& p) {
      number_member(x, p, "specularFactor", kUnit);
      texture_info(x, p, "specularTexture");
      numbers_member(x, p, "specularColorFactor", 3, kNonNegative);
      texture_info(x, p, "specularColorTexture");
    });
    ext("KHR_materials_transmission", [&](const json& x, const Pointer& p) {
      number_member(x, p, "transmissionFactor", kUnit);
      texture_info(x, p, "transmissionTexture");
    });
    ext("KHR_materials_volume", [&](const json& x, const Pointer& p) {
      number_member(x, p, "thicknessFactor", kNonNegative);
      texture_info(x, p, "thicknessTexture");
      number_member(x, p, "attenuationDistance", kPositive);
      numbers_member(x, p, "attenuationColor", 3, kUnit);
    });
    ext("KHR_materials_dispersion", [&](const json& x, const Pointer& p) {
      number_member(x, p, "dispersion", kNonNegative);
    });
  }

  void camera(const json& c, const Pointer& at) {
    const std::string type =
        enum_string(need(c, at, "type"), at / "type", {"perspective", "orthographic"});
    const json* perspective = has(c, at, "perspective");
    const json* orthographic = has(c, at, "orthographic");
    if (perspective && orthographic)
      fail(at, "has both perspective and orthographic (it must have one)");
    const bool is_perspective = type == "perspective";
    const json* p = is_perspective ? perspective : orthographic;
    const Pointer pp = at / type;
    if (!p) fail(pp, "is missing (it is required for type \"" + type + "\")");
    property(*p, pp);
    double znear = 0.0;
    if (is_perspective) {
      number_member(*p, pp, "aspectRatio", kPositive);
      number(need(*p, pp, "yfov"), pp / "yfov", kPositive);
      znear = number(need(*p, pp, "znear"), pp / "znear", kPositive);
    } else {
      for (const char* key : {"xmag", "ymag"})
        if (number(need(*p, pp, key), pp / key, kAnyNumber) == 0.0)
          fail(pp / key, "is 0 (it must not be zero)");
      znear = number(need(*p, pp, "znear"), pp / "znear", kNonNegative);
    }
    if (const json* v = has(*p, pp, "zfar", !is_perspective))
      if (const double zfar = number(*v, pp / "zfar", kPositive); !(zfar > znear))
        fail(pp / "zfar", describe(*v) + " is not greater than znear " + describe(p->at("znear")));
  }

  void mesh(const json& m, const Pointer& at) {
    const json& primitives =
        array(need(m, at, "primitives"), at / "primitives", "an array of objects");
    for (size_t i = 0; i < primitives.size(); ++i) {
      const Pointer p = at / "primitives" / i;
      const json& prim = property(primitives[i], p);
      attributes(need(prim, p, "attributes"), p / "attributes", true);
      index_member(prim, p, "indices", "accessors");
      index_member(prim, p, "material", "materials");
      if (const json* v = has(prim, p, "mode")) enum_int(*v, p / "mode", {0, 1, 2, 3, 4, 5, 6});
      if (const json* x = extension(prim, p, "KHR_materials_variants")) {
        const Pointer xt = p / "extensions" / "KHR_materials_variants";
        const json& mappings =
            array(need(*x, xt, "mappings"), xt / "mappings", "an array of objects");
        // A variant maps a primitive to one material: in one mapping at most.
        std::vector<bool> mapped(variant_count_, false);
        for (size_t k = 0; k < mappings.size(); ++k) {
          const json& mapping = property(mappings[k], xt / "mappings" / k);
          index_member(mapping, xt / "mappings" / k, "material", "materials", true);
          const Pointer vt = xt / "mappings" / k / "variants";
          const json& variants = need(mapping, xt / "mappings" / k, "variants");
          indices(variants, vt, "variants");
          for (size_t i = 0; i < variants.size(); ++i) {
            const size_t v = variants[i].get<size_t>();
            if (mapped[v]) fail(vt / i, "variant " + str(int64_t(v)) + " is mapped twice");
            mapped[v] = true;
          }
        }
      }
      if (const json* x = extension(prim, p, "KHR_draco_mesh_compression")) {
        const Pointer xt = p / "extensions" / "KHR_draco_mesh_compression";
        index_member(*x, xt, "bufferView", "bufferViews", true);
        const json& ids = property(need(*x, xt, "attributes"), xt / "attributes");
        for (auto it = ids.begin(); it != ids.end(); ++it)
          integer(it.value(), xt / "attributes" / it.key(), 0, kMaxInt);
      }
      if (const json* targets = has(prim, p, "targets")) {
        array(*targets, p / "targets", "an array of objects");
        for (size_t t = 0; t < targets->size(); ++t)
          attributes((*targets)[t], p / "targets" / t, false);
      }
    }
    weights_member(m, at, "weights");
  }

  void skin(const json& s, const Pointer& at) {
    indices(need(s, at, "joints"), at / "joints", "nodes");
    index_member(s, at, "inverseBindMatrices", "accessors");
    index_member(s, at, "skeleton", "nodes");
  }

  void node(const json& n, const Pointer& at) {
    index_member(n, at, "camera", "cameras");
    index_member(n, at, "mesh", "meshes");
    index_member(n, at, "skin", "skins");
    if (const json* c = has(n, at, "children")) indices(*c, at / "children", "nodes");
    numbers_member(n, at, "matrix", 16, kAnyNumber);
    numbers_member(n, at, "translation", 3, kAnyNumber);
    numbers_member(n, at, "rotation", 4, kSignedUnit);
    numbers_member(n, at, "scale", 3, kAnyNumber);
    if (has(n, at, "matrix"))
      for (const char* trs : {"translation", "rotation", "scale"})
        if (has(n, at, trs))
          fail(at / "matrix",
               std::string("is given with ") + trs + " (a node has a matrix or TRS, not both)");
    weights_member(n, at, "weights");
    for (const char* key : {"skin", "weights"})
      if (has(n, at, key) && !has(n, at, "mesh")) fail(at / key, "is given without a mesh");
    if (const json* x = extension(n, at, "KHR_lights_punctual"))
      index_member(*x, at / "extensions" / "KHR_lights_punctual", "light", "lights", true);
    if (const json* x = extension(n, at, "EXT_mesh_gpu_instancing")) {
      const Pointer p = at / "extensions" / "EXT_mesh_gpu_instancing";
      attributes(need(*x, p, "attributes"), p / "attributes", true);
    }
  }

  void scene(const json& s, const Pointer& at) {
    if (const json* nodes = has(s, at, "nodes")) indices(*nodes, at / "nodes", "nodes");
  }

  void light(const json& l, const Pointer& at) {
    // A type this version does not know (the validator warns) is left to the loader, which
    // skips the light with a warning.
    const json& type = need(l, at, "type");
    if (type.is_string() && type != "directional" && type != "point" && type != "spot") return;
    enum_string(type, at / "type", {"directional", "point", "spot"});
    numbers_member(l, at, "color", 3, kUnit);
    number_member(l, at, "intensity", kNonNegative);
    number_member(l, at, "range", kPositive);
    if (const json* spot = has(l, at, "spot")) {
      const Pointer sp = at / "spot";
      property(*spot, sp);
      double inner = 0.0, outer = kPi / 4;  // the defaults
      if (const json* v = has(*spot, sp, "innerConeAngle"))
        inner = number(*v, sp / "innerConeAngle", kInnerCone);
      if (const json* v = has(*spot, sp, "outerConeAngle"))
        outer = number(*v, sp / "outerConeAngle", kOuterCone);
      if (!(inner < outer))
        fail(sp / "innerConeAngle", "is not less than outerConeAngle (" + std::to_string(inner) +
                                        " >= " + std::to_string(outer) + ")");
    }
  }

  // Every node has one parent at most, no node is its own ancestor, and scenes list roots only.
  void hierarchy() const {
    const size_t n = count("nodes");
    if (n == 0) return;
    const json& nodes = root_.at("nodes");
    std::vector<int64_t> parent(n, -1);
    std::vector<size_t> slot(n, 0);  // where in its parent's children
    for (size_t i = 0; i < n; ++i) {
      auto children = nodes[i].find("children");
      if (children == nodes[i].end()) continue;
      for (size_t k = 0; k < children->size(); ++k) {
        const auto c = (*children)[k].get<size_t>();
        if (parent[c] >= 0)
          fail(Pointer() / "nodes" / i / "children" / k,
               "node " + str(int64_t(c)) + " is already a child of node " + str(parent[c]) +
                   " (a node has one parent at most)");
        parent[c] = int64_t(i), slot[c] = k;
      }
    }
    // With one parent each, a cycle is a loop of parent links: walk up from every node.
    std::vector<uint8_t> state(n, 0);  // 0 not seen, 1 on the current walk, 2 leads to a root
    std::vector<size_t> walk;
    for (size_t s = 0; s < n; ++s) {
      walk.clear();
      int64_t v = int64_t(s);
      while (v >= 0 && state[size_t(v)] == 0) {
        state[size_t(v)] = 1;
        walk.push_back(size_t(v));
        v = parent[size_t(v)];
      }
      if (v >= 0 && state[size_t(v)] == 1)
        fail(Pointer() / "nodes" / size_t(parent[size_t(v)]) / "children" / slot[size_t(v)],
             "node " + str(v) + " is its own ancestor (a cycle)");
      for (size_t w : walk) state[w] = 2;
    }
    const size_t scenes = count("scenes");
    for (size_t s = 0; s < scenes; ++s) {
      const json& scene = root_.at("scenes")[s];
      auto roots = scene.find("nodes");
      if (roots == scene.end()) continue;
      for (size_t k = 0; k < roots->size(); ++k)
        if (const auto r = (*roots)[k].get<size_t>(); parent[r] >= 0)
          fail(Pointer() / "scenes" / s / "nodes" / k,
               "node " + str(int64_t(r)) + " is not a root node (it is a child of node " +
                   str(parent[r]) + ")");
    }
  }

  const std::string& path_;
  const json& root_;
  size_t light_count_ = 0;
  size_t variant_count_ = 0;  // KHR_materials_variants
  std::vector<std::string> warnings_;
  mutable bool whole_floats_ = false;  // an integer written as 1.0
};

}  // namespace

bool gltf_extension_supported(std::string_view name) {
  return std::find(std::begin(kSupportedExtensions), std::end(kSupportedExtensions), name) !=
         std::end(kSupportedExtensions);
}

SchemaCheck check_gltf_schema(const std::string& path, const nlohmann::json& doc) {
  return Checker(path, doc).run();
}

}  // namespace dacrt
