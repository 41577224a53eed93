// glTF 2.0 loading: tinygltf parses the file (Debian ships it compiled in libtinygltf.so, so no
// TINYGLTF_IMPLEMENTATION here), then the chosen scene's node tree is flattened into world-space
// triangles, a material table and cameras. Everything read from the file is validated first, so a
// malformed file gives one dacrt::Error line and never a crash or an out-of-bounds read.
//
// Supported: .gltf (external .bin or data URIs) and .glb; TRS and matrix nodes; triangle lists,
// indexed (u8/u16/u32) or not; sparse accessors and accessors without a bufferView (zeros);
// NORMAL, TANGENT, TEXCOORD_0/1 and COLOR_0 (float or normalised integers); the metallic-roughness
// factors with KHR_materials_ior and KHR_materials_specular, emissiveFactor ×
// KHR_materials_emissive_strength, doubleSided; baseColor, metallic-roughness, normal and
// emissive textures with KHR_texture_transform and samplers, from PNG or JPEG images (embedded,
// in a bufferView, or external files); tangents generated where a normal map needs them and the
// file has none; perspective and orthographic cameras.
// Triangle lists, strips and fans. Skipped with one warning line each: point and line primitives,
// primitives without POSITION (the spec says to skip them).
// Ignored: occlusion textures (a path tracer computes occlusion), images no material uses (never
// decoded), skins, morph targets, animations, and extensions that are only "used" (the spec says
// the asset renders without them).
// Rejected: files that *require* an extension not read here (compressed or quantised meshes...).
// Normals that are NaN, infinite or zero are replaced by the triangle's geometric normal: they are
// only shading hints. A non-finite position is an error, since the triangle has no place.
#include "io/gltf.h"

#include <tbb/parallel_for.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <iostream>
#include <limits>
#include <new>
#include <optional>
#include <string_view>
#include <unordered_map>

#include "io/gltf_file.h"
#include "io/texture_decode.h"
#include "util/error.h"
#include "util/memory.h"

namespace dacrt {
namespace {

static_assert(std::endian::native == std::endian::little, "glTF buffers are little-endian");

using Bytes = std::vector<unsigned char>;

// Accessors without a bufferView (all zeros, maybe sparse-patched) are materialised; their size is
// not bounded by any buffer, so bound it here.
constexpr size_t kMaxSynthesisedBytes = size_t(1) << 30;
// What a triangle takes at least once loaded and traced: its corners and material (40 bytes),
// shading normals (36), the loader's corner indices while it is built (12), the kernel's triangle
// record (20).
constexpr uint64_t kBytesPerTriangle = 40 + 36 + 12 + 20;
// Hits report the triangle as a uint32_t with ~0u meaning "miss".
constexpr size_t kMaxTriangles = std::numeric_limits<uint32_t>::max() - 1;

template <class Number>
std::string str(Number n) {
  return std::to_string(n);
}

// a + b for messages, saturating instead of wrapping.
size_t sat_add(size_t a, size_t b) {
  return a > SIZE_MAX - b ? SIZE_MAX : a + b;
}

// True if the material has extension `extension` with member `member`.
bool has_member(const tinygltf::Material& m, const char* extension, const char* member) {
  auto e = m.extensions.find(extension);
  return e != m.extensions.end() && e->second.IsObject() && e->second.Has(member);
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Normalised n, or `fallback` when n has no usable direction (zero, NaN, inf).
glm::vec3 unit_or(const glm::vec3& n, const glm::vec3& fallback) {
  float len = glm::length(n);
  if (!(len > 0.f) || !std::isfinite(len)) return fallback;
  glm::vec3 u = n / len;
  return finite(u) ? u : fallback;
}

glm::vec3 geometric_normal(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  return unit_or(glm::cross(b - a, c - a), glm::vec3(0.f, 0.f, 1.f));
}

// A validated strided window onto an accessor's elements: element i is the `components` values of
// `component_type` at data + i * stride. Accessors that are sparse or have no bufferView are
// materialised into `owned` (which `data` then points into, so a View is move-only).
struct View {
  const unsigned char* data = nullptr;
  size_t count = 0, stride = 0;
  int component_type = 0, components = 0;
  std::vector<unsigned char> owned;

  View() = default;
  View(View&&) = default;
  View(const View&) = delete;
};

// Bytes per component; 0 for INT (5124) and DOUBLE, which glTF 2.0 accessors do not allow.
size_t component_size(int type) {
  static constexpr size_t sizes[] = {1, 1, 2, 2, 0, 4, 4};  // BYTE ... FLOAT = 5120 ... 5126
  return type >= 5120 && type <= 5126 ? sizes[type - 5120] : 0;
}

bool unsigned_index_type(int type) {
  return type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

// An unsigned index of 1, 2 or 4 bytes (little-endian, like the host: the low bytes come first).
uint32_t read_uint(const unsigned char* p, size_t size) {
  uint32_t v = 0;
  std::memcpy(&v, p, size);
  return v;
}

// Component `c` of an element as a float: FLOAT as it is, integers normalised as glTF defines it
// (unsigned c / max, signed max(c / max, -1)).
float component_value(const unsigned char* element, int c, int type) {
  const unsigned char* p = element + size_t(c) * component_size(type);
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return float(*p) / 255.f;
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return std::max(float(int8_t(*p)) / 127.f, -1.f);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t x;
      std::memcpy(&x, p, 2);
      return float(x) / 65535.f;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t x;
      std::memcpy(&x, p, 2);
      return std::max(float(x) / 32767.f, -1.f);
    }
  }
  return 0.f;
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return "FLOAT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return "SHORT";
  }
  return "an integer type";
}

// glTF's default material (a file's primitives without one use it).
Material default_material() {
  Material m;
  m.name = "default";
  return m;
}

// A per-corner attribute (3 values per triangle) kept once some primitive has it; the triangles
// added before then get `fill`.
template <class T>
struct CornerStream {
  std::vector<T> data;
  bool on = false;
  void start(size_t triangles, const T& fill) {
    if (!on) on = true, data.assign(3 * triangles, fill);
  }
};

// Tangents for a normal map laid out by `uv` when the file gives none, 3 per triangle of
// `corners`, grouped and weighted as MikkTSpace does (not its code, so not bit-identical): at
// each corner the triangle's uv tangent ∂p/∂u is projected onto the plane of the corner's shading
// normal `normals[3 t + k]`, normalised and weighted by the triangle's angle there; corners
// sum over the triangles that share their vertex (vertices with the same position, normal and uv
// count as one, as MikkTSpace welds them), apart for triangles whose layout is mirrored; each sum
// is projected and normalised again. w is the bitangent's sign (bitangent = cross(n, t) · w):
// glTF's v runs down the image while a normal map's +Y points up it, so an unmirrored layout has
// w = 1 with cross(n, t) along −∂p/∂v. Zero where no uv tangent reached the corner.
std::vector<glm::vec4> generate_tangents(const std::vector<glm::vec3>& p,
                                         const std::vector<glm::vec2>& uv,
                                         const std::vector<std::array<uint32_t, 3>>& corners,
                                         const std::vector<glm::vec3>& normals) {
  // One key per distinct (position, normal, uv) among the corners.
  // Keys compare and hash the same canonical bits: −0 as +0, every NaN as one NaN (NaN uvs
  // would otherwise never equal themselves and pile up under one hash).
  struct Key {
    uint32_t bits[8];
    Key(const glm::vec3& p, const glm::vec3& n, const glm::vec2& uv) {
      const float f[8] = {p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y};
      for (int k = 0; k < 8; ++k) {
        const float c = std::isnan(f[k]) ? std::numeric_limits<float>::quiet_NaN() : f[k] + 0.f;
        std::memcpy(&bits[k], &c, 4);
      }
    }
    bool operator==(const Key& o) const { return std::memcmp(bits, o.bits, sizeof bits) == 0; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      size_t h = 0xcbf29ce484222325ull;
      for (uint32_t b : k.bits) h = (h ^ b) * 0x100000001b3ull;
      return h;
    }
  };
  std::unordered_map<Key, uint32_t, KeyHash> welded;
  std::vector<uint32_t> group(3 * corners.size());
  for (size_t t = 0; t < corners.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = corners[t][size_t(k)];
      group[3 * t + size_t(k)] =
          welded.try_emplace(Key(p[i], normals[3 * t + size_t(k)], uv[i]), uint32_t(welded.size()))
              .first->second;
    }
  std::vector<glm::vec3> sum(2 * welded.size(), glm::vec3(0.f));
  std::vector<uint8_t> mirrored(corners.size(), 0);
  for (size_t t = 0; t < corners.size(); ++t) {
    const auto& c = corners[t];
    const glm::vec3 e1 = p[c[1]] - p[c[0]], e2 = p[c[2]] - p[c[0]];
    const glm::vec2 d1 = uv[c[1]] - uv[c[0]], d2 = uv[c[2]] - uv[c[0]];
    const float det = d1.x * d2.y - d1.y * d2.x;
    if (!(std::abs(det) > 0.f)) continue;
    const glm::vec3 dpdu = (e1 * d2.y - e2 * d1.y) / det, dpdv = (e2 * d1.x - e1 * d2.x) / det;
    mirrored[t] = glm::dot(glm::cross(glm::cross(e1, e2), dpdu), dpdv) > 0.f;
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = normals[3 * t + size_t(k)];
      const glm::vec3 projected = dpdu - n * glm::dot(n, dpdu);
      const float len = glm::length(projected);
      const glm::vec3 a = p[c[size_t(k + 1) % 3]] - p[c[size_t(k)]];
      const glm::vec3 b = p[c[size_t(k + 2) % 3]] - p[c[size_t(k)]];
      const float ab = glm::length(a) * glm::length(b);
      if (!(len > 0.f) || !std::isfinite(len) || !(ab > 0.f) || !std::isfinite(ab)) continue;
      const float angle = std::acos(std::clamp(glm::dot(a, b) / ab, -1.f, 1.f));
      sum[2 * size_t(group[3 * t + size_t(k)]) + mirrored[t]] += projected * (angle / len);
    }
  }
  std::vector<glm::vec4> out(3 * corners.size(), glm::vec4(0.f));
  for (size_t t = 0; t < corners.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = normals[3 * t + size_t(k)];
      glm::vec3 s = sum[2 * size_t(group[3 * t + size_t(k)]) + mirrored[t]];
      s -= n * glm::dot(n, s);
      const float len = glm::length(s);
      if (len > 0.f && std::isfinite(len))
        out[3 * t + size_t(k)] = glm::vec4(s / len, mirrored[t] ? -1.f : 1.f);
    }
  return out;
}

