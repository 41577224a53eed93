// Compressed glTF geometry, each through the library made for it: EXT_meshopt_compression
// bufferViews through meshoptimizer, KHR_draco_mesh_compression primitives through Draco. Both
// decode into bytes laid out as the file's bufferViews and accessors say, kept for the load, so
// the readers of accessors.cpp see ordinary data. Every size is checked before it is allocated:
// what one file may decode in all is bounded (kMaxDecodedBytes), and so are meshoptimizer's
// parameters, whose limits it only asserts.
#include <draco/compression/decode.h>
#include <meshoptimizer.h>

#include <cmath>
#include <cstring>

#include "dacrt/io/gltf/internal.h"

namespace dacrt::gltf {
namespace {

// All bufferViews and accessors a file decodes, together.
constexpr uint64_t kMaxDecodedBytes = uint64_t(2) << 30;

using Bytes = std::vector<unsigned char>;

// Reserves `bytes` of the file's decoding budget (under gltf.decoded_mutex).
void reserve(const Gltf& gltf, uint64_t bytes, const std::string& what) {
  if (bytes > kMaxDecodedBytes - gltf.decoded_bytes)
    gltf.fail(what + " decodes to " + str(bytes) + " bytes, which with the " +
              str(gltf.decoded_bytes) + " decoded before is more than the " +
              str(kMaxDecodedBytes) + " a file may decode");
  gltf.decoded_bytes += bytes;
}

// An integer member of an extension object: a whole number in [lo, hi], or `fallback` when absent
// (nullopt: required).
uint64_t member(const Gltf& gltf, const tinygltf::Value& x, const char* key, uint64_t lo,
                uint64_t hi, std::optional<uint64_t> fallback, const std::string& what) {
  if (!x.Has(key)) {
    if (!fallback) gltf.fail(what + " has no " + key);
    return *fallback;
  }
  const tinygltf::Value& v = x.Get(key);
  const double d = v.IsNumber() ? v.GetNumberAsDouble() : NAN;
  if (!(d >= double(lo) && d <= double(hi)) || d != std::floor(d))
    gltf.fail(what + "'s " + key + " must be a whole number in [" + str(lo) + ", " + str(hi) + "]");
  return uint64_t(d);
}

std::string text_member(const Gltf& gltf, const tinygltf::Value& x, const char* key,
                        const char* fallback, const std::string& what) {
  if (!x.Has(key)) return fallback;
  const tinygltf::Value& v = x.Get(key);
  if (!v.IsString()) gltf.fail(what + "'s " + key + " must be a string");
  return v.Get<std::string>();
}

// Decodes bufferView `index`'s EXT_meshopt_compression object `x` into `out`.
void decode_meshopt(const Gltf& gltf, int index, const tinygltf::Value& x, Bytes& out) {
  const std::string what = "bufferView " + str(index) + "'s EXT_meshopt_compression";
  if (!x.IsObject()) gltf.fail(what + " is not an object");
  const uint64_t buffer = member(gltf, x, "buffer", 0, gltf.model.buffers.size() - 1, {}, what);
  const uint64_t offset = member(gltf, x, "byteOffset", 0, uint64_t(1) << 53, 0, what);
  const uint64_t length = member(gltf, x, "byteLength", 1, uint64_t(1) << 53, {}, what);
  const uint64_t stride = member(gltf, x, "byteStride", 1, 256, {}, what);
  const uint64_t count = member(gltf, x, "count", 1, uint64_t(1) << 53, {}, what);
  const std::string mode = text_member(gltf, x, "mode", "", what);
  const std::string filter = text_member(gltf, x, "filter", "NONE", what);
  // The limits meshoptimizer asserts, checked here.
  if (mode == "ATTRIBUTES") {
    if (stride % 4 != 0) gltf.fail(what + ": ATTRIBUTES need a byteStride divisible by 4");
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4) gltf.fail(what + ": " + mode + " need a byteStride of 2 or 4");
    if (mode == "TRIANGLES" && count % 3 != 0)
      gltf.fail(what + ": TRIANGLES need a count divisible by 3");
  } else {
    gltf.fail(what + " has mode \"" + one_line(mode.substr(0, 40)) +
              "\" (ATTRIBUTES, TRIANGLES or INDICES)");
  }
  if (filter != "NONE") {
    if (mode != "ATTRIBUTES") gltf.fail(what + ": filters apply to ATTRIBUTES only");
    if (filter == "OCTAHEDRAL"    ? stride != 4 && stride != 8
        : filter == "QUATERNION"  ? stride != 8
        : filter == "EXPONENTIAL" ? false
                                  : true)
      gltf.fail(what + " has filter \"" + one_line(filter.substr(0, 40)) + "\" with byteStride " +
                str(stride) + " (OCTAHEDRAL: 4 or 8, QUATERNION: 8, EXPONENTIAL: any)");
  }
  const tinygltf::BufferView& bv = gltf.model.bufferViews[size_t(index)];
  const uint64_t bytes = count * stride;  // count ≤ 2^53, stride ≤ 256: no overflow
  if (bytes > bv.byteLength)
    gltf.fail(what + " decodes to " + str(bytes) +
              " bytes, more than the bufferView's byteLength " + str(bv.byteLength));
  const Bytes& source = gltf.model.buffers[size_t(buffer)].data;
  if (offset > source.size() || length > source.size() - offset)
    gltf.fail(what + " overruns buffer " + str(buffer) + " (needs " + str(offset + length) +
              " bytes, has " + str(source.size()) + ")");
  // The stream's length bounds what it can decode to, so a short stream claiming a large count
  // is refused before the output is allocated. The least a stream can spend (meshoptimizer 0.18's
  // codecs, version 0): ATTRIBUTES 2 bits of group header for 16 bytes of one byte column (1/64
  // of the data); TRIANGLES one code byte for a triangle of 3 indices; INDICES one varint byte an
  // index.
  const uint64_t ratio = mode == "ATTRIBUTES" ? 64 : mode == "TRIANGLES" ? 3 * stride : stride;
  if (bytes / ratio > length)
    gltf.fail(what + " claims " + str(count) + " elements of " + str(stride) + " bytes (" +
              str(bytes) + " bytes), more than its " + str(length) +
              "-byte stream can decode to");
  reserve(gltf, bytes, what);
  out.assign(size_t(bytes), 0);
  const unsigned char* in = source.data() + offset;
  const int failed =
      mode == "ATTRIBUTES"  ? meshopt_decodeVertexBuffer(out.data(), count, stride, in, length)
      : mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out.data(), count, stride, in, length)
                            : meshopt_decodeIndexSequence(out.data(), count, stride, in, length);
  if (failed)
    gltf.fail(what + ": the compressed data is malformed (meshoptimizer error " + str(failed) +
              ")");
  if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out.data(), count, stride);
  if (filter == "QUATERNION") meshopt_decodeFilterQuat(out.data(), count, stride);
  if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data(), count, stride);
}

