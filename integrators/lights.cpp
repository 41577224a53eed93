#include "dacrt/integrators/lights.h"

#include <algorithm>
#include <glm/gtc/constants.hpp>

#include "dacrt/materials/sampling.h"
#include "dacrt/scene/surface.h"

namespace dacrt {
namespace {

// The triangle's emitted radiance (times its coverage, for alpha-tested materials), averaged over
// its centroid and the midpoints between the centroid and each corner when it varies over the
// triangle. Only the choice of light depends on it: a texel it misses is still found by BSDF
// sampling (MIS gives that full weight where next-event estimation's pmf is 0), so the estimator
// stays unbiased.
glm::vec3 average_emission(const Scene& scene, uint32_t tri) {
  const Material& m = scene.materials[scene.geometry.material[tri]];
  const bool covered = m.alpha_mode == Material::AlphaMode::opaque;
  if (m.uniform_emission() && covered) return m.emission;
  constexpr float third = 1.f / 3.f, near = 2.f / 3.f, far = 1.f / 6.f;
  const glm::vec2 points[4] = {{third, third}, {far, far}, {near, far}, {far, near}};
  glm::vec3 sum(0.f);
  for (const glm::vec2& b : points)
    sum += emission_at(scene, tri, b.x, b.y, scene.geometry.unit_normal(tri)) *
           (covered ? 1.f : coverage_at(scene, tri, b.x, b.y));
  return 0.25f * sum;
}

}  // namespace

LightSampler::LightSampler(const Scene& scene, std::span<const PunctualLight> lights)
    : scene_(scene) {
  const Geometry& g = scene.geometry;
  std::vector<double> power;
  for (uint32_t tri = 0; tri < g.size(); ++tri) {
    const Material& m = scene.materials[g.material[tri]];
    if (!m.emitter()) continue;
    double p = glm::pi<double>() * luminance(average_emission(scene, tri)) * g.area(tri) *
               (m.double_sided ? 2 : 1);
    if (!(p > 0.0)) continue;  // zero-area or black emitters can never be sampled usefully
    triangles_.push_back(tri);
    power.push_back(p);
  }
  const Box bounds = scene.bounds();
  // In double: in float the extent (of a triangle spanning ±3e38) or its squared length (in
  // scenes scaled by 1e±30) over- or underflows, and a sun's power with it.
  const double radius =
      bounds.empty() ? 1.0 : 0.5 * glm::length(glm::dvec3(bounds.hi) - glm::dvec3(bounds.lo));
  for (const PunctualLight& l : lights) {
    const double i = luminance(l.intensity);
    switch (l.type) {
      case PunctualLight::Type::point:
        power.push_back(4.0 * glm::pi<double>() * i);
        break;
      case PunctualLight::Type::spot:  // the solid angle of the cone halfway through the falloff
        power.push_back(glm::pi<double>() * (2.0 - l.cos_inner - l.cos_outer) * i);
        break;
      case PunctualLight::Type::directional:
        power.push_back(glm::pi<double>() * radius * radius * i);
        break;
    }
  }
  table_ = AliasTable(power);
  if (table_.empty()) return;  // nothing emits
  if (triangles_.empty()) return;
  index_by_triangle_.assign(g.size(), none);
  for (size_t i = 0; i < triangles_.size(); ++i) {
    const uint32_t tri = triangles_[i];
    index_by_triangle_[tri] = uint32_t(i);
    const glm::vec3 &v0 = g.vertex(tri, 0), &v1 = g.vertex(tri, 1), &v2 = g.vertex(tri, 2);
    const glm::vec3 centre = (v0 + v1 + v2) * (1.f / 3.f);
    const float r2 = std::max({glm::dot(v0 - centre, v0 - centre), glm::dot(v1 - centre, v1 - centre),
                               glm::dot(v2 - centre, v2 - centre)});
    emitters_.push_back({g.unit_normal(tri), centre, r2, float(table_.pmf(i)), g.area(tri)});
  }
}

LightSampler::Sample LightSampler::sample(float u, float u1, float u2) const {
  const size_t i = table_.sample(u);       // a light whose pmf is 0 (black) is never returned
  const float pmf = float(table_.pmf(i));  // a multiple of 2^-24: exact in float
  if (i >= triangles_.size())
    return {int(i - triangles_.size()), 0, glm::vec3(0.f), glm::vec2(0.f), pmf};
  uint32_t tri = triangles_[i];
  glm::vec2 b = sample_triangle(u1, u2);
  const Geometry& g = scene_.geometry;
  glm::vec3 p =
      (1.f - b.x - b.y) * g.vertex(tri, 0) + b.x * g.vertex(tri, 1) + b.y * g.vertex(tri, 2);
  return {-1, tri, p, b, pmf};
}

}  // namespace dacrt