// The part of a node's world transform that positions, normals and winding need.
struct Transform {
  glm::mat4 world;
  glm::mat3 normal;  // inverse-transpose of world's 3x3, up to a positive factor
  bool flips;        // negative determinant: mirrored, so the winding must be swapped back
  int node;
};

class Loader {
 public:
  Loader(const std::string& path, const tinygltf::Model& model) : path_(path), model_(model) {}

  Scene run(int scene) {
    scene_.path = path_;
    // Required extensions, types, ranges and indices were checked against the schema
    // (io/gltf_schema.cpp) before tinygltf parsed the file.

    bool by_default = scene == -1;
    if (by_default) scene = model_.defaultScene == -1 ? 0 : model_.defaultScene;
    size_t count = model_.scenes.size();
    // A file without scenes (a library of meshes) gives an empty scene, unless one was asked for.
    if ((scene < 0 || size_t(scene) >= count) && !(count == 0 && by_default && scene == 0))
      fail(std::string(by_default ? "default " : "") + "scene " + str(scene) + " does not exist (" +
           str(count) + " scenes)");
    texture_used_.assign(model_.textures.size(), false);
    load_materials();
    mesh_seen_.assign(model_.meshes.size(), false);
    if (count > 0) traverse(scene);
    load_textures();

    if (keep_normals_) scene_.normals = std::move(normals_);
    for (int set = 0; set < 2; ++set) scene_.texcoords[set] = std::move(texcoords_[set].data);
    scene_.colors = std::move(colors_.data);
    scene_.tangents = std::move(tangents_.data);
    if (scene_.materials.empty()) scene_.materials.push_back(default_material());
    scene_.cameras_from_file = scene_.cameras.size();
    if (scene_.cameras.empty()) scene_.cameras.push_back(frame_bounds(scene_.bounds(), 0.f));

    auto warn = [&](size_t n, const char* what) {
      if (n > 0) std::cerr << "warning: " << path_ << ": skipped " << n << " " << what << "\n";
    };
    warn(skipped_modes_, "point and line primitives");
    warn(skipped_unpositioned_, "primitives without POSITION");
    const Scene::Ignored& i = scene_.ignored;
    if (i.any()) {
      std::string what;
      auto add = [&](size_t n, const char* name) {
        if (n) what += (what.empty() ? "" : ", ") + str(n) + " " + name;
      };
      add(i.specular_textures, "KHR_materials_specular textures");
      add(i.volumes, "KHR_materials_volume thicknesses (rendered thin-walled)");
      std::cerr << "warning: " << path_ << ": not rendered as specified in this version: " << what
                << "\n";
    }
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }

  struct Span {
    const unsigned char* data;
    size_t size;
    size_t stride;
  };

  Span buffer_view(int index, const std::string& user) const {
    if (index < 0 || size_t(index) >= model_.bufferViews.size())
      fail(user + " refers to bufferView " + str(index) + ", which does not exist");
    const tinygltf::BufferView& bv = model_.bufferViews[size_t(index)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size())
      fail("bufferView " + str(index) + " refers to buffer " + str(bv.buffer) +
           ", which does not exist");
    const Bytes& buffer = model_.buffers[size_t(bv.buffer)].data;
    if (bv.byteOffset > buffer.size() || bv.byteLength > buffer.size() - bv.byteOffset)
      fail("bufferView " + str(index) + " (of " + user + ") overruns buffer " + str(bv.buffer) +
           " (needs " + str(sat_add(bv.byteOffset, bv.byteLength)) + " bytes, has " +
           str(buffer.size()) + ")");
    return {buffer.data() + bv.byteOffset, bv.byteLength, bv.byteStride};
  }

  // `bytes` tightly packed bytes at `offset` in bufferView `view` (sparse indices and values).
  const unsigned char* region(int view, int offset, size_t bytes, const std::string& what) const {
    Span span = buffer_view(view, what);
    if (offset < 0) fail(what + " has a negative byteOffset");
    if (size_t(offset) > span.size || bytes > span.size - size_t(offset))
      fail(what + " overruns bufferView " + str(view) + " (needs " +
           str(sat_add(size_t(offset), bytes)) + " bytes, has " + str(span.size) + ")");
    return span.data + offset;
  }