// Draco attribute `att`'s values for every point, as accessor `a` lays them out (tightly).
template <class T>
void convert(const draco::Mesh& mesh, const draco::PointAttribute& att, int components,
             Bytes& out) {
  T value[4] = {};
  for (draco::PointIndex p(0); p < mesh.num_points(); ++p) {
    att.ConvertValue<T>(att.mapped_index(p), int8_t(components), value);
    std::memcpy(out.data() + size_t(p.value()) * sizeof(T) * size_t(components), value,
                sizeof(T) * size_t(components));
  }
}

}  // namespace

Span meshopt_view(const Gltf& gltf, int index) {
  std::lock_guard<std::mutex> lock(gltf.decoded_mutex);
  auto known = gltf.decoded_views.find(index);
  if (known == gltf.decoded_views.end()) {
    Bytes out;
    const tinygltf::BufferView& bv = gltf.model.bufferViews[size_t(index)];
    decode_meshopt(gltf, index, bv.extensions.at("EXT_meshopt_compression"), out);
    ++gltf.decodes;
    known = gltf.decoded_views.emplace(index, std::move(out)).first;
  }
  const tinygltf::BufferView& bv = gltf.model.bufferViews[size_t(index)];
  return {known->second.data(), known->second.size(), bv.byteStride};
}

