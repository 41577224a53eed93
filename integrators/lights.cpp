#include "integrators/lights.h"

#include <algorithm>

#include "materials/sampling.h"

namespace dacrt {

LightSampler::LightSampler(const Scene& scene) : scene_(scene) {
  const Geometry& g = scene.geometry;
  std::vector<double> power;
  for (uint32_t tri = 0; tri < g.size(); ++tri) {
    const Material& m = scene.materials[g.material[tri]];
    if (!m.emissive()) continue;
    double p = double(luminance(m.emission)) * g.area(tri) * (m.double_sided ? 2.0 : 1.0);
    if (!(p > 0.0)) continue;  // zero-area or black emitters can never be sampled usefully
    triangles_.push_back(tri);
    power.push_back(p);
  }
  if (triangles_.empty()) return;
  double total = 0.0;
  for (double p : power) total += p;
  pmf_by_triangle_.assign(g.size(), 0.f);
  cdf_.resize(power.size());
  double running = 0.0;
  for (size_t i = 0; i < power.size(); ++i) {
    running += power[i];
    cdf_[i] = float(running / total);
    pmf_by_triangle_[triangles_[i]] = float(power[i] / total);
  }
  cdf_.back() = 1.f;
}

LightSampler::Sample LightSampler::sample(float u, float u1, float u2) const {
  size_t i = size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
  i = std::min(i, cdf_.size() - 1);
  uint32_t tri = triangles_[i];
  glm::vec2 b = sample_triangle(u1, u2);
  const Geometry& g = scene_.geometry;
  glm::vec3 p =
      (1.f - b.x - b.y) * g.vertex(tri, 0) + b.x * g.vertex(tri, 1) + b.y * g.vertex(tri, 2);
  return {tri, p, pmf_by_triangle_[tri]};
}

}  // namespace dacrt
