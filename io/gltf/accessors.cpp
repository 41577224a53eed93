// glTF accessors: every attribute, index and instance array is read through one validated strided
// view (bufferView and buffer bounds, strides, sparse patches, accessors without a bufferView),
// then converted to floats, vectors, quaternions or indices with the spec's normalisation.
#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>

#include "dacrt/io/gltf/internal.h"

namespace dacrt::gltf {
namespace {

static_assert(std::endian::native == std::endian::little, "glTF buffers are little-endian");

using Bytes = std::vector<unsigned char>;

// Accessors without a bufferView (all zeros, maybe sparse-patched) are never materialised, but
// what is read of them is: their size is not bounded by any buffer, so bound it here.
constexpr size_t kMaxSynthesisedBytes = size_t(1) << 30;

// a + b for messages, saturating instead of wrapping.
size_t sat_add(size_t a, size_t b) {
  return a > SIZE_MAX - b ? SIZE_MAX : a + b;
}

// What a View reads where an accessor has no bufferView: zeros (the largest element read is a
// FLOAT MAT4, 64 bytes).
constexpr unsigned char kZeros[64] = {};

// Sparse patches, in all accessors of a file, at most (each is kept, 16 bytes, for the load).
constexpr uint64_t kMaxSparseEntries = uint64_t(1) << 26;

// A validated strided window onto an accessor's elements: element i is the `components` values of
// `component_type` at data + i * stride, unless a sparse patch replaces it. Nothing is copied or
// materialised: reading k elements costs k, whatever the accessor's count.
struct View {
  const unsigned char* data = nullptr;
  size_t count = 0, stride = 0;
  int component_type = 0, components = 0;
  const std::vector<std::pair<uint32_t, const unsigned char*>>* patches = nullptr;