void decode_draco(const Gltf& gltf, const tinygltf::Primitive& prim, const std::string& where) {
  const std::string what = where + "'s KHR_draco_mesh_compression";
  const tinygltf::Value& x = prim.extensions.at("KHR_draco_mesh_compression");
  if (!x.IsObject()) gltf.fail(what + " is not an object");
  if (prim.mode != TINYGLTF_MODE_TRIANGLES)
    gltf.fail(what + ": only TRIANGLES primitives are read compressed (mode " + str(prim.mode) +
              ")");
  const int view =
      int(member(gltf, x, "bufferView", 0,
                 gltf.model.bufferViews.empty() ? 0 : gltf.model.bufferViews.size() - 1, {}, what));
  if (!x.Has("attributes") || !x.Get("attributes").IsObject())
    gltf.fail(what + " has no attributes object");
  const tinygltf::Value& attributes = x.Get("attributes");
  {
    std::lock_guard<std::mutex> lock(gltf.decoded_mutex);
    if (gltf.decoded_primitives.count(&prim)) return;  // another instance decoded it
  }
  const Span data = buffer_view(gltf, view, what);
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(data.data), data.size);
  ++gltf.decodes;
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok())
    gltf.fail(what + ": the Draco data cannot be decoded (" +
              one_line(decoded.status().error_msg_string().substr(0, 200)) + ")");
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  const uint64_t points = mesh->num_points(), faces = mesh->num_faces();

  std::map<int, Bytes> accessors;    // decoded, by accessor
  auto take = [&](uint64_t bytes) {  // before each allocation
    std::lock_guard<std::mutex> lock(gltf.decoded_mutex);
    reserve(gltf, bytes, what);
  };
  auto accessor = [&](int index, const std::string& role) -> const tinygltf::Accessor& {
    if (index < 0 || size_t(index) >= gltf.model.accessors.size())
      gltf.fail(what + ": " + role + " refers to accessor " + str(index) +
                ", which does not exist");
    return gltf.model.accessors[size_t(index)];
  };
  if (prim.indices != -1) {
    const tinygltf::Accessor& a = accessor(prim.indices, "indices");
    const size_t size = component_size(a.componentType);
    if (a.type != TINYGLTF_TYPE_SCALAR || size == 0 ||
        a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
        a.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
        a.componentType == TINYGLTF_COMPONENT_TYPE_SHORT)
      gltf.fail(what + ": accessor " + str(prim.indices) +
                " (indices) must be an UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT SCALAR");
    if (a.count != 3 * faces)
      gltf.fail(what + ": accessor " + str(prim.indices) + " (indices) has count " + str(a.count) +
                ", the Draco mesh " + str(3 * faces) + " indices");
    const uint64_t most = size == 1 ? 0xff : size == 2 ? 0xffff : 0xffffffff;
    if (points > 0 && points - 1 > most)
      gltf.fail(what + ": " + str(points) + " vertices do not fit accessor " + str(prim.indices) +
                "'s index type");
    take(a.count * size);
    Bytes out(size_t(a.count) * size);
    for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f)
      for (int k = 0; k < 3; ++k) {
        const uint32_t i = mesh->face(f)[k].value();
        std::memcpy(out.data() + (size_t(f.value()) * 3 + size_t(k)) * size, &i, size);
      }
    accessors[prim.indices] = std::move(out);
  } else if (points != 3 * faces) {
    gltf.fail(what + ": the primitive has no indices but the Draco mesh has " + str(points) +
              " vertices for " + str(faces) + " triangles");
  }
  for (const std::string& name : attributes.Keys()) {
    auto it = prim.attributes.find(name);
    if (it == prim.attributes.end())
      gltf.fail(what + ": attribute " + one_line(name.substr(0, 40)) +
                " is not an attribute of the primitive");
    const uint64_t id = member(gltf, attributes, name.c_str(), 0, UINT32_MAX, {}, what);
    const draco::PointAttribute* att = mesh->GetAttributeByUniqueId(uint32_t(id));
    if (!att)
      gltf.fail(what + ": the Draco mesh has no attribute " + str(id) + " (for " +
                one_line(name.substr(0, 40)) + ")");
    const tinygltf::Accessor& a = accessor(it->second, name);
    const int components = a.type == TINYGLTF_TYPE_SCALAR ? 1 : a.type;
    const size_t size = component_size(a.componentType);
    if (size == 0 || components < 1 || components > 4)
      gltf.fail(what + ": accessor " + str(it->second) + " (" + one_line(name.substr(0, 40)) +
                ") is not a vector of up to 4 components");
    if (a.count != points)
      gltf.fail(what + ": accessor " + str(it->second) + " (" + one_line(name.substr(0, 40)) +
                ") has count " + str(a.count) + ", the Draco mesh " + str(points) + " vertices");
    take(points * size * uint64_t(components));
    Bytes out(size_t(points) * size * size_t(components));
    switch (a.componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        convert<float>(*mesh, *att, components, out);
        break;
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        convert<int8_t>(*mesh, *att, components, out);
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        convert<uint8_t>(*mesh, *att, components, out);
        break;
      case TINYGLTF_COMPONENT_TYPE_SHORT:
        convert<int16_t>(*mesh, *att, components, out);
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        convert<uint16_t>(*mesh, *att, components, out);
        break;
      default:
        convert<uint32_t>(*mesh, *att, components, out);
        break;
    }
    accessors[it->second] = std::move(out);
  }
  std::lock_guard<std::mutex> lock(gltf.decoded_mutex);
  for (auto& [index, out] : accessors) gltf.decoded_accessors[index] = std::move(out);
  gltf.decoded_primitives.insert(&prim);
}

}  // namespace dacrt::gltf
