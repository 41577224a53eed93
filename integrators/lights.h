// LightSampler: next-event estimation's choice of emitter. Emissive triangles and punctual lights
// (KHR_lights_punctual) are picked in proportion to their power: π × luminance of the emitted
// radiance × area × sides for a triangle (then a point uniformly on it; with an emissive texture,
// the radiance is averaged over a few points of the triangle, so dark texels get few samples), 4π I
// for a point light, the cone's solid angle × I for a spot, and the irradiance over the scene's
// bounding disk for a directional light. pmf() answers for any triangle, so MIS can weigh emitters
// found by BSDF sampling; punctual lights are deltas that only next-event estimation can reach.
// The choice goes through an alias table (util/alias_table.h), so pmf() is exactly the
// probability of the choice, whatever the number of emitters or the spread of their powers.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "dacrt/scene/scene.h"
#include "dacrt/util/alias_table.h"

namespace dacrt {

class LightSampler {
 public:
  // The scene's emissive triangles and `lights` (a render's: Shot::lights).
  LightSampler(const Scene& scene, std::span<const PunctualLight> lights);

  bool empty() const { return table_.empty(); }
  size_t triangles() const { return triangles_.size(); }

  struct Sample {
    int light;              // index into the lights given, or -1 for an emissive triangle
    uint32_t triangle;      // the emissive triangle, when light is -1
    glm::vec3 point;        // on the triangle
    glm::vec2 barycentric;  // of the point: (1 − x − y)·p0 + x·p1 + y·p2
    float pmf;              // probability of having picked this emitter
  };
  // u picks the emitter, (u1, u2) the point on a triangle.
  Sample sample(float u, float u1, float u2) const;
  // The entry u picks (sample's choice): an index into triangles(), or past them a punctual light.
  size_t pick(float u) const { return table_.sample(u); }
  size_t entries() const { return table_.size(); }
  uint32_t triangle(size_t entry) const { return triangles_[entry]; }
  // What next-event estimation asks of a sampled triangle, made once: its unit normal (front
  // side), area, and the ball around it (centre, squared radius out to its farthest corner).
  struct Emitter {
    glm::vec3 normal, centre;
    float radius2, pmf;
    double area;
  };
  // Triangle tri's, or null for triangles that are never sampled (they do not emit, or emit
  // nothing: zero area or black).
  const Emitter* emitter(uint32_t tri) const {
    if (index_by_triangle_.empty() || index_by_triangle_[tri] == none) return nullptr;
    return &emitters_[index_by_triangle_[tri]];
  }
  // Probability of picking triangle `tri` (0 for triangles that are never sampled).
  float pmf(uint32_t tri) const {
    const Emitter* e = emitter(tri);
    return e ? e->pmf : 0.f;
  }

 private:
  static constexpr uint32_t none = ~0u;
  const Scene& scene_;
  std::vector<uint32_t> triangles_;  // emissive triangles; table_ has them, then the lights
  AliasTable table_;
  std::vector<Emitter> emitters_;            // of triangles_, in its order
  std::vector<uint32_t> index_by_triangle_;  // into emitters_, or none
};

}  // namespace dacrt
