#include "dacrt/integrators/lights.h"

#include <algorithm>
#include <cfloat>
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

LightSampler::LightSampler(const Scene& scene, std::span<const PunctualLight> lights,
                           LightPicking picking)
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
  entries_ = power.size();
  // The tree's emitters: those with power that are not directional.
  std::vector<uint32_t> in_tree;
  double tree_power = 0.0, most = 0.0;
  for (uint32_t e = 0; e < entries_; ++e) {
    const bool directional = e >= triangles_.size() &&
                             lights[e - triangles_.size()].type == PunctualLight::Type::directional;
    if (directional || !(power[e] > 0.0)) continue;
    in_tree.push_back(e);
    tree_power += power[e], most = std::max(most, power[e]);
  }
  const bool use_tree = !in_tree.empty() && (picking == LightPicking::tree ||
                                             (picking == LightPicking::automatic &&
                                              entries_ >= tree_threshold));
  if (!use_tree) {
    table_ = AliasTable(power);
  } else {
    std::vector<LightTree::Bounds> leaves;
    for (const uint32_t e : in_tree) {
      LightTree::Bounds b;
      // Relative to the most powerful, as a float (at least the least normal float: a leaf of
      // power 0 would be as good as absent).
      b.power = std::max(FLT_MIN, float(power[e] / most));
      if (e < triangles_.size()) {
        const uint32_t tri = triangles_[e];
        b.lo = glm::min(glm::min(g.vertex(tri, 0), g.vertex(tri, 1)), g.vertex(tri, 2));
        b.hi = glm::max(glm::max(g.vertex(tri, 0), g.vertex(tri, 1)), g.vertex(tri, 2));
        b.w = g.unit_normal(tri);
        b.two_sided = scene.materials[g.material[tri]].double_sided;
      } else {
        const PunctualLight& l = lights[e - triangles_.size()];
        b.lo = b.hi = l.position;
        if (l.type == PunctualLight::Type::spot && glm::length(l.direction) > 0.f) {
          // Full intensity within θi of its axis, none past θo: θe = θo − θi beyond the first.
          b.w = glm::normalize(l.direction);
          b.cos_o = std::clamp(l.cos_inner, -1.f, 1.f);
          b.cos_e = std::cos(std::acos(std::clamp(l.cos_outer, -1.f, 1.f)) - std::acos(b.cos_o));
        } else {
          b.cos_o = -1.f;  // every direction
        }
      }
      leaves.push_back(b);
    }
    tree_ = LightTree(leaves);
    tree_entry_ = in_tree;
    entry_in_tree_.assign(entries_, none);
    for (uint32_t k = 0; k < in_tree.size(); ++k) entry_in_tree_[in_tree[k]] = k;
    // The tree's share of the choice and the directional lights', by power.
    std::vector<double> top{tree_power};
    for (uint32_t e = uint32_t(triangles_.size()); e < entries_; ++e)
      if (lights[e - triangles_.size()].type == PunctualLight::Type::directional)
        directional_.push_back(e), top.push_back(power[e]);
    table_ = AliasTable(top);
    tree_units_ = table_.units(0);
    uint32_t sum = tree_units_;
    for (size_t j = 0; j < directional_.size(); ++j)
      directional_units_.push_back(sum += table_.units(j + 1));
  }
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
    emitters_.push_back(
        {g.unit_normal(tri), centre, r2, tree() ? 0.f : float(table_.pmf(i)), g.area(tri)});
  }
}

LightSampler::Choice LightSampler::pick(float u, const LightContext& at) const {
  if (tree_.empty()) {
    const size_t i = table_.sample(u);         // a light whose pmf is 0 (black) is never returned
    return {i, float(table_.pmf(i))};          // a multiple of 2^-24: exact in float
  }
  constexpr uint32_t all = AliasTable::kUnits;
  uint32_t k = std::min(all - 1, uint32_t(std::max(0.f, u) * float(all)));
  if (k < tree_units_) {
    const LightTree::Pick p = tree_.sample(k, tree_units_, at);
    return {tree_entry_[p.entry], float(p.units) * (1.f / all)};
  }
  const size_t j = size_t(std::upper_bound(directional_units_.begin(), directional_units_.end(), k) -
                          directional_units_.begin());
  const uint32_t below = j == 0 ? tree_units_ : directional_units_[j - 1];
  return {directional_[j], float(directional_units_[j] - below) * (1.f / all)};
}

float LightSampler::entry_pmf(size_t entry, const LightContext& at) const {
  if (tree_.empty()) return float(table_.pmf(entry));
  constexpr float unit = 1.f / AliasTable::kUnits;
  if (entry_in_tree_[entry] != none)
    return float(tree_.units(entry_in_tree_[entry], tree_units_, at)) * unit;
  for (size_t j = 0; j < directional_.size(); ++j)
    if (directional_[j] == entry)
      return float(directional_units_[j] - (j == 0 ? tree_units_ : directional_units_[j - 1])) *
             unit;
  return 0.f;  // (emits nothing)
}

LightSampler::Sample LightSampler::sample(float u, float u1, float u2,
                                          const LightContext& at) const {
  const auto [i, pmf] = pick(u, at);
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