  View view(int index, const std::string& role) const {
    if (index < 0 || size_t(index) >= model_.accessors.size())
      fail(role + " refers to accessor " + str(index) + ", which does not exist");
    const tinygltf::Accessor& a = model_.accessors[size_t(index)];
    std::string what = "accessor " + str(index) + " (" + role + ")";
    View v;
    v.count = a.count;
    v.component_type = a.componentType;
    v.components = a.type == TINYGLTF_TYPE_SCALAR ? 1 : (a.type >= 2 && a.type <= 4 ? a.type : 0);
    size_t csize = component_size(a.componentType);
    if (csize == 0)
      fail(what + " has componentType " + str(a.componentType) + ", which glTF 2.0 does not allow");
    if (v.components == 0) fail(what + " has a matrix type, which no vertex attribute uses");
    size_t element = csize * size_t(v.components);
    v.stride = element;

    if (a.bufferView != -1) {
      Span span = buffer_view(a.bufferView, what);
      if (span.stride != 0) {
        if (span.stride < element)
          fail(what + " has " + str(element) + "-byte elements but bufferView " +
               str(a.bufferView) + " has byteStride " + str(span.stride));
        v.stride = span.stride;
      }
      // byteOffset + (count - 1) * stride + element, without wrapping: a huge count must fail
      // here as an overrun, not allocate or read.
      size_t needed = 0;
      if (v.count > 0 && (__builtin_mul_overflow(v.count - 1, v.stride, &needed) ||
                          __builtin_add_overflow(needed, element, &needed) ||
                          __builtin_add_overflow(needed, a.byteOffset, &needed)))
        needed = SIZE_MAX;
      if (needed > span.size)
        fail(what + " overruns bufferView " + str(a.bufferView) + " (needs " + str(needed) +
             " bytes, has " + str(span.size) + ")");
      v.data = span.data + (v.count > 0 ? a.byteOffset : 0);
    } else {
      // No bufferView: the spec says zeros (then patched by `sparse`). Nothing bounds the count.
      size_t bytes = 0;
      bool overflows = __builtin_mul_overflow(v.count, element, &bytes);
      if (overflows || bytes > kMaxSynthesisedBytes)
        fail(what + " has no bufferView and count " + str(v.count) + ": it would need " +
             (overflows ? std::string("more than 2^64") : str(bytes)) + " bytes");
      v.owned.assign(bytes, 0);
      v.data = v.owned.data();
    }
    if (a.sparse.isSparse) apply_sparse(a, v, what);
    return v;
  }

  void apply_sparse(const tinygltf::Accessor& a, View& v, const std::string& what) const {
    const auto& s = a.sparse;
    if (s.count < 0 || size_t(s.count) > v.count)
      fail(what + " has sparse count " + str(s.count) + ", outside [0, " + str(v.count) + "]");
    size_t element = component_size(v.component_type) * size_t(v.components);
    if (a.bufferView != -1) {
      // Patch a packed copy, never the file's buffer (other accessors may share it). The copy is no
      // bigger than the bufferView, which was bounds-checked above.
      Bytes dense(v.count * element);
      for (size_t i = 0; i < v.count; ++i)
        std::memcpy(&dense[i * element], v.data + i * v.stride, element);
      v.owned = std::move(dense);
      v.data = v.owned.data();
      v.stride = element;
    }
    size_t index_size = component_size(s.indices.componentType);
    if (!unsigned_index_type(s.indices.componentType))
      fail(what + " has sparse indices of componentType " + str(s.indices.componentType) +
           " (must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT)");
    size_t n = size_t(s.count);
    const unsigned char* indices = region(s.indices.bufferView, s.indices.byteOffset,
                                          n * index_size, "the sparse index array of " + what);
    const unsigned char* values = region(s.values.bufferView, s.values.byteOffset, n * element,
                                         "the sparse value array of " + what);
    for (size_t k = 0; k < n; ++k) {
      uint32_t i = read_uint(indices + k * index_size, index_size);
      if (i >= v.count)
        fail(what + " has sparse index " + str(i) + ", past its count " + str(v.count));
      std::memcpy(&v.owned[i * element], values + k * element, element);
    }
  }

  // EXT_mesh_gpu_instancing's per-instance TRANSLATION, ROTATION and SCALE as matrices (T R S);
  // nothing when the node does not use it (and an empty list for zero instances).
  std::optional<std::vector<glm::mat4>> instance_transforms(const tinygltf::Node& node,
                                                            int index) const {
    auto ext = node.extensions.find("EXT_mesh_gpu_instancing");
    if (ext == node.extensions.end()) return std::nullopt;
    const std::string where = "node " + str(index) + " EXT_mesh_gpu_instancing";
    if (!ext->second.IsObject() || !ext->second.Has("attributes") ||
        !ext->second.Get("attributes").IsObject())
      fail(where + " has no attributes");
    const tinygltf::Value& attributes = ext->second.Get("attributes");
    auto accessor = [&](const char* name) {
      if (!attributes.Has(name)) return -1;
      const tinygltf::Value& v = attributes.Get(name);
      if (!v.IsNumber()) fail(where + ": " + name + " is not an accessor index");
      return int(v.GetNumberAsDouble());
    };
    const int t = accessor("TRANSLATION"), r = accessor("ROTATION"), s = accessor("SCALE");
    std::vector<glm::vec3> translation, scale;
    std::vector<glm::quat> rotation;
    size_t count = 0;
    bool counted = false;
    auto same_count = [&](size_t n, const char* name) {
      if (counted && n != count)
        fail(where + ": " + name + " has " + str(n) + " instances, not " + str(count));
      count = n, counted = true;
    };
    if (t != -1)
      translation = read_vec3(t, "TRANSLATION of " + where),
      same_count(translation.size(), "TRANSLATION");
    if (s != -1) scale = read_vec3(s, "SCALE of " + where), same_count(scale.size(), "SCALE");
    if (r != -1)
      rotation = read_rotations(r, "ROTATION of " + where), same_count(rotation.size(), "ROTATION");
    if (!counted) fail(where + " has none of TRANSLATION, ROTATION and SCALE");
    std::vector<glm::mat4> out(count);
    for (size_t i = 0; i < count; ++i) {
      glm::mat4 m(1.f);
      if (!translation.empty()) m = glm::translate(m, translation[i]);
      if (!rotation.empty()) m *= glm::mat4_cast(rotation[i]);
      if (!scale.empty()) m = glm::scale(m, scale[i]);
      if (!finite(glm::vec3(m[0])) || !finite(glm::vec3(m[1])) || !finite(glm::vec3(m[2])) ||
          !finite(glm::vec3(m[3])))
        fail(where + ": instance " + str(i) + " has a non-finite transform");
      out[i] = m;
    }
    return out;
  }

  // Unit quaternions (x, y, z, w): FLOAT, or normalised BYTE or SHORT as the spec allows.
  std::vector<glm::quat> read_rotations(int accessor, const std::string& role) const {
    std::vector<glm::vec4> q = read_floats(
        accessor, role, 4, 4, {TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT}, 1.f);
    std::vector<glm::quat> out(q.size());
    for (size_t i = 0; i < q.size(); ++i) {
      const glm::quat rotation(q[i].w, q[i].x, q[i].y, q[i].z);  // glm: (w, x, y, z)
      const float len = glm::length(rotation);
      if (!(len > 0.f) || !std::isfinite(len))
        fail("accessor " + str(accessor) + " (" + role + ") element " + str(i) +
             " is not a rotation");
      out[i] = rotation / len;
    }
    return out;
  }

  // An attribute of `min_components`..`max_components` components, FLOAT or one of the normalised
  // integer types `integers` (the accessor must then say normalized), as floats; components the
  // accessor lacks are `fill`.
  std::vector<glm::vec4> read_floats(int accessor, const std::string& role, int min_components,
                                     int max_components, std::initializer_list<int> integers,
                                     float fill) const {
    View v = view(accessor, role);
    const int type = v.component_type;
    const std::string what = "accessor " + str(accessor) + " (" + role + ")";
    bool allowed = type == TINYGLTF_COMPONENT_TYPE_FLOAT;
    std::string types = "FLOAT";
    for (int t : integers) allowed |= type == t, types += std::string(", ") + type_name(t);
    if (!allowed || v.components < min_components || v.components > max_components)
      fail(what + " must be " + types + " with " + str(min_components) +
           (max_components > min_components ? " to " + str(max_components) : std::string()) +
           " components (it is " + type_name(type) + " with " + str(v.components) + ")");
    if (type != TINYGLTF_COMPONENT_TYPE_FLOAT && !model_.accessors[size_t(accessor)].normalized)
      fail(what + " must be normalized (" + type_name(type) + ")");
    std::vector<glm::vec4> out(v.count, glm::vec4(fill));
    for (size_t i = 0; i < v.count; ++i)
      for (int c = 0; c < v.components; ++c)
        out[i][c] = component_value(v.data + i * v.stride, c, type);
    return out;
  }

