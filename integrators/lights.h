// LightSampler: next-event estimation's choice of emitter. Emissive triangles and punctual lights
// (KHR_lights_punctual) have a power: π × luminance of the emitted radiance × area × sides for a
// triangle (with an emissive texture, the radiance is averaged over a few points of the
// triangle, so dark texels get few samples), 4π I for a point light, the cone's solid angle × I
// for a spot, and the irradiance over the scene's bounding disk for a directional light. Then a
// point is picked uniformly on a triangle. pmf() answers for any triangle, so MIS can weigh
// emitters found by BSDF sampling; punctual lights are deltas that only next-event estimation
// can reach.
//
// The choice is made one of two ways (LightPicking), both exact: pmf() is the probability of the
// choice, a multiple of 2⁻²⁴, whatever the number of emitters or the spread of their powers.
// - By power alone, through an alias table (util/alias_table.h), the same from every point.
// - By a light tree (integrators/light_tree.h) over the triangles, point and spot lights, by
//   what each may send to the shading point (LightContext); directional lights, which light
//   every point alike, take their share of power beside the tree. With many emitters most are
//   far or turned away from any one point, and the tree spends few shadow rays on them.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "dacrt/integrators/light_tree.h"
#include "dacrt/scene/scene.h"
#include "dacrt/util/alias_table.h"

namespace dacrt {

class LightSampler {
 public:
  // automatic picks by the tree from this many emitters on (triangles and punctual lights). On
  // a floor under n lamps of two triangles each, spread over 40 m (tools/make_many_lights.py),
  // the eight-wide tree's noise² at equal time was 0.38x the alias table's for n = 4 (within
  // the noise), 0.02x for 16, 0.10x for 64, 0.37x for 256 and 0.18–0.30x for 4000
  // (docs/benchmarks.md, "Many lights"). Below, a lamp or three (the Cornell box's two
  // triangles) keep the alias table and their images.
  static constexpr size_t tree_threshold = 8;

  // The scene's emissive triangles and `lights` (a render's: Shot::lights).
  LightSampler(const Scene& scene, std::span<const PunctualLight> lights,
               LightPicking picking = LightPicking::automatic);

  bool empty() const { return table_.empty(); }
  bool tree() const { return !tree_.empty(); }
  int tree_depth() const { return tree_.depth(); }
  size_t triangles() const { return triangles_.size(); }
  // The emitters: the triangles (triangle(entry)), then the punctual lights given, in order.
  size_t entries() const { return entries_; }
  uint32_t triangle(size_t entry) const { return triangles_[entry]; }

  struct Sample {
    int light;              // index into the lights given, or -1 for an emissive triangle
    uint32_t triangle;      // the emissive triangle, when light is -1
    glm::vec3 point;        // on the triangle
    glm::vec2 barycentric;  // of the point: (1 − x − y)·p0 + x·p1 + y·p2
    float pmf;              // probability of having picked this emitter
  };
  // u picks the emitter (from `at`, for the tree), (u1, u2) the point on a triangle.
  Sample sample(float u, float u1, float u2, const LightContext& at) const;
  // The entry u picks from `at` (sample's choice), and its probability.
  struct Choice {
    size_t entry;
    float pmf;
  };
  Choice pick(float u, const LightContext& at) const;
  // The probability that pick() chooses `entry` from `at`.
  float entry_pmf(size_t entry, const LightContext& at) const;

  // What next-event estimation asks of a sampled triangle, made once: its unit normal (front
  // side), area, and the ball around it (centre, squared radius out to its farthest corner).
  struct Emitter {
    glm::vec3 normal, centre;
    float radius2, pmf;  // pmf: by power (the alias table's), 0 with the tree
    double area;
  };
  // Triangle tri's, or null for triangles that are never sampled (they do not emit, or emit
  // nothing: zero area or black).
  const Emitter* emitter(uint32_t tri) const {
    if (index_by_triangle_.empty() || index_by_triangle_[tri] == none) return nullptr;
    return &emitters_[index_by_triangle_[tri]];
  }
  // Probability of picking triangle `tri` from `at` (0 for triangles that are never sampled).
  float pmf(uint32_t tri, const LightContext& at) const {
    const Emitter* e = emitter(tri);
    if (!e) return 0.f;
    return tree_.empty() ? e->pmf : entry_pmf(index_by_triangle_[tri], at);
  }

 private:
  static constexpr uint32_t none = ~0u;
  const Scene& scene_;
  std::vector<uint32_t> triangles_;  // emissive triangles; the entries are they, then the lights
  size_t entries_ = 0;
  AliasTable table_;  // by power: all entries, or (with the tree) the tree then directional lights
  // With the tree: its entries (the sampler's entry of each leaf) and back (none for directional
  // lights); the units of 2²⁴ the tree has, then the directional lights', summed in order.
  LightTree tree_;
  std::vector<uint32_t> tree_entry_, entry_in_tree_;
  std::vector<uint32_t> directional_, directional_units_;  // entries, and their cumulative units
  uint32_t tree_units_ = 0;
  std::vector<Emitter> emitters_;            // of triangles_, in its order
  std::vector<uint32_t> index_by_triangle_;  // into emitters_, or none
};

}  // namespace dacrt
