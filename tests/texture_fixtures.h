// What the texture tests share: a 2 × 2 RGBA image (kTexels), a unit quad glTF file that samples
// it (quad_file, add_texture), the quad's surface at a point, and the error decode_image gives for
// some bytes, as a string.
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <glm/glm.hpp>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gltf_writer.h"
#include "dacrt/io/texture_decode.h"
#include "dacrt/materials/texture.h"
#include "dacrt/scene/surface.h"
#include "png.h"
#include "dacrt/util/error.h"

namespace dacrt::test {

inline bool near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) {
  return glm::all(glm::lessThanEqual(glm::abs(a - b), glm::vec3(eps)));
}

// 2 × 2 RGBA: red, half-transparent green / blue, grey 188 (sRGB 188 is linear 0.5029).
inline const std::vector<uint8_t> kTexels = {255, 0, 0,   255, 0,   255, 0,   128,
                                             0,   0, 255, 255, 188, 188, 188, 255};
inline const float kGrey = srgb_to_linear(188.f / 255.f);

// A unit quad in z = 0 facing +z, triangles (0, 1, 2) and (0, 2, 3) over the corners (0, 0),
// (1, 0), (1, 1), (0, 1), with TEXCOORD_0 = (x, 1 − y) (the image upright) and material 0.
// `attributes` adds or replaces attributes.
inline GltfWriter quad_file(const nlohmann::json& material,
                            nlohmann::json attributes = nlohmann::json::object()) {
  GltfWriter w;
  const std::vector<glm::vec3> corners = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<glm::vec2> uv = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  nlohmann::json attr = {
      {"POSITION", w.add_vec3(corners)},
      {"TEXCOORD_0", w.add_accessor(w.add_view(uv.data(), 32), kFloat, 4, "VEC2")}};
  attr.update(attributes);
  w.add_material(material);
  int indices = w.add_indices(std::vector<uint8_t>{0, 1, 2, 0, 2, 3});
  int mesh = w.add_mesh({{"attributes", attr}, {"indices", indices}, {"material", 0}});
  w.set_scene({w.add_node({{"mesh", mesh}})});
  return w;
}

enum class Embed { data_uri, buffer_view, file };

// Adds `bytes` as an image of MIME type `mime` (`image/png`, `image/webp`...: the data URI's
// type, the bufferView's mimeType, the file's extension); returns the image index.
inline int add_image(GltfWriter& w, const std::vector<unsigned char>& bytes,
                     Embed embed = Embed::data_uri, const std::string& dir = "",
                     const std::string& mime = "image/png") {
  nlohmann::json image;
  if (embed == Embed::data_uri) {
    image = {{"uri", "data:" + mime + ";base64," + base64(bytes)}};
  } else if (embed == Embed::buffer_view) {
    image = {{"bufferView", w.add_view(bytes.data(), bytes.size())}, {"mimeType", mime}};
  } else {
    const std::string name =
        "image" + std::to_string(w.doc["images"].size()) + "." + mime.substr(mime.find('/') + 1);
    write_bytes(dir + "/" + name, bytes.data(), bytes.size());
    image = {{"uri", name}};
  }
  w.doc["images"].push_back(image);
  return int(w.doc["images"].size()) - 1;
}

// Adds `png` as image + texture (with `sampler` unless null); returns the texture index.
inline int add_texture(GltfWriter& w, const std::vector<unsigned char>& png,
                       nlohmann::json sampler = nullptr, Embed embed = Embed::data_uri,
                       const std::string& dir = "") {
  nlohmann::json texture = {{"source", add_image(w, png, embed, dir)}};
  if (!sampler.is_null()) {
    w.doc["samplers"].push_back(sampler);
    texture["sampler"] = w.doc["samplers"].size() - 1;
  }
  w.doc["textures"].push_back(texture);
  return int(w.doc["textures"].size()) - 1;
}

inline const nlohmann::json kNearest = {{"magFilter", 9728}, {"minFilter", 9728}};

// The point (x, y) of the quad: its triangle and barycentrics there.
struct QuadPoint {
  uint32_t tri;
  float u, v;
};
inline QuadPoint quad_point(const Scene& scene, float x, float y) {
  REQUIRE(scene.geometry.size() == 2);
  return x >= y ? QuadPoint{0, x - y, y} : QuadPoint{1, x, y - x};
}

// The surface of the quad at (x, y).
inline SurfacePoint quad_surface(const Scene& scene, float x, float y) {
  const QuadPoint p = quad_point(scene, x, y);
  return surface_at(scene, p.tri, p.u, p.v, glm::vec3(0, 0, 1));
}

// The start of a KTX 2.0 file (KHR_texture_basisu's images): its identifier, then zeros.
inline std::vector<unsigned char> ktx2() {
  static const unsigned char identifier[12] = {0xab, 'K',  'T',  'X',  ' ',  '2',
                                               '0',  0xbb, '\r', '\n', 0x1a, '\n'};
  std::vector<unsigned char> out(80, 0);
  std::copy(std::begin(identifier), std::end(identifier), out.begin());
  return out;
}

// The error decode_image throws for `bytes`, or "no error".
inline std::string decode_error(const std::vector<unsigned char>& bytes) {
  try {
    decode_image(bytes.data(), bytes.size(), "x.png");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

inline bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

inline std::vector<unsigned char> bytes_of(const std::string& s) {
  return {s.begin(), s.end()};
}

}  // namespace dacrt::test