  // POSITION and NORMAL: FLOAT VEC3, copied out of their (possibly strided) view.
  std::vector<glm::vec3> read_vec3(int accessor, const std::string& role) const {
    View v = view(accessor, role);
    if (v.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT || v.components != 3)
      fail("accessor " + str(accessor) + " (" + role + ") must be FLOAT VEC3 (componentType " +
           str(v.component_type) + ", " + str(v.components) + " components)");
    std::vector<glm::vec3> out(v.count);
    for (size_t i = 0; i < v.count; ++i)
      std::memcpy(&out[i], v.data + i * v.stride, sizeof(glm::vec3));
    return out;
  }

  void load_materials() {
    for (size_t i = 0; i < model_.materials.size(); ++i) {
      const tinygltf::Material& src = model_.materials[i];
      std::string what = "material " + str(i);
      Material m;
      m.name = src.name;
      m.double_sided = src.doubleSided;
      Scene::Ignored& ignored = scene_.ignored;
      ignored.specular_textures +=
          has_member(src, "KHR_materials_specular", "specularTexture") ||
          has_member(src, "KHR_materials_specular", "specularColorTexture");
      if (src.alphaMode == "MASK")
        m.alpha_mode = Material::AlphaMode::mask;
      else if (src.alphaMode == "BLEND")
        m.alpha_mode = Material::AlphaMode::blend;
      else if (src.alphaMode != "OPAQUE" && !src.alphaMode.empty())
        fail(what + ": alphaMode \"" + src.alphaMode + "\" is not OPAQUE, MASK or BLEND");
      if (!(src.alphaCutoff >= 0.0) || !std::isfinite(src.alphaCutoff))
        fail(what + ": alphaCutoff is not a finite number >= 0");
      m.alpha_cutoff = float(src.alphaCutoff);
      const auto& base = src.pbrMetallicRoughness.baseColorFactor;
      const auto& emissive = src.emissiveFactor;
      if (base.size() != 4)
        fail(what + ": baseColorFactor has " + str(base.size()) + " numbers, not 4");
      if (emissive.size() != 3)
        fail(what + ": emissiveFactor has " + str(emissive.size()) + " numbers, not 3");
      // The spec bounds the factors to [0, 1]; clamping keeps the albedo energy-conserving.
      m.base_color = glm::clamp(glm::vec3(base[0], base[1], base[2]), 0.f, 1.f);
      if (!std::isfinite(base[3])) fail(what + ": baseColorFactor is not finite");
      m.alpha = std::clamp(float(base[3]), 0.f, 1.f);
      glm::vec3 emission = glm::clamp(glm::vec3(emissive[0], emissive[1], emissive[2]), 0.f, 1.f);
      // A number member of an extension object, or `fallback` when it is absent.
      auto extension_number = [&](const char* extension, const char* member, double fallback) {
        if (!has_member(src, extension, member)) return fallback;
        const tinygltf::Value& value = src.extensions.at(extension).Get(member);
        if (!value.IsNumber() || !std::isfinite(value.GetNumberAsDouble()))
          fail(what + ": " + extension + "." + member + " is not a finite number");
        return value.GetNumberAsDouble();
      };
      ignored.volumes += extension_number("KHR_materials_volume", "thicknessFactor", 0.0) > 0.0;
      const double strength =
          extension_number("KHR_materials_emissive_strength", "emissiveStrength", 1.0);
      if (!(strength >= 0.0) || !std::isfinite(float(strength)))
        fail(what +
             ": KHR_materials_emissive_strength.emissiveStrength is not a finite number >= 0");
      m.emission = emission * float(strength);
      if (!finite(m.base_color) || !finite(m.emission))
        fail(what + ": a colour factor is not finite");
      // Factors the spec bounds to [0, 1] are clamped; what is not a number is an error.
      auto unit = [&](double value, const char* name) {
        if (!std::isfinite(value)) fail(what + ": " + name + " is not a finite number");
        return std::clamp(float(value), 0.f, 1.f);
      };
      m.metallic = unit(src.pbrMetallicRoughness.metallicFactor, "metallicFactor");
      m.roughness = unit(src.pbrMetallicRoughness.roughnessFactor, "roughnessFactor");
      // KHR_materials_ior: 1 or more, or exactly 0 (Fresnel 1, for converted spec-gloss files).
      const double ior = extension_number("KHR_materials_ior", "ior", 1.5);
      if (!(ior >= 1.0 || ior == 0.0))
        fail(what + ": KHR_materials_ior.ior is " + std::to_string(ior) + ", not 0 or >= 1");
      m.ior = float(std::min(ior, 1e6));  // beyond, F0 is 1 to float precision
      m.specular = unit(extension_number("KHR_materials_specular", "specularFactor", 1.0),
                        "KHR_materials_specular.specularFactor");
      m.transmission =
          unit(extension_number("KHR_materials_transmission", "transmissionFactor", 0.0),
               "KHR_materials_transmission.transmissionFactor");
      if (has_member(src, "KHR_materials_transmission", "transmissionTexture"))
        m.transmission_texture = texture_ref(
            extension_texture(
                src.extensions.at("KHR_materials_transmission").Get("transmissionTexture"),
                what + " KHR_materials_transmission.transmissionTexture"),
            what + " KHR_materials_transmission.transmissionTexture");
      if (has_member(src, "KHR_materials_specular", "specularColorFactor")) {
        const tinygltf::Value& c =
            src.extensions.at("KHR_materials_specular").Get("specularColorFactor");
        if (!c.IsArray() || c.ArrayLen() != 3)
          fail(what + ": KHR_materials_specular.specularColorFactor is not 3 numbers");
        for (int k = 0; k < 3; ++k) {
          if (!c.Get(k).IsNumber() || !std::isfinite(c.Get(k).GetNumberAsDouble()) ||
              c.Get(k).GetNumberAsDouble() < 0.0)
            fail(what + ": KHR_materials_specular.specularColorFactor is not 3 numbers >= 0");
          m.specular_color[k] = float(c.Get(k).GetNumberAsDouble());
        }
      }
      const auto& pbr = src.pbrMetallicRoughness;
      m.base_color_texture = texture_ref(pbr.baseColorTexture, what + " baseColorTexture");
      m.metallic_roughness_texture =
          texture_ref(pbr.metallicRoughnessTexture, what + " metallicRoughnessTexture");
      m.emissive_texture = texture_ref(src.emissiveTexture, what + " emissiveTexture");
      m.normal_texture = texture_ref(src.normalTexture, what + " normalTexture");
      if (!std::isfinite(src.normalTexture.scale))
        fail(what + ": normalTexture.scale is not a finite number");
      m.normal_scale = float(src.normalTexture.scale);
      scene_.materials.push_back(m);
    }
  }

  // A textureInfo inside an extension (tinygltf leaves those as JSON values).
  tinygltf::TextureInfo extension_texture(const tinygltf::Value& v, const std::string& what) const {
    tinygltf::TextureInfo info;
    auto integer = [&](const char* name, int fallback) {
      if (!v.Has(name)) return fallback;
      const tinygltf::Value& n = v.Get(name);
      if (!n.IsNumber() || !(n.GetNumberAsDouble() >= 0.0 && n.GetNumberAsDouble() < 1e9))
        fail(what + ": " + name + " is not an index");
      return int(n.GetNumberAsDouble());
    };
    if (!v.IsObject() || !v.Has("index")) fail(what + " has no texture index");
    info.index = integer("index", -1);
    info.texCoord = integer("texCoord", 0);
    if (v.Has("extensions") && v.Get("extensions").IsObject())
      for (const std::string& key : v.Get("extensions").Keys())
        info.extensions[key] = v.Get("extensions").Get(key);
    return info;
  }

