// What the glTF schema check's files share (io/gltf/schema*.cpp; schema.h is its interface): the
// Checker, which walks a file's JSON element kind by element kind, the JSON Pointer its messages
// name, and the number ranges they state. schema.cpp runs the check and checks the root's members;
// schema_values.cpp has the value and member checks that every element uses; the elements are
// checked in schema_buffers.cpp (buffers, bufferViews, accessors), schema_materials.cpp (images,
// samplers, textures, materials) and schema_nodes.cpp (cameras, meshes, skins, nodes, scenes,
// lights, and the node hierarchy).
#pragma once

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "dacrt/io/gltf/schema.h"
#include "dacrt/util/error.h"

namespace dacrt::gltf::schema {

using json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
// tinygltf keeps byte offsets, lengths and counts as size_t: bounded where a double is still exact.
constexpr int64_t kMaxSize = int64_t(1) << 53;
// ... and indices, enums, texCoord sets and sparse counts and offsets as int.
constexpr int64_t kMaxInt = std::numeric_limits<int32_t>::max();

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

inline std::string str(int64_t n) {
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
std::string describe(const json& v);

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

// The check of one file's JSON `root` (`path` starts every message): run() throws dacrt::Error
// at the first violation, else returns the warnings.
class Checker {
 public:
  Checker(const std::string& path, const json& root) : path_(path), root_(root) {}

  SchemaCheck run();  // schema.cpp

 private:
  [[noreturn]] void fail(const Pointer& at, const std::string& what) const {
    throw Error(path_ + ": " + at.str() + ": " + what);
  }
  void warn(const Pointer& at, const std::string& what) {
    warnings_.push_back(path_ + ": " + at.str() + ": " + what);
  }

  // The number of elements of root array `array` (or of the lights, or the variants).
  size_t count(std::string_view array) const;

  template <class Check>
  void each(const char* array, Check check) {
    if (const json* a = has(root_, Pointer(), array))
      for (size_t i = 0; i < a->size(); ++i) (this->*check)((*a)[i], Pointer() / array / i);
  }

  // Member `key` of object `o` (at `at`), or nullptr; a `required` one must be there.
  const json* has(const json& o, const Pointer& at, const char* key, bool required = false) const;
  const json& need(const json& o, const Pointer& at, const char* key) const {
    return *has(o, at, key, true);
  }

  // ---- values (schema_values.cpp)

  const json& object(const json& v, const Pointer& at) const;
  // A glTF property: an object whose `extensions`, when present, is an object of objects.
  const json& property(const json& v, const Pointer& at) const;
  // An element of a root array: a property with an optional string name.
  void child_of_root(const json& v, const Pointer& at) const;
  // The extension object `name` of property `o`, or nullptr.
  const json* extension(const json& o, const Pointer& at, const char* name) const;

  const json& array(const json& v, const Pointer& at, const std::string& of,
                    size_t min_items = 1) const;

  // An integer from `lo` to `hi`, written as an integer literal; `what` says what is expected.
  int64_t integer(const json& v, const Pointer& at, int64_t lo, int64_t hi,
                  const std::string& what) const;
  int64_t integer(const json& v, const Pointer& at, int64_t lo, int64_t hi = kMaxSize) const;
  // An index into root array `array` (or into KHR_lights_punctual's lights).
  int64_t index(const json& v, const Pointer& at, const char* array) const;
  // An array of at least one index into `array`, none twice.
  void indices(const json& v, const Pointer& at, const char* array) const;

  double number(const json& v, const Pointer& at, const Range& r) const;
  // An array of exactly `n` numbers in `r`.
  void numbers(const json& v, const Pointer& at, size_t n, const Range& r) const;
  void string(const json& v, const Pointer& at) const;
  // A buffer's or image's URI: a data URI, or a path relative to the file, which on Linux has at
  // most PATH_MAX (4096) bytes. A longer one names no file: refused here, before tinygltf parses
  // the JSON again and the loader copies it into paths and messages.
  void uri(const json& v, const Pointer& at) const;
  void boolean(const json& v, const Pointer& at) const;
  int64_t enum_int(const json& v, const Pointer& at, std::initializer_list<int64_t> values) const;
  std::string enum_string(const json& v, const Pointer& at,
                          std::initializer_list<const char*> values) const;

  // ---- members: each checks `key` of `o` when present (or, `required`, insists on it)
  // (schema_values.cpp)

  void index_member(const json& o, const Pointer& at, const char* key, const char* array,
                    bool required = false) const;
  void number_member(const json& o, const Pointer& at, const char* key, const Range& r) const;
  void numbers_member(const json& o, const Pointer& at, const char* key, size_t n,
                      const Range& r) const;
  // An array of at least one number (morph target weights).
  void weights_member(const json& o, const Pointer& at, const char* key) const;
  // A textureInfo (with KHR_texture_transform), or nullptr when absent.
  const json* texture_info(const json& o, const Pointer& parent, const char* key) const;
  // An object of accessor indices (primitive attributes, morph targets, instancing attributes).
  void attributes(const json& v, const Pointer& at, bool non_empty) const;

  // ---- the root's members (schema.cpp)

  void asset(const Pointer& top);
  void extension_lists(const Pointer& top) const;
  // KHR_lights_punctual's lights array (shape checked), or nullptr.
  const json* light_list() const;

  // ---- the elements

  // schema_buffers.cpp
  void buffer(const json& b, const Pointer& at);
  void buffer_view(const json& v, const Pointer& at);
  void accessor(const json& a, const Pointer& at);
  // schema_materials.cpp
  void image(const json& i, const Pointer& at);
  void sampler(const json& s, const Pointer& at);
  void texture(const json& t, const Pointer& at);
  void material(const json& m, const Pointer& at);
  // schema_nodes.cpp
  void camera(const json& c, const Pointer& at);
  void mesh(const json& m, const Pointer& at);
  void skin(const json& s, const Pointer& at);
  void node(const json& n, const Pointer& at);
  void scene(const json& s, const Pointer& at);
  void light(const json& l, const Pointer& at);
  // Every node has one parent at most, no node is its own ancestor, and scenes list roots only.
  void hierarchy() const;

  const std::string& path_;
  const json& root_;
  size_t light_count_ = 0;
  size_t variant_count_ = 0;  // KHR_materials_variants
  std::vector<std::string> warnings_;
  mutable bool whole_floats_ = false;  // an integer written as 1.0
};

}  // namespace dacrt::gltf::schema
