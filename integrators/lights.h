// LightSampler: next-event estimation's choice of emitter. Emissive triangles are picked in
// proportion to their power (luminance of emitted radiance × area × sides), then a point uniformly
// on the triangle; pdf() answers for any triangle, so MIS can weigh hits found by BSDF sampling.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "scene/scene.h"

namespace dacrt {

class LightSampler {
 public:
  explicit LightSampler(const Scene& scene);

  bool empty() const { return triangles_.empty(); }
  size_t size() const { return triangles_.size(); }

  struct Sample {
    uint32_t triangle;
    glm::vec3 point;
    float pmf;  // probability of having picked this triangle
  };
  // u picks the triangle, (u1, u2) the point on it.
  Sample sample(float u, float u1, float u2) const;
  // Probability of picking triangle `tri` (0 for triangles that do not emit).
  float pmf(uint32_t tri) const { return pmf_by_triangle_.empty() ? 0.f : pmf_by_triangle_[tri]; }

 private:
  const Scene& scene_;
  std::vector<uint32_t> triangles_;  // emissive triangles
  std::vector<float> cdf_;           // over triangles_, cdf_.back() == 1
  std::vector<float> pmf_by_triangle_;
};

}  // namespace dacrt