  // A textureInfo (with KHR_texture_transform); marks the texture used and its TEXCOORD set needed.
  template <class Info>
  TextureRef texture_ref(const Info& info, const std::string& what) {
    TextureRef ref;
    if (info.index == -1) return ref;
    if (info.index < 0 || size_t(info.index) >= model_.textures.size())
      fail(what + " refers to texture " + str(info.index) + ", which does not exist (" +
           str(model_.textures.size()) + " textures)");
    ref.texture = info.index;
    int set = info.texCoord;
    if (auto ext = info.extensions.find("KHR_texture_transform"); ext != info.extensions.end()) {
      const std::string where = what + " KHR_texture_transform";
      const tinygltf::Value& t = ext->second;
      if (!t.IsObject()) fail(where + " is not an object");
      auto pair = [&](const char* name, glm::vec2 fallback) {
        if (!t.Has(name)) return fallback;
        const tinygltf::Value& a = t.Get(name);
        if (!a.IsArray() || a.ArrayLen() != 2 || !a.Get(0).IsNumber() || !a.Get(1).IsNumber())
          fail(where + ": " + name + " is not 2 numbers");
        glm::vec2 out(a.Get(0).GetNumberAsDouble(), a.Get(1).GetNumberAsDouble());
        if (!std::isfinite(out.x) || !std::isfinite(out.y))
          fail(where + ": " + name + " is not finite");
        return out;
      };
      const glm::vec2 offset = pair("offset", glm::vec2(0.f)),
                      scale = pair("scale", glm::vec2(1.f));
      float rotation = 0.f;
      if (t.Has("rotation")) {
        if (!t.Get("rotation").IsNumber() || !std::isfinite(t.Get("rotation").GetNumberAsDouble()))
          fail(where + ": rotation is not a finite number");
        rotation = float(t.Get("rotation").GetNumberAsDouble());
      }
      if (t.Has("texCoord")) {
        if (!t.Get("texCoord").IsNumber()) fail(where + ": texCoord is not a number");
        set = int(std::clamp(t.Get("texCoord").GetNumberAsDouble(), -1.0, 1e6));
      }
      // offset · rotation · scale: u' = cos·sx·u + sin·sy·v + ox, v' = −sin·sx·u + cos·sy·v + oy
      // (the rotation turns the image clockwise on screen, as the Khronos TextureTransformTest
      // model's markers check).
      const float c = std::cos(rotation), s = std::sin(rotation);
      ref.transform = glm::mat3x2(glm::vec2(c * scale.x, -s * scale.x),
                                  glm::vec2(s * scale.y, c * scale.y), offset);
    }
    if (set < 0 || set > 1)
      fail(what + ": texCoord " + str(set) + " is not supported (TEXCOORD_0 and TEXCOORD_1 are)");
    ref.texcoord = uint8_t(set);
    return ref;
  }

  // Samplers for every texture; images decoded (in parallel) for the textures materials use.
  void load_textures() {
    std::vector<bool> image_used(model_.images.size(), false);
    scene_.textures.resize(model_.textures.size());
    for (size_t i = 0; i < model_.textures.size(); ++i) {
      if (!texture_used_[i]) continue;
      const tinygltf::Texture& src = model_.textures[i];
      const std::string what = "texture " + str(i);
      Texture& t = scene_.textures[i];
      if (src.source < 0 || size_t(src.source) >= model_.images.size())
        fail(what + (src.source == -1
                         ? " has no PNG or JPEG source image"
                         : " refers to image " + str(src.source) + ", which does not exist (" +
                               str(model_.images.size()) + " images)"));
      t.image = uint32_t(src.source);
      image_used[size_t(src.source)] = true;
      if (src.sampler != -1) {
        if (src.sampler < 0 || size_t(src.sampler) >= model_.samplers.size())
          fail(what + " refers to sampler " + str(src.sampler) + ", which does not exist");
        const tinygltf::Sampler& sampler = model_.samplers[size_t(src.sampler)];
        const std::string where = "sampler " + str(src.sampler);
        t.wrap_s = wrap_mode(sampler.wrapS, where + " wrapS");
        t.wrap_t = wrap_mode(sampler.wrapT, where + " wrapT");
        t.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
      }
    }
    // Images with the same encoded bytes (or bufferView) are decoded once: textures point at the
    // first of them.
    std::vector<size_t> used, first(model_.images.size());
    std::unordered_map<uint64_t, std::vector<size_t>> by_source;  // source hash → images
    for (size_t i = 0; i < image_used.size(); ++i) {
      if (!image_used[i]) continue;
      std::vector<size_t>& bucket = by_source[source_hash(i)];
      auto same =
          std::find_if(bucket.begin(), bucket.end(), [&](size_t j) { return same_source(j, i); });
      first[i] = same == bucket.end() ? i : *same;
      if (first[i] == i) used.push_back(i), bucket.push_back(i);
    }
    for (size_t t = 0; t < scene_.textures.size(); ++t)
      if (texture_used_[t]) scene_.textures[t].image = uint32_t(first[scene_.textures[t].image]);
    scene_.images.resize(model_.images.size());
    // The sizes first, so that the whole set is bounded before anything is decoded.
    constexpr uint64_t kMaxDecodedBytes = uint64_t(1) << 32;
    uint64_t total = 0;
    for (size_t i : used) {
      const auto [data, size] = image_bytes(i);
      total += decoded_size(data, size, path_ + ": " + image_name(i));
    }
    if (total > kMaxDecodedBytes)
      fail("its images would take " + str(total >> 20) + " MiB decoded, more than the " +
           str(kMaxDecodedBytes >> 20) + " MiB limit");
    // In parallel. Reported: the first header error in image order (above), else the first
    // decoding error in image order. Images are decoded straight into what is kept; on top of
    // it, a progressive JPEG being decoded holds its coefficients (2 bytes a sample) per thread.
    std::vector<std::string> errors(used.size());
    tbb::parallel_for(size_t(0), used.size(), [&](size_t k) {
      const size_t i = used[k];
      try {
        const auto [data, size] = image_bytes(i);
        scene_.images[i] = decode_image(data, size, path_ + ": " + image_name(i));
      } catch (const Error& e) {
        errors[k] = e.what();
      }
    });
    for (const std::string& e : errors)
      if (!e.empty()) throw Error(e);
  }

  // "image N (uri or name)", for messages.
  std::string image_name(size_t i) const {
    const tinygltf::Image& image = model_.images[i];
    std::string what = "image " + str(i);
    if (!image.uri.empty() && image.uri.rfind("data:", 0) != 0)
      what += " (" + one_line(image.uri.substr(0, 200)) + ")";
    else if (!image.name.empty())
      what += " (" + one_line(image.name.substr(0, 200)) + ")";
    return what;
  }

  // The encoded bytes of image i: its bufferView, or what tinygltf read from its URI.
  std::pair<const unsigned char*, size_t> image_bytes(size_t i) const {
    const tinygltf::Image& image = model_.images[i];
    if (image.bufferView != -1) {
      const Span span = buffer_view(image.bufferView, image_name(i));
      return {span.data, span.size};
    }
    if (image.image.empty()) fail(image_name(i) + " cannot be read (missing or empty file)");
    return {image.image.data(), image.image.size()};
  }

