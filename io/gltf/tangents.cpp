// Tangents for normal maps, generated where the file gives none, grouped and weighted as
// MikkTSpace does.
#include <algorithm>
#include <cstring>
#include <limits>
#include <unordered_map>

#include "dacrt/io/gltf/internal.h"

namespace dacrt::gltf {

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

}  // namespace dacrt::gltf