  const unsigned char* element(size_t i) const {
    if (patches) {
      auto after = std::upper_bound(patches->begin(), patches->end(), i,
                                    [](size_t e, const auto& p) { return e < p.first; });
      if (after != patches->begin() && std::prev(after)->first == i)
        return std::prev(after)->second;
    }
    return data + i * stride;
  }
};

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

// Component `c` of an element as the integer it is (KHR_mesh_quantization's unnormalized
// attributes), or as a float for FLOAT.
float plain_value(const unsigned char* element, int c, int type) {
  const unsigned char* p = element + size_t(c) * component_size(type);
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return float(*p);
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return float(int8_t(*p));
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t x;
      std::memcpy(&x, p, 2);
      return float(x);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t x;
      std::memcpy(&x, p, 2);
      return float(x);
    }
  }
  return component_value(element, c, type);
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

// `bytes` tightly packed bytes at `offset` in bufferView `view` (sparse indices and values).
const unsigned char* region(const Gltf& gltf, int view, int offset, size_t bytes,
                            const std::string& what) {
  Span span = buffer_view(gltf, view, what);
  if (offset < 0) gltf.fail(what + " has a negative byteOffset");
  if (size_t(offset) > span.size || bytes > span.size - size_t(offset))
    gltf.fail(what + " overruns bufferView " + str(view) + " (needs " +
              str(sat_add(size_t(offset), bytes)) + " bytes, has " + str(span.size) + ")");
  return span.data + offset;
}

// The sparse patches of accessor `index` (of `v.count` elements of `element` bytes), checked and
// sorted once for the whole load.
void apply_sparse(const Gltf& gltf, int index, const tinygltf::Accessor& a, View& v, size_t element,
                  const std::string& what) {
  if (auto known = gltf.sparse_patches.find(index); known != gltf.sparse_patches.end()) {
    v.patches = &known->second;
    return;
  }
  const auto& s = a.sparse;
  if (s.count < 0 || size_t(s.count) > v.count)
    gltf.fail(what + " has sparse count " + str(s.count) + ", outside [0, " + str(v.count) + "]");
  if (gltf.sparse_entries + uint64_t(s.count) > kMaxSparseEntries)
    gltf.fail(what + " brings the file's sparse accessors to more than " + str(kMaxSparseEntries) +
              " patched elements");
  size_t index_size = component_size(s.indices.componentType);
  if (!unsigned_index_type(s.indices.componentType))
    gltf.fail(what + " has sparse indices of componentType " + str(s.indices.componentType) +
              " (must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT)");
  size_t n = size_t(s.count);
  const unsigned char* indices = region(gltf, s.indices.bufferView, s.indices.byteOffset,
                                        n * index_size, "the sparse index array of " + what);
  const unsigned char* values = region(gltf, s.values.bufferView, s.values.byteOffset, n * element,
                                       "the sparse value array of " + what);
  std::vector<std::pair<uint32_t, const unsigned char*>> patches(n);
  for (size_t k = 0; k < n; ++k) {
    uint32_t i = read_uint(indices + k * index_size, index_size);
    if (i >= v.count)
      gltf.fail(what + " has sparse index " + str(i) + ", past its count " + str(v.count));
    patches[k] = {i, values + k * element};
  }
  // The spec wants the indices increasing; a repeated one is applied in order (the last wins).
  std::stable_sort(patches.begin(), patches.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  gltf.sparse_entries += n;
  v.patches = &(gltf.sparse_patches[index] = std::move(patches));
}

View view(const Gltf& gltf, int index, const std::string& role) {
  if (index < 0 || size_t(index) >= gltf.model.accessors.size())
    gltf.fail(role + " refers to accessor " + str(index) + ", which does not exist");
  const tinygltf::Accessor& a = gltf.model.accessors[size_t(index)];
  std::string what = "accessor " + str(index) + " (" + role + ")";
  View v;
  v.count = a.count;
  v.component_type = a.componentType;
  v.components = a.type == TINYGLTF_TYPE_SCALAR          ? 1
                 : a.type >= 2 && a.type <= 4                ? a.type
                 : a.type == TINYGLTF_TYPE_MAT4 && a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT
                     ? 16  // inverse bind matrices (FLOAT: no column padding)
                     : 0;
  size_t csize = component_size(a.componentType);
  if (csize == 0)
    gltf.fail(what + " has componentType " + str(a.componentType) +
              ", which glTF 2.0 does not allow");
  if (v.components == 0)
    gltf.fail(what + " has a matrix type other than FLOAT MAT4, which nothing reads");
  size_t element = csize * size_t(v.components);
  v.stride = element;

  const auto decoded = [&]() -> const Bytes* {
    std::lock_guard<std::mutex> lock(gltf.decoded_mutex);
    auto it = gltf.decoded_accessors.find(index);
    return it == gltf.decoded_accessors.end() ? nullptr : &it->second;
  }();
  if (decoded) {  // a Draco primitive's, laid out tightly (compression.cpp)
    if (decoded->size() != v.count * element)
      gltf.fail(what + " was decoded to " + str(decoded->size()) + " bytes, not " +
                str(v.count * element));
    v.data = decoded->data();
  } else if (a.bufferView != -1) {
    Span span = buffer_view(gltf, a.bufferView, what);
    if (span.stride != 0) {
      if (span.stride < element)
        gltf.fail(what + " has " + str(element) + "-byte elements but bufferView " +
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
      gltf.fail(what + " overruns bufferView " + str(a.bufferView) + " (needs " + str(needed) +
                " bytes, has " + str(span.size) + ")");
    v.data = span.data + (v.count > 0 ? a.byteOffset : 0);
  } else {
    // No bufferView: the spec says zeros (then patched by `sparse`). Nothing but the file's
    // word bounds the count: it is held to what a buffer could hold.
    size_t bytes = 0;
    bool overflows = __builtin_mul_overflow(v.count, element, &bytes);
    if (overflows || bytes > kMaxSynthesisedBytes)
      gltf.fail(what + " has no bufferView and count " + str(v.count) + ": it would need " +
                (overflows ? std::string("more than 2^64") : str(bytes)) + " bytes");
    v.data = kZeros;
    v.stride = 0;
  }
  if (a.sparse.isSparse) apply_sparse(gltf, index, a, v, element, what);
  return v;
}

// The k-th element a reader reads: k itself, or the k-th of those listed.
size_t element_index(const Gltf& gltf, const View& v, Elements which, size_t k,
                     const std::string& what) {
  if (!which) return k;
  const size_t i = (*which)[k];
  if (i >= v.count)
    gltf.fail(what + " has " + str(v.count) + " elements, not the " + str(i + 1) + " it needs");
  return i;
}

}  // namespace

size_t component_size(int type) {
  static constexpr size_t sizes[] = {1, 1, 2, 2, 0, 4, 4};  // BYTE ... FLOAT = 5120 ... 5126
  return type >= 5120 && type <= 5126 ? sizes[type - 5120] : 0;
}

size_t accessor_count(const Gltf& gltf, int accessor, const std::string& role) {
  return view(gltf, accessor, role).count;  // checked against its bufferView; nothing is read
}

Span buffer_view(const Gltf& gltf, int index, const std::string& user) {
  if (index < 0 || size_t(index) >= gltf.model.bufferViews.size())
    gltf.fail(user + " refers to bufferView " + str(index) + ", which does not exist");
  const tinygltf::BufferView& bv = gltf.model.bufferViews[size_t(index)];
  if (bv.extensions.count("EXT_meshopt_compression")) return meshopt_view(gltf, index);
  if (bv.buffer < 0 || size_t(bv.buffer) >= gltf.model.buffers.size())
    gltf.fail("bufferView " + str(index) + " refers to buffer " + str(bv.buffer) +
              ", which does not exist");
  const Bytes& buffer = gltf.model.buffers[size_t(bv.buffer)].data;
  if (buffer.empty() &&
      gltf.model.buffers[size_t(bv.buffer)].extensions.count("EXT_meshopt_compression"))
    gltf.fail("bufferView " + str(index) + " (of " + user + ") refers to buffer " + str(bv.buffer) +
              ", an EXT_meshopt_compression fallback whose data is not in the file, without "
              "compressed data of its own");
  if (bv.byteOffset > buffer.size() || bv.byteLength > buffer.size() - bv.byteOffset)
    gltf.fail("bufferView " + str(index) + " (of " + user + ") overruns buffer " + str(bv.buffer) +
              " (needs " + str(sat_add(bv.byteOffset, bv.byteLength)) + " bytes, has " +
              str(buffer.size()) + ")");
  return {buffer.data() + bv.byteOffset, bv.byteLength, bv.byteStride};
}

namespace {

// The bit of an integer componentType in IntegerTypes (0 for the others).
uint8_t type_bit(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return kByte;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return kUnsignedByte;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return kShort;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return kUnsignedShort;
  }
  return 0;
}

// "FLOAT, normalized BYTE, SHORT", for messages.
std::string type_names(IntegerTypes t) {
  std::string out = "FLOAT";
  const int types[] = {TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                       TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
  for (const auto& [bits, how] : {std::pair{t.normalized, "normalized "}, {t.plain, ""}}) {
    std::string list;
    for (int type : types)
      if (bits & type_bit(type)) list += (list.empty() ? how : ", ") + std::string(type_name(type));
    if (!list.empty()) out += ", " + list;
  }
  return out;
}

// Checks that accessor `accessor` (view v) has a type `integers` allows; true when its values are
// to be read as plain integers.
bool check_type(const Gltf& gltf, int accessor, const View& v, IntegerTypes integers,
                const std::string& what, const std::string& shape) {
  const int type = v.component_type;
  if (type == TINYGLTF_COMPONENT_TYPE_FLOAT) return false;
  const bool normalized = gltf.model.accessors[size_t(accessor)].normalized;
  if ((normalized ? integers.normalized : integers.plain) & type_bit(type)) return !normalized;
  if (((normalized ? integers.plain : integers.normalized) & type_bit(type)) != 0)
    gltf.fail(what + (normalized ? " must not be normalized (" : " must be normalized (") +
              type_name(type) + ")");
  gltf.fail(what + " must be " + type_names(integers) + " " + shape + " (it is " + type_name(type) +
            " with " + str(v.components) + " components)");
}

}  // namespace

std::vector<glm::quat> read_rotations(const Gltf& gltf, int accessor, const std::string& role) {
  std::vector<glm::vec4> q = read_floats(gltf, accessor, role, 4, 4, {kByte | kShort, 0}, 1.f);
  std::vector<glm::quat> out(q.size());
  for (size_t i = 0; i < q.size(); ++i) {
    const glm::quat rotation(q[i].w, q[i].x, q[i].y, q[i].z);  // glm: (w, x, y, z)
    const float len = glm::length(rotation);
    if (!(len > 0.f) || !std::isfinite(len))
      gltf.fail("accessor " + str(accessor) + " (" + role + ") element " + str(i) +
                " is not a rotation");
    out[i] = rotation / len;
  }
  return out;
}

std::vector<glm::vec4> read_floats(const Gltf& gltf, int accessor, const std::string& role,
                                   int min_components, int max_components, IntegerTypes integers,
                                   float fill, Elements which) {
  ++gltf.decodes;
  const View v = view(gltf, accessor, role);
  const int type = v.component_type;
  const std::string what = "accessor " + str(accessor) + " (" + role + ")";
  const std::string shape =
      "with " + str(min_components) +
      (max_components > min_components ? " to " + str(max_components) : std::string()) +
      " components";
  if (v.components < min_components || v.components > max_components)
    gltf.fail(what + " must be " + type_names(integers) + " " + shape + " (it is " +
              type_name(type) + " with " + str(v.components) + " components)");
  const bool plain = check_type(gltf, accessor, v, integers, what, shape);
  std::vector<glm::vec4> out(which ? which->size() : v.count, glm::vec4(fill));
  for (size_t k = 0; k < out.size(); ++k) {
    const unsigned char* e = v.element(element_index(gltf, v, which, k, what));
    for (int c = 0; c < v.components; ++c)
      out[k][c] = plain ? plain_value(e, c, type) : component_value(e, c, type);
  }
  return out;
}

std::vector<glm::vec3> read_vec3(const Gltf& gltf, int accessor, const std::string& role,
                                 Elements which, IntegerTypes integers) {
  ++gltf.decodes;
  const View v = view(gltf, accessor, role);
  const std::string what = "accessor " + str(accessor) + " (" + role + ")";
  const int type = v.component_type;
  if (v.components != 3)
    gltf.fail(what + " must be " + type_names(integers) + " VEC3 (it is " + type_name(type) +
              " with " + str(v.components) + " components)");
  const bool plain = check_type(gltf, accessor, v, integers, what, "VEC3");
  std::vector<glm::vec3> out(which ? which->size() : v.count);
  for (size_t k = 0; k < out.size(); ++k) {
    const unsigned char* e = v.element(element_index(gltf, v, which, k, what));
    if (type == TINYGLTF_COMPONENT_TYPE_FLOAT)
      std::memcpy(&out[k], e, sizeof(glm::vec3));
    else
      for (int c = 0; c < 3; ++c)
        out[k][c] = plain ? plain_value(e, c, type) : component_value(e, c, type);
  }
  return out;
}

std::vector<glm::vec4> read_matrix_columns(const Gltf& gltf, int accessor,
                                          const std::string& role) {
  ++gltf.decodes;
  const View v = view(gltf, accessor, role);
  if (v.components != 16 || v.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT)
    gltf.fail("accessor " + str(accessor) + " (" + role + ") must be FLOAT MAT4");
  std::vector<glm::vec4> out(4 * v.count);
  for (size_t k = 0; k < v.count; ++k) std::memcpy(&out[4 * k], v.element(k), 64);
  return out;
}

std::vector<uint32_t> read_indices(const Gltf& gltf, int accessor, const std::string& role,
                                   size_t vertex_count) {
  ++gltf.decodes;
  const View v = view(gltf, accessor, role);
  size_t size = component_size(v.component_type);
  if (v.components != 1 || !unsigned_index_type(v.component_type))
    gltf.fail("accessor " + str(accessor) + " (" + role +
              ") must be an UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT SCALAR");
  // The type's largest value is the primitive restart value, which the spec forbids.
  const uint64_t restart = (uint64_t(1) << (8 * size)) - 1;
  std::vector<uint32_t> indices(v.count);
  for (size_t k = 0; k < v.count; ++k) {
    indices[k] = read_uint(v.element(k), size);
    if (indices[k] == restart)
      gltf.fail("accessor " + str(accessor) + " (" + role + ") element " + str(k) + " is " +
                str(indices[k]) + ", the primitive restart value, which glTF forbids");
    if (indices[k] >= vertex_count)
      gltf.fail("accessor " + str(accessor) + " (" + role + ") element " + str(k) + " is index " +
                str(indices[k]) + ", past the vertex count " + str(vertex_count));
  }
  return indices;
}

}  // namespace dacrt::gltf
