// GltfWriter: builds tiny glTF 2.0 files for tests. Vertex data goes into one binary buffer; the
// JSON is an nlohmann::json that a test may edit (to break it on purpose) before writing it as
// .gltf (buffer as a base64 data URI or a .bin side file) or as .glb (written by hand: header,
// JSON chunk padded with spaces, BIN chunk padded with zeros).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "temp_dir.h"

namespace dacrt::test {

constexpr int kUnsignedByte = 5121, kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;

inline std::string base64(const std::vector<unsigned char>& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t n = uint32_t(bytes[i]) << 16;
    if (i + 1 < bytes.size()) n |= uint32_t(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) n |= bytes[i + 2];
    out += digits[(n >> 18) & 63];
    out += digits[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? digits[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? digits[n & 63] : '=';
  }
  return out;
}

inline void write_bytes(const std::string& path, const void* data, size_t size) {
  std::ofstream out(path, std::ios::binary);
  out.write(static_cast<const char*>(data), std::streamsize(size));
}

inline void write_text(const std::string& path, const std::string& text) {
  write_bytes(path, text.data(), text.size());
}

struct GltfWriter {
  nlohmann::json doc = {{"asset", {{"version", "2.0"}}}};
  std::vector<unsigned char> bin;
  std::vector<nlohmann::json> more_buffers;  // after buffer 0 (bin), as they are

  // Appends `size` bytes (4-byte aligned) as a new bufferView of buffer 0; returns its index.
  int add_view(const void* data, size_t size, int stride = 0) {
    while (bin.size() % 4) bin.push_back(0);
    nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", size}};
    if (stride) view["byteStride"] = stride;
    const auto* bytes = static_cast<const unsigned char*>(data);
    bin.insert(bin.end(), bytes, bytes + size);
    return push("bufferViews", view);
  }

  int add_accessor(int view, int component_type, size_t count, const std::string& type,
                   size_t byte_offset = 0) {
    nlohmann::json a = {{"componentType", component_type}, {"count", count}, {"type", type}};
    if (view >= 0) a["bufferView"] = view;
    if (byte_offset) a["byteOffset"] = byte_offset;
    return push("accessors", a);
  }

  // FLOAT VEC3 (POSITION or NORMAL); POSITION gets the min/max the spec asks for.
  int add_vec3(const std::vector<glm::vec3>& v, bool with_bounds = true) {
    int a =
        add_accessor(add_view(v.data(), v.size() * sizeof(glm::vec3)), kFloat, v.size(), "VEC3");
    if (with_bounds && !v.empty()) {
      glm::vec3 lo = v[0], hi = v[0];
      for (const glm::vec3& p : v) lo = glm::min(lo, p), hi = glm::max(hi, p);
      doc["accessors"][a]["min"] = {lo.x, lo.y, lo.z};
      doc["accessors"][a]["max"] = {hi.x, hi.y, hi.z};
    }
    return a;
  }

  // Indices as uint8_t, uint16_t or uint32_t: the component type follows T.
  template <class T>
  int add_indices(const std::vector<T>& indices) {
    int type = sizeof(T) == 1 ? kUnsignedByte : sizeof(T) == 2 ? kUnsignedShort : kUnsignedInt;
    return add_accessor(add_view(indices.data(), indices.size() * sizeof(T)), type, indices.size(),
                        "SCALAR");
  }

  // {"attributes": {"POSITION": ...}} plus `extra` members (indices, material, mode, ...).
  static nlohmann::json primitive(int position, nlohmann::json extra = nlohmann::json::object()) {
    nlohmann::json p = {{"attributes", {{"POSITION", position}}}};
    p.update(extra);
    return p;
  }

  int add_mesh(const nlohmann::json& primitives) {
    return push(
        "meshes",
        {{"primitives", primitives.is_array() ? primitives : nlohmann::json::array({primitives})}});
  }
  int add_node(const nlohmann::json& node) { return push("nodes", node); }
  int add_material(const nlohmann::json& material) { return push("materials", material); }
  void set_scene(const std::vector<int>& roots) {
    doc["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }

  // The common case: one mesh of one primitive, instanced by one root node. Returns the node.
  int add_triangles(const std::vector<glm::vec3>& positions,
                    nlohmann::json extra = nlohmann::json::object()) {
    int node = add_node({{"mesh", add_mesh(primitive(add_vec3(positions), extra))}});
    set_scene({node});
    return node;
  }

  // Writes .gltf with the buffer as a data URI (embed) or as `<stem>.bin` next to it.
  std::string write_gltf(const std::string& path, bool embed = true) {
    nlohmann::json out = doc;
    if (!bin.empty()) {
      std::string uri = "data:application/octet-stream;base64," + base64(bin);
      if (!embed) {
        uri = std::filesystem::path(path).stem().string() + ".bin";
        write_bytes((std::filesystem::path(path).parent_path() / uri).string(), bin.data(),
                    bin.size());
      }
      out["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}, {"uri", uri}}});
    }
    for (const nlohmann::json& b : more_buffers) out["buffers"].push_back(b);
    write_text(path, out.dump(1));
    return path;
  }

  std::string write_glb(const std::string& path) {
    nlohmann::json out = doc;
    if (!bin.empty()) out["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}}});
    for (const nlohmann::json& b : more_buffers) out["buffers"].push_back(b);
    std::string json = out.dump();
    while (json.size() % 4) json += ' ';
    std::vector<unsigned char> chunk = bin;
    while (chunk.size() % 4) chunk.push_back(0);
    std::vector<unsigned char> glb;
    auto u32 = [&](uint32_t v) {
      for (int i = 0; i < 4; ++i) glb.push_back((v >> (8 * i)) & 0xff);
    };
    uint32_t length =
        12 + 8 + uint32_t(json.size()) + (chunk.empty() ? 0 : 8 + uint32_t(chunk.size()));
    u32(0x46546C67);  // "glTF"
    u32(2);
    u32(length);
    u32(uint32_t(json.size()));
    u32(0x4E4F534A);  // "JSON"
    glb.insert(glb.end(), json.begin(), json.end());
    if (!chunk.empty()) {
      u32(uint32_t(chunk.size()));
      u32(0x004E4942);  // "BIN\0"
      glb.insert(glb.end(), chunk.begin(), chunk.end());
    }
    write_bytes(path, glb.data(), glb.size());
    return path;
  }

 private:
  int push(const char* array, const nlohmann::json& value) {
    doc[array].push_back(value);
    return int(doc[array].size()) - 1;
  }
};

}  // namespace dacrt::test