  // The bufferView, or a hash of the encoded bytes (FNV-1a).
  uint64_t source_hash(size_t i) const {
    const tinygltf::Image& image = model_.images[i];
    if (image.bufferView != -1) return uint64_t(image.bufferView);
    uint64_t h = 0xcbf29ce484222325ull ^ image.image.size();
    for (unsigned char c : image.image) h = (h ^ c) * 0x100000001b3ull;
    return h | (uint64_t(1) << 63);  // apart from bufferView indices
  }

  bool same_source(size_t a, size_t b) const {
    const tinygltf::Image &x = model_.images[a], &y = model_.images[b];
    if (x.bufferView != -1 || y.bufferView != -1) return x.bufferView == y.bufferView;
    return !x.image.empty() && x.image == y.image;
  }

  Wrap wrap_mode(int mode, const std::string& what) const {
    switch (mode) {
      case TINYGLTF_TEXTURE_WRAP_REPEAT:
        return Wrap::repeat;
      case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
        return Wrap::clamp;
      case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
        return Wrap::mirror;
    }
    fail(what + " is " + str(mode) + ", not 10497, 33071 or 33648");
  }

  // The material's textures are needed once a primitive uses it (only those are decoded).
  void use_textures(const Material& m) {
    for (const TextureRef* ref : m.sampled_textures())
      if (ref && *ref) texture_used_[size_t(ref->texture)] = true;
  }

  uint32_t material_for(int index, const std::string& where) {
    if (index == -1) {  // the glTF default material, appended once, only if used
      if (default_material_ < 0) {
        default_material_ = int(scene_.materials.size());
        scene_.materials.push_back(default_material());
      }
      return uint32_t(default_material_);
    }
    if (index < 0 || size_t(index) >= model_.materials.size())
      fail(where + " refers to material " + str(index) + ", which does not exist (" +
           str(model_.materials.size()) + " materials)");
    return uint32_t(index);
  }

