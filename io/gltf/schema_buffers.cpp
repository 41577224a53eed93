// The glTF schema check of buffers, bufferViews (with EXT_meshopt_compression) and accessors
// (with their sparse substitutions); the Checker is in io/gltf/schema_checker.h.
#include <string>

#include "dacrt/io/gltf/schema_checker.h"

namespace dacrt::gltf::schema {

void Checker::buffer(const json& b, const Pointer& at) {
  integer(need(b, at, "byteLength"), at / "byteLength", 1);
  if (const json* u = has(b, at, "uri")) uri(*u, at / "uri");
}

void Checker::buffer_view(const json& v, const Pointer& at) {
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

void Checker::accessor(const json& a, const Pointer& at) {
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
  const std::string type = enum_string(need(a, at, "type"), at / "type",
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
    if (n > count) fail(sp / "count", str(n) + " is more than the accessor's count " + str(count));
    const Pointer ip = sp / "indices", vp = sp / "values";
    const json& indices = property(need(*s, sp, "indices"), ip);
    index_member(indices, ip, "bufferView", "bufferViews", true);
    if (const json* o = has(indices, ip, "byteOffset")) integer(*o, ip / "byteOffset", 0, kMaxInt);
    enum_int(need(indices, ip, "componentType"), ip / "componentType", {5121, 5123, 5125});
    const json& values = property(need(*s, sp, "values"), vp);
    index_member(values, vp, "bufferView", "bufferViews", true);
    if (const json* o = has(values, vp, "byteOffset")) integer(*o, vp / "byteOffset", 0, kMaxInt);
  }
}

}  // namespace dacrt::gltf::schema
