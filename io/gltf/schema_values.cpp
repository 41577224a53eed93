// The glTF schema check's values and members (io/gltf/schema_checker.h): the checks of a JSON
// value's type, range and shape that every element's check is made of, each failing with the
// JSON Pointer of the value and what it is not.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <type_traits>

#include "dacrt/io/gltf/schema_checker.h"

namespace dacrt::gltf::schema {
namespace {

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

const char* singular(std::string_view array) {
  for (const Kind& k : kKinds)
    if (array == k.array) return k.one;
  return "element";
}

}  // namespace

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

size_t Checker::count(std::string_view array) const {
  if (array == "lights") return light_count_;
  if (array == "variants") return variant_count_;
  auto a = root_.find(array);
  return a == root_.end() ? 0 : a->size();  // checked to be an array first
}

const json* Checker::has(const json& o, const Pointer& at, const char* key, bool required) const {
  auto it = o.find(key);
  if (it != o.end()) return &*it;
  if (required) fail(at / key, "is missing (it is required)");
  return nullptr;
}

// ---- values

const json& Checker::object(const json& v, const Pointer& at) const {
  if (!v.is_object()) fail(at, describe(v) + " is not an object");
  return v;
}

const json& Checker::property(const json& v, const Pointer& at) const {
  object(v, at);
  if (const json* e = has(v, at, "extensions")) {
    object(*e, at / "extensions");
    for (auto it = e->begin(); it != e->end(); ++it)
      object(it.value(), at / "extensions" / it.key());
  }
  return v;
}

void Checker::child_of_root(const json& v, const Pointer& at) const {
  property(v, at);
  if (const json* name = has(v, at, "name")) string(*name, at / "name");
}

const json* Checker::extension(const json& o, const Pointer& at, const char* name) const {
  auto e = o.find("extensions");
  if (e == o.end()) return nullptr;
  auto x = e->find(name);
  if (x == e->end()) return nullptr;
  property(*x, at / "extensions" / name);
  return &*x;
}

const json& Checker::array(const json& v, const Pointer& at, const std::string& of,
                           size_t min_items) const {
  if (!v.is_array()) fail(at, describe(v) + " is not " + of);
  if (v.size() < min_items) fail(at, "is an empty array (it needs at least 1 element)");
  return v;
}

int64_t Checker::integer(const json& v, const Pointer& at, int64_t lo, int64_t hi,
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

int64_t Checker::integer(const json& v, const Pointer& at, int64_t lo, int64_t hi) const {
  return integer(v, at, lo, hi,
                 hi == kMaxSize || hi == kMaxInt
                     ? "an integer >= " + str(lo) + (hi == kMaxSize ? "" : " (and < 2^31)")
                     : "an integer from " + str(lo) + " to " + str(hi));
}

int64_t Checker::index(const json& v, const Pointer& at, const char* array) const {
  const size_t n = count(array);
  const std::string what = n == 0 ? "an index (the file has no " + std::string(array) + ")"
                                  : "an index (an integer from 0 to " + str(int64_t(n) - 1) +
                                        " for the " + str(int64_t(n)) + " " +
                                        (n == 1 ? singular(array) : array) + ")";
  return integer(v, at, 0, int64_t(n) - 1, what);
}

void Checker::indices(const json& v, const Pointer& at, const char* array) const {
  this->array(v, at, "an array of indices");
  std::vector<bool> seen(count(array), false);
  for (size_t i = 0; i < v.size(); ++i) {
    const auto k = size_t(index(v[i], at / i, array));
    if (seen[k]) fail(at / i, str(int64_t(k)) + " is listed twice (the indices must be unique)");
    seen[k] = true;
  }
}

double Checker::number(const json& v, const Pointer& at, const Range& r) const {
  const double x = v.is_number() ? v.get<double>() : 0.0;
  if (!v.is_number() || !std::isfinite(x) || !r.contains(x))
    fail(at, describe(v) + " is not a number" + r.text);
  return x;
}

void Checker::numbers(const json& v, const Pointer& at, size_t n, const Range& r) const {
  const std::string what = std::to_string(n) + " numbers" + r.text;
  if (!v.is_array()) fail(at, describe(v) + " is not an array of " + what);
  if (v.size() != n)
    fail(at, "has " + std::to_string(v.size()) + " elements, where " + what + " are required");
  for (size_t i = 0; i < n; ++i) number(v[i], at / i, r);
}

void Checker::string(const json& v, const Pointer& at) const {
  if (!v.is_string()) fail(at, describe(v) + " is not a string");
}

void Checker::uri(const json& v, const Pointer& at) const {
  string(v, at);
  const std::string& text = v.get_ref<const std::string&>();
  constexpr size_t kMaxPath = 4096;
  if (text.size() > kMaxPath && text.rfind("data:", 0) != 0)
    fail(at, "is a file name of " + str(text.size()) + " bytes, longer than any path can be (" +
                 str(kMaxPath) + ")");
}

void Checker::boolean(const json& v, const Pointer& at) const {
  if (!v.is_boolean()) fail(at, describe(v) + " is not true or false");
}

int64_t Checker::enum_int(const json& v, const Pointer& at,
                          std::initializer_list<int64_t> values) const {
  const std::string what = "one of " + one_of(values);
  const int64_t x = integer(v, at, *std::min_element(values.begin(), values.end()),
                            *std::max_element(values.begin(), values.end()), what);
  if (std::find(values.begin(), values.end(), x) == values.end())
    fail(at, str(x) + " is not " + what);
  return x;
}

std::string Checker::enum_string(const json& v, const Pointer& at,
                                 std::initializer_list<const char*> values) const {
  if (v.is_string())
    for (const char* s : values)
      if (v.get_ref<const std::string&>() == s) return s;
  fail(at, describe(v) + " is not " + one_of(values));
}

// ---- members

void Checker::index_member(const json& o, const Pointer& at, const char* key, const char* array,
                           bool required) const {
  if (const json* v = has(o, at, key, required)) index(*v, at / key, array);
}

void Checker::number_member(const json& o, const Pointer& at, const char* key,
                            const Range& r) const {
  if (const json* v = has(o, at, key)) number(*v, at / key, r);
}

void Checker::numbers_member(const json& o, const Pointer& at, const char* key, size_t n,
                             const Range& r) const {
  if (const json* v = has(o, at, key)) numbers(*v, at / key, n, r);
}

void Checker::weights_member(const json& o, const Pointer& at, const char* key) const {
  if (const json* v = has(o, at, key)) {
    array(*v, at / key, "an array of numbers");
    for (size_t i = 0; i < v->size(); ++i) number((*v)[i], at / key / i, kAnyNumber);
  }
}

const json* Checker::texture_info(const json& o, const Pointer& parent, const char* key) const {
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

void Checker::attributes(const json& v, const Pointer& at, bool non_empty) const {
  object(v, at);
  if (non_empty && v.empty()) fail(at, "is an empty object (it needs at least 1 attribute)");
  for (auto it = v.begin(); it != v.end(); ++it) index(it.value(), at / it.key(), "accessors");
}

}  // namespace dacrt::gltf::schema