  glm::mat4 local_transform(int index) const {
    const tinygltf::Node& n = model_.nodes[size_t(index)];
    std::string what = "node " + str(index);
    auto expect = [&](const std::vector<double>& v, size_t size, const char* name) {
      if (!v.empty() && v.size() != size)
        fail(what + ": " + name + " has " + str(v.size()) + " numbers, not " + str(size));
      return !v.empty();
    };
    glm::mat4 m(1.f);
    if (expect(n.matrix, 16, "matrix")) {
      for (int i = 0; i < 16; ++i)
        m[i / 4][i % 4] = float(n.matrix[size_t(i)]);  // both column-major
      // glTF requires the bottom row to be 0 0 0 1; keep the transform affine whatever the file
      // says.
      m[0][3] = m[1][3] = m[2][3] = 0.f;
      m[3][3] = 1.f;
    } else {
      glm::mat4 t(1.f), r(1.f), s(1.f);
      if (expect(n.translation, 3, "translation"))
        t[3] = glm::vec4(float(n.translation[0]), float(n.translation[1]), float(n.translation[2]),
                         1.f);
      if (expect(n.rotation, 4, "rotation")) {
        glm::quat q(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]),
                    float(n.rotation[2]));
        float len = glm::length(q);
        if (!(len > 0.f) || !std::isfinite(len))
          fail(what + ": rotation is not a usable quaternion");
        r = glm::mat4_cast(q / len);  // files round their unit quaternions; renormalise
      }
      if (expect(n.scale, 3, "scale"))
        for (int axis = 0; axis < 3; ++axis) s[axis][axis] = float(n.scale[size_t(axis)]);
      m = t * r * s;
    }
    for (int c = 0; c < 4; ++c)
      if (!finite(glm::vec3(m[c]))) fail(what + ": transform is not finite");
    return m;
  }

  // Depth-first, pre-order, with an explicit stack: deep trees cannot overflow the call stack, and
  // a node reached twice (a cycle, two parents, or listed twice) is caught before it is pushed
  // again.
  void traverse(int scene) {
    constexpr int kUnreached = -2, kRoot = -1;
    std::vector<int> parent(model_.nodes.size(), kUnreached);
    struct Pending {
      int node;
      glm::mat4 parent_world;
    };
    std::vector<Pending> stack;
    auto push = [&](int child, int from, const glm::mat4& parent_world) {
      std::string by = from == kRoot ? "scene " + str(scene) : "node " + str(from);
      if (child < 0 || size_t(child) >= model_.nodes.size())
        fail(by + " refers to node " + str(child) + ", which does not exist");
      int& p = parent[size_t(child)];
      if (p != kUnreached) {
        for (int a = from; a >= 0; a = parent[size_t(a)])
          if (a == child) fail("node " + str(child) + " is its own ancestor (cycle)");
        std::string first = p == kRoot ? "scene " + str(scene) : "node " + str(p);
        fail("node " + str(child) + " has two parents (" + first + " and " + by + ")");
      }
      p = from;
      stack.push_back({child, parent_world});
    };

    const auto& roots = model_.scenes[size_t(scene)].nodes;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) push(*it, kRoot, glm::mat4(1.f));
    while (!stack.empty()) {
      Pending item = stack.back();
      stack.pop_back();
      const tinygltf::Node& node = model_.nodes[size_t(item.node)];
      ++scene_.node_count;
      glm::mat4 world = item.parent_world * local_transform(item.node);
      if (node.mesh != -1) {
        // EXT_mesh_gpu_instancing: the mesh once per instance, never at the node itself.
        if (auto instances = instance_transforms(node, item.node); !instances)
          add_mesh(node.mesh, world, item.node);
        else
          for (const glm::mat4& m : *instances) add_mesh(node.mesh, world * m, item.node);
      }
      if (node.camera != -1) add_camera(node.camera, world, item.node);
      add_light(node, world, item.node);
      for (auto it = node.children.rbegin(); it != node.children.rend(); ++it)
        push(*it, item.node, world);
    }
  }

  void add_mesh(int mesh, const glm::mat4& world, int node) {
    if (mesh < 0 || size_t(mesh) >= model_.meshes.size())
      fail("node " + str(node) + " refers to mesh " + str(mesh) + ", which does not exist");
    bool first_instance = !mesh_seen_[size_t(mesh)];
    mesh_seen_[size_t(mesh)] = true;
    scene_.mesh_count += first_instance;

    Transform xf{world, glm::mat3(1.f), false, node};
    glm::mat3 linear(world);
    // The cofactor matrix is det × inverse-transpose: always finite, even for a zero scale.
    xf.normal = glm::mat3(glm::cross(linear[1], linear[2]), glm::cross(linear[2], linear[0]),
                          glm::cross(linear[0], linear[1]));
    xf.flips = glm::determinant(linear) < 0.f;
    if (xf.flips) xf.normal = -xf.normal;
    for (size_t p = 0; p < model_.meshes[size_t(mesh)].primitives.size(); ++p)
      add_primitive(mesh, int(p), xf, first_instance);
  }

  // Once one primitive has NORMAL, every triangle needs 3 normals: earlier ones get geometric
  // normals.
  void start_normals() {
    keep_normals_ = true;
    const Geometry& g = scene_.geometry;
    normals_.reserve(3 * g.size());
    for (size_t t = 0; t < g.size(); ++t)
      normals_.insert(normals_.end(), 3,
                      geometric_normal(g.vertex(t, 0), g.vertex(t, 1), g.vertex(t, 2)));
  }

  void add_primitive(int mesh, int index, const Transform& xf, bool first_instance) {
    const tinygltf::Primitive& prim = model_.meshes[size_t(mesh)].primitives[size_t(index)];
    std::string where = "mesh " + str(mesh) + " primitive " + str(index);
    const int mode = prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      skipped_modes_ += first_instance;  // points and lines
      return;
    }
    auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end()) {
      skipped_unpositioned_ += first_instance;
      return;
    }
    uint32_t material = material_for(prim.material, where);
    const Material& mat = scene_.materials[material];
    use_textures(mat);

    std::vector<glm::vec3> points = read_vec3(position->second, "POSITION of " + where);
    size_t vertex_count = points.size();
    for (size_t i = 0; i < vertex_count; ++i) {
      if (!finite(points[i]))
        fail("accessor " + str(position->second) + " (POSITION of " + where + ") vertex " + str(i) +
             " is not finite");
      points[i] = glm::vec3(xf.world * glm::vec4(points[i], 1.f));
      if (!finite(points[i]))
        fail("node " + str(xf.node) + " puts vertex " + str(i) + " of " + where +
             " at a non-finite position");
    }

    auto same_count = [&](int accessor, const std::string& role, size_t n) {
      if (n != vertex_count)
        fail("accessor " + str(accessor) + " (" + role + ") has " + str(n) +
             " elements but POSITION has " + str(vertex_count));
    };
    std::vector<glm::vec3> normals;
    if (auto normal = prim.attributes.find("NORMAL"); normal != prim.attributes.end()) {
      normals = read_vec3(normal->second, "NORMAL of " + where);
      same_count(normal->second, "NORMAL of " + where, normals.size());
      for (glm::vec3& n : normals) n = xf.normal * n;  // normalised per corner below
      if (!keep_normals_) start_normals();
    }
    const size_t before = scene_.geometry.size();
    // Texture coordinates, only for the sets some material samples.
    std::vector<glm::vec2> uv[2];
    for (int set = 0; set < 2; ++set) {
      const std::string name = set ? "TEXCOORD_1" : "TEXCOORD_0";
      auto attribute = prim.attributes.find(name);
      bool needed = false;  // does this primitive's material sample set `set`?
      for (const TextureRef* ref : mat.sampled_textures())
        needed |= ref && *ref && ref->texcoord == set;
      if (!needed || attribute == prim.attributes.end()) continue;
      const std::string role = name + " of " + where;
      std::vector<glm::vec4> values = read_floats(
          attribute->second, role, 2, 2,
          {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT}, 0.f);
      same_count(attribute->second, role, values.size());
      uv[set].resize(values.size());
      for (size_t i = 0; i < values.size(); ++i) uv[set][i] = glm::vec2(values[i]);
      texcoords_[set].start(before, glm::vec2(0.f));
    }
    std::vector<glm::vec4> colors;
    if (auto attribute = prim.attributes.find("COLOR_0"); attribute != prim.attributes.end()) {
      const std::string role = "COLOR_0 of " + where;
      colors = read_floats(
          attribute->second, role, 3, 4,
          {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT}, 1.f);
      same_count(attribute->second, role, colors.size());
      for (size_t i = 0; i < colors.size(); ++i) {
        if (!finite(glm::vec3(colors[i])) || !std::isfinite(colors[i].w))
          fail("accessor " + str(attribute->second) + " (" + role + ") element " + str(i) +
               " is not finite");
        colors[i] = glm::clamp(colors[i], 0.f, 1.f);
      }
      colors_.start(before, glm::vec4(1.f));
    }
    // Tangents, only for normal-mapped materials: from the file, else generated below. The spec
    // says to ignore TANGENT when NORMAL is absent (the normals are then flat).
    const TextureRef& normal_map = mat.normal_texture;
    std::vector<glm::vec4> tangents;
    if (auto attribute = prim.attributes.find("TANGENT");
        normal_map && !normals.empty() && attribute != prim.attributes.end()) {
      const std::string role = "TANGENT of " + where;
      tangents = read_floats(attribute->second, role, 4, 4, {}, 0.f);
      same_count(attribute->second, role, tangents.size());
      const glm::mat3 linear(xf.world);
      for (glm::vec4& t : tangents) {
        // A mirroring transform turns the bitangent cross(n, t) around: flip its sign back.
        t = glm::vec4(linear * glm::vec3(t), (t.w < 0.f) != xf.flips ? -1.f : 1.f);
        if (!finite(glm::vec3(t))) t = glm::vec4(0.f);
      }
    }

    std::vector<uint32_t> indices;
    size_t corner_count = vertex_count;
    if (prim.indices != -1) {
      std::string role = "indices of " + where;
      View v = view(prim.indices, role);
      size_t size = component_size(v.component_type);
      if (v.components != 1 || !unsigned_index_type(v.component_type))
        fail("accessor " + str(prim.indices) + " (" + role +
             ") must be an UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT SCALAR");
      indices.resize(v.count);
      for (size_t k = 0; k < v.count; ++k) {
        indices[k] = read_uint(v.data + k * v.stride, size);
        if (indices[k] >= vertex_count)
          fail("accessor " + str(prim.indices) + " (" + role + ") element " + str(k) +
               " is index " + str(indices[k]) + ", past the vertex count " + str(vertex_count));
      }
      corner_count = v.count;
    }
    // Lists: a trailing incomplete triangle is ignored. Strips and fans: the spec's corner order
    // (every strip triangle keeps the first one's winding); their degenerate triangles (repeated
    // indices, used to join strips) are dropped.
    const size_t triangles = mode == TINYGLTF_MODE_TRIANGLES ? corner_count / 3
                             : corner_count >= 3             ? corner_count - 2
                                                             : 0;
    if (triangles > kMaxTriangles - scene_.geometry.size())
      fail("has more than " + str(kMaxTriangles) + " triangles");
    // A small file can instance a large mesh many times: the triangles are bounded by memory as
    // they are added, before they are.
    const uint64_t total = uint64_t(scene_.geometry.size() + triangles);
    if (total * kBytesPerTriangle > available_memory_)
      fail(where + " brings the scene to " + str(total) + " triangles, which need about " +
           format_bytes(total * kBytesPerTriangle) + ", more than the " +
           format_bytes(available_memory_) + " of memory available");

    // The triangles' corners (vertex indices), in the order the front face winds.
    std::vector<std::array<uint32_t, 3>> corners;
    corners.reserve(triangles);
    for (size_t t = 0; t < triangles; ++t) {
      size_t c[3] = {3 * t, 3 * t + 1, 3 * t + 2};
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
        c[0] = t, c[1] = t + 1 + t % 2, c[2] = t + 2 - t % 2;
      else if (mode == TINYGLTF_MODE_TRIANGLE_FAN)
        c[0] = t + 1, c[1] = t + 2, c[2] = 0;
      if (!indices.empty())
        for (size_t& k : c) k = indices[k];
      if (mode != TINYGLTF_MODE_TRIANGLES && (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]))
        continue;
      // A mirrored instance turns counter-clockwise (front) into clockwise: swap back.
      if (xf.flips) std::swap(c[1], c[2]);
      corners.push_back({uint32_t(c[0]), uint32_t(c[1]), uint32_t(c[2])});
    }
    // Shading normals per corner, as stored: computed once, when they are kept or tangents are
    // generated from them.
    const bool generate = tangents.empty() && normal_map && !uv[normal_map.texcoord].empty();
    std::vector<glm::vec3> corner_normals;  // 3 per triangle of `corners`
    if (keep_normals_ || generate) {
      corner_normals.reserve(3 * corners.size());
      for (const auto& c : corners) {
        const glm::vec3 g = geometric_normal(points[c[0]], points[c[1]], points[c[2]]);
        for (uint32_t i : c) corner_normals.push_back(normals.empty() ? g : unit_or(normals[i], g));
      }
    }
    std::vector<glm::vec4> corner_tangents;  // 3 per triangle of `corners`
    if (!tangents.empty()) {
      corner_tangents.reserve(3 * corners.size());
      for (const auto& c : corners)
        for (uint32_t i : c) corner_tangents.push_back(tangents[i]);
    } else if (generate) {
      corner_tangents = generate_tangents(points, uv[normal_map.texcoord], corners, corner_normals);
    }
    if (normal_map) tangents_.start(before, glm::vec4(0.f));

    Geometry& geometry = scene_.geometry;
    for (size_t t = 0; t < corners.size(); ++t) {
      const std::array<uint32_t, 3>& c = corners[t];
      geometry.add(points[c[0]], points[c[1]], points[c[2]], material);
      for (int k = 0; k < 3; ++k) {
        const uint32_t i = c[size_t(k)];
        if (keep_normals_) normals_.push_back(corner_normals[3 * t + size_t(k)]);
        for (int set = 0; set < 2; ++set)
          if (texcoords_[set].on)
            texcoords_[set].data.push_back(uv[set].empty() ? glm::vec2(0.f) : uv[set][i]);
        if (colors_.on) colors_.data.push_back(colors.empty() ? glm::vec4(1.f) : colors[i]);
        if (tangents_.on)
          tangents_.data.push_back(corner_tangents.empty() ? glm::vec4(0.f)
                                                           : corner_tangents[3 * t + size_t(k)]);
      }
    }
    scene_.primitive_count += first_instance;
  }

  void add_camera(int index, const glm::mat4& world, int node) {
    if (index < 0 || size_t(index) >= model_.cameras.size())
      fail("node " + str(node) + " refers to camera " + str(index) + ", which does not exist");
    const tinygltf::Camera& src = model_.cameras[size_t(index)];
    std::string what = "camera " + str(index);
    Camera cam;
    cam.name = src.name;
    if (src.type == "orthographic") {
      // xmag and ymag are half the view's width and height; the spec forbids zero.
      const double xmag = std::abs(src.orthographic.xmag), ymag = std::abs(src.orthographic.ymag);
      if (!(xmag > 0.0 && ymag > 0.0) || !std::isfinite(xmag / ymag) || !std::isfinite(ymag))
        fail(what + ": orthographic xmag and ymag must be finite and non-zero");
      cam.orthographic = true;
      cam.ymag = float(ymag);
      cam.aspect = float(xmag / ymag);
      cam.znear = float(src.orthographic.znear);
    } else if (src.type == "perspective") {
      cam.yfov = float(src.perspective.yfov);
      cam.aspect = float(src.perspective.aspectRatio);
      cam.znear = float(src.perspective.znear);
    } else {
      fail(what + ": type \"" + src.type + "\" is neither perspective nor orthographic");
    }
    if (!cam.orthographic && !(cam.yfov > 0.f && cam.yfov < 3.14159f))
      fail(what + ": yfov " + str(cam.yfov) + " is not in (0, pi)");
    if (!(cam.aspect >= 0.f) || !std::isfinite(cam.aspect))
      fail(what + ": aspectRatio is not a finite number >= 0");
    if (!(cam.znear >= 0.f) || !std::isfinite(cam.znear))
      fail(what + ": znear is not a finite number >= 0");

    // Remove scale (and shear) with Gram-Schmidt, keeping the viewing axis (-Z) and then +Y.
    glm::vec3 z = unit_or(glm::vec3(world[2]), glm::vec3(0.f));
    glm::vec3 y =
        unit_or(glm::vec3(world[1]) - glm::dot(glm::vec3(world[1]), z) * z, glm::vec3(0.f));
    if (z == glm::vec3(0.f) || y == glm::vec3(0.f))
      fail("node " + str(node) + " gives " + what + " a degenerate transform (zero scale)");
    cam.to_world = glm::mat4(glm::vec4(glm::cross(y, z), 0.f), glm::vec4(y, 0.f), glm::vec4(z, 0.f),
                             glm::vec4(glm::vec3(world[3]), 1.f));
    scene_.cameras.push_back(cam);
  }

  // KHR_lights_punctual: {"extensions": {"KHR_lights_punctual": {"light": index}}} on a node.
  void add_light(const tinygltf::Node& node, const glm::mat4& world, int index) {
    auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end()) return;
    const std::string where = "node " + str(index);
    if (!ext->second.IsObject() || !ext->second.Has("light") ||
        !ext->second.Get("light").IsNumber())
      fail(where + ": KHR_lights_punctual has no light index");
    const double light = ext->second.Get("light").GetNumberAsDouble();
    if (!(light >= 0.0 && light < double(model_.lights.size())) || light != std::floor(light))
      fail(where + " refers to light " + std::to_string(light) + ", which does not exist (" +
           str(model_.lights.size()) + " lights)");
    const tinygltf::Light& src = model_.lights[size_t(light)];
    const std::string what = "light " + str(int(light));
    PunctualLight l;
    l.name = src.name;
    if (src.type == "point")
      l.type = PunctualLight::Type::point;
    else if (src.type == "spot")
      l.type = PunctualLight::Type::spot;
    else if (src.type == "directional")
      l.type = PunctualLight::Type::directional;
    else
      fail(what + ": type \"" + src.type + "\" is not point, spot or directional");
    glm::vec3 color(1.f);
    if (!src.color.empty()) {
      if (src.color.size() != 3) fail(what + ": color has " + str(src.color.size()) + " numbers");
      color = glm::vec3(src.color[0], src.color[1], src.color[2]);
    }
    if (!finite(color) || glm::any(glm::lessThan(color, glm::vec3(0.f))))
      fail(what + ": color is not 3 finite numbers >= 0");
    if (!(src.intensity >= 0.0) || !std::isfinite(src.intensity))
      fail(what + ": intensity is not a finite number >= 0");
    if (!(src.range >= 0.0) || !std::isfinite(src.range))
      fail(what + ": range is not a finite number > 0");
    l.intensity = color * float(src.intensity);
    l.range = float(src.range);
    if (l.type == PunctualLight::Type::spot) {
      const double inner = src.spot.innerConeAngle, outer = src.spot.outerConeAngle;
      if (!(inner >= 0.0 && inner < outer && outer <= 0.5 * M_PI))
        fail(what + ": spot cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2");
      l.cos_inner = float(std::cos(inner)), l.cos_outer = float(std::cos(outer));
    }
    l.position = glm::vec3(world[3]);
    l.direction = unit_or(-glm::vec3(world[2]), glm::vec3(0.f));
    if (l.direction == glm::vec3(0.f) && l.type != PunctualLight::Type::point)
      fail(where + " gives " + what + " a degenerate transform (zero scale)");
    scene_.lights.push_back(l);
  }

  const std::string& path_;
  const tinygltf::Model& model_;
  Scene scene_;
  const uint64_t available_memory_ = available_memory();
  std::vector<glm::vec3> normals_;  // per corner; kept once any primitive has NORMAL
  bool keep_normals_ = false;
  CornerStream<glm::vec2> texcoords_[2];
  CornerStream<glm::vec4> colors_, tangents_;
  std::vector<bool> texture_used_;  // by a material some primitive uses
  int default_material_ = -1;
  std::vector<bool> mesh_seen_;
  size_t skipped_modes_ = 0, skipped_unpositioned_ = 0;
};

}  // namespace

namespace {

// Runs `read` (which gives the model) and the loader, turning every failure into one Error line.
template <typename Read>
Scene load(const std::string& path, const GltfOptions& options, Read read) {
  try {
    std::vector<std::string> files;
    tinygltf::Model model = read(files);
    Scene scene = Loader(path, model).run(options.scene);
    scene.files = std::move(files);
    return scene;
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(path + ": out of memory while loading");
  } catch (const std::exception& e) {
    throw Error(path + ": cannot be loaded: " + one_line(e.what()));
  }
}

}  // namespace

Scene load_gltf(const std::string& path, const GltfOptions& options) {
  return load(path, options,
              [&](std::vector<std::string>& files) { return read_gltf_model(path, &files); });
}

Scene load_gltf_memory(const std::string& path, const unsigned char* data, size_t size,
                       const GltfOptions& options) {
  return load(path, options, [&](std::vector<std::string>& files) {
    return parse_gltf_model(path, data, size, &files);
  });
}

}  // namespace dacrt
