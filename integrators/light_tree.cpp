// The light tree (see light_tree.h): its build, importance and exact descent.
#include "dacrt/integrators/light_tree.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <numeric>

namespace dacrt {
namespace {

constexpr double pi = glm::pi<double>();

// cos(max(0, θa − θb)) and sin(max(0, θa − θb)) from both angles' sines and cosines (pbrt-v4's
// cosSubClamped and sinSubClamped).
float cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
  if (cos_a > cos_b) return 1.f;
  return cos_a * cos_b + sin_a * sin_b;
}
float sin_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
  if (cos_a > cos_b) return 0.f;
  return sin_a * cos_b - cos_a * sin_b;
}
float sine(float cos) { return std::sqrt(std::max(0.f, 1.f - cos * cos)); }

// The smallest cone holding cones (a, cos_a) and (b, cos_b) (pbrt-v4's DirectionCone Union), in
// double, widened by a little against rounding: a cone too narrow would take light from points
// it reaches (still unbiased, as their pmf says 0, but noisier).
void cone_union(const glm::vec3& a, float cos_a, const glm::vec3& b, float cos_b, glm::vec3& w,
                float& cos_o) {
  const double theta_a = std::acos(std::clamp(double(cos_a), -1.0, 1.0));
  const double theta_b = std::acos(std::clamp(double(cos_b), -1.0, 1.0));
  const glm::dvec3 da(a), db(b);
  const double theta_d = std::acos(std::clamp(glm::dot(da, db), -1.0, 1.0));
  if (std::min(theta_d + theta_b, pi) <= theta_a) {
    w = a, cos_o = cos_a;
    return;
  }
  if (std::min(theta_d + theta_a, pi) <= theta_b) {
    w = b, cos_o = cos_b;
    return;
  }
  const double theta_o = 0.5 * (theta_a + theta_d + theta_b) + 1e-4;
  const glm::dvec3 axis = glm::cross(da, db);
  const double axis2 = glm::dot(axis, axis);
  if (theta_o >= pi || !(axis2 > 1e-24)) {
    w = a, cos_o = -1.f;
    return;
  }
  // a rotated towards b by θo − θa about their common perpendicular (Rodrigues).
  const double theta_r = theta_o - 1e-4 - theta_a;
  const glm::dvec3 k = axis / std::sqrt(axis2);
  const glm::dvec3 r =
      da * std::cos(theta_r) + glm::cross(k, da) * std::sin(theta_r) +
      k * glm::dot(k, da) * (1.0 - std::cos(theta_r));
  w = glm::vec3(glm::normalize(r));
  cos_o = float(std::cos(theta_o));
}

LightTree::Bounds merge(const LightTree::Bounds& a, const LightTree::Bounds& b) {
  if (!(a.power > 0.f)) return b;
  if (!(b.power > 0.f)) return a;
  LightTree::Bounds m;
  m.lo = glm::min(a.lo, b.lo), m.hi = glm::max(a.hi, b.hi);
  m.power = a.power + b.power;
  cone_union(a.w, a.cos_o, b.w, b.cos_o, m.w, m.cos_o);
  m.cos_e = std::min(a.cos_e, b.cos_e);
  m.two_sided = a.two_sided || b.two_sided;
  return m;
}

// The surface area heuristic for lights (pbrt-v4's EvaluateCost): power × the measure of the
// directions the cone emits into × the box's area, the box stretched along the split axis by
// its longest side over that axis's (long thin boxes make poor bounds).
double cost(const LightTree::Bounds& b, int axis) {
  if (!(b.power > 0.f)) return 0.0;
  const double theta_o = std::acos(std::clamp(double(b.cos_o), -1.0, 1.0));
  const double theta_e = std::acos(std::clamp(double(b.cos_e), -1.0, 1.0));
  const double theta_w = std::min(theta_o + theta_e, pi);
  const double sin_o = std::sin(theta_o);
  const double m_omega = 2 * pi * (1 - std::cos(theta_o)) +
                         pi / 2 *
                             (2 * theta_w * sin_o - std::cos(theta_o - 2 * theta_w) -
                              2 * theta_o * sin_o + std::cos(theta_o));
  const glm::dvec3 d = glm::dvec3(b.hi) - glm::dvec3(b.lo);
  const double area = 2 * (d.x * d.y + d.y * d.z + d.z * d.x);
  const double longest = std::max({d.x, d.y, d.z});
  const double kr = d[axis] > 0 ? longest / d[axis] : 1.0;
  return double(b.power) * m_omega * kr * area;
}

glm::vec3 centre(const LightTree::Bounds& b) { return 0.5f * (b.lo + b.hi); }

// Past this depth the build splits at the median: a tree of n emitters is at most
// max_sah_depth + log2(n) deep, so that pmf() can walk up it on the stack.
constexpr int max_sah_depth = 40;
constexpr int max_depth = max_sah_depth + 33;

}  // namespace

LightTree::LightTree(std::span<const Bounds> emitters) {
  if (emitters.empty()) return;
  std::vector<uint32_t> order(emitters.size());
  std::iota(order.begin(), order.end(), 0u);
  nodes_.reserve(2 * emitters.size());
  leaf_.assign(emitters.size(), 0);
  build(order, 0, order.size(), emitters, 0);
  parent_.assign(nodes_.size(), 0);
  for (uint32_t i = 0; i < nodes_.size(); ++i)
    if (!nodes_[i].leaf) parent_[i + 1] = i, parent_[nodes_[i].child] = i;
}

uint32_t LightTree::build(std::vector<uint32_t>& order, size_t first, size_t last,
                          std::span<const Bounds> emitters, int depth) {
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.emplace_back();
  depth_ = std::max(depth_, depth);
  if (last - first == 1) {
    const uint32_t e = order[first];
    nodes_[index] = node(emitters[e]);
    nodes_[index].child = e;
    nodes_[index].leaf = true;
    leaf_[e] = index;
    return index;
  }
  Bounds all;
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (size_t i = first; i < last; ++i) {
    all = merge(all, emitters[order[i]]);
    lo = glm::min(lo, centre(emitters[order[i]]));
    hi = glm::max(hi, centre(emitters[order[i]]));
  }
  // The split of least cost among 12 buckets of the centres along each axis.
  constexpr int buckets = 12;
  double best = INFINITY;
  int best_axis = -1, best_bucket = 0;
  auto bucket_of = [&](const Bounds& b, int axis) {
    const float t = (centre(b)[axis] - lo[axis]) / (hi[axis] - lo[axis]);
    return std::clamp(int(float(buckets) * t), 0, buckets - 1);
  };
  if (depth < max_sah_depth)
    for (int axis = 0; axis < 3; ++axis) {
      if (!(hi[axis] > lo[axis])) continue;
      std::array<Bounds, buckets> bucket{};
      for (size_t i = first; i < last; ++i) {
        const Bounds& b = emitters[order[i]];
        Bounds& into = bucket[size_t(bucket_of(b, axis))];
        into = merge(into, b);
      }
      // The cost of the buckets above each split, swept from the top, then below it.
      std::array<double, buckets> above_cost{};
      Bounds above;
      for (int split = buckets - 2; split >= 0; --split) {
        above = merge(above, bucket[size_t(split + 1)]);
        above_cost[size_t(split)] = cost(above, axis);
      }
      Bounds below;
      for (int split = 0; split + 1 < buckets; ++split) {
        below = merge(below, bucket[size_t(split)]);
        const double c = cost(below, axis) + above_cost[size_t(split)];
        if (c < best) best = c, best_axis = axis, best_bucket = split;
      }
    }
  size_t mid = first;
  if (best_axis >= 0) {
    mid = size_t(std::stable_partition(order.begin() + first, order.begin() + last,
                                       [&](uint32_t e) {
                                         return bucket_of(emitters[e], best_axis) <= best_bucket;
                                       }) -
                 order.begin());
  }
  // A split that leaves almost nothing on one side makes the tree deep, and every pick walks
  // it: at the median instead. (On 4000 lamps, tools/make_many_lights.py: depth 35 → 21, a
  // pick 20 % faster, the noise per sample the same.)
  const size_t smaller = std::min(mid - first, last - mid);
  if (smaller == 0 || (last - first >= 64 && smaller * 8 < last - first)) {
    const glm::vec3 extent = hi - lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    mid = (first + last) / 2;
    std::nth_element(order.begin() + first, order.begin() + mid, order.begin() + last,
                     [&](uint32_t a, uint32_t b) {
                       const float ca = centre(emitters[a])[axis], cb = centre(emitters[b])[axis];
                       return ca < cb || (ca == cb && a < b);
                     });
  }
  build(order, first, mid, emitters, depth + 1);
  const uint32_t right = build(order, mid, last, emitters, depth + 1);
  nodes_[index] = node(all);
  nodes_[index].child = right;
  return index;
}

LightTree::Node LightTree::node(const Bounds& b) {
  const glm::vec3 half = 0.5f * (b.hi - b.lo);
  return {0.5f * (b.lo + b.hi), glm::dot(half, half), b.w, b.power, b.cos_o, sine(b.cos_o), b.cos_e,
          0, false, b.two_sided};
}

float LightTree::importance(const Bounds& b, const LightContext& at) {
  return importance(node(b), at);
}

float LightTree::importance(const Node& b, const LightContext& at) {
  const glm::vec3 to = at.p - b.centre;  // from the centre to the point
  const float d2 = glm::dot(to, to);
  // The half angle the ball subtends from the point: every direction from inside it.
  float sin_b = 0.f, cos_b = -1.f;
  if (d2 > b.radius2) {
    const float sin2 = b.radius2 / d2;
    sin_b = std::sqrt(sin2), cos_b = std::sqrt(1.f - sin2);
  }
  const float inv_d = d2 > 0.f ? 1.f / std::sqrt(d2) : 0.f;
  float cos_pi = 1.f;
  if (at.n != glm::vec3(0.f)) {  // the point's horizon, first: it ends many walks early
    // The cosine at the point, towards the nearest direction of the ball (1 at the centre).
    const float cos_i = d2 > 0.f ? -glm::dot(to, at.n) * inv_d : 1.f;
    cos_pi = cos_sub_clamped(sine(cos_i), cos_i, sin_b, cos_b);
    if (!(cos_pi > 0.f)) return 0.f;
  }
  // The least angle between the emitted directions and the point: θ' = max(0, θw − θo − θb).
  float cos_w = d2 > 0.f ? glm::dot(b.w, to) * inv_d : 1.f;
  if (b.two_sided) cos_w = std::abs(cos_w);
  const float sin_w = sine(cos_w);
  const float cos_x = cos_sub_clamped(sin_w, cos_w, b.sin_o, b.cos_o);
  const float sin_x = sin_sub_clamped(sin_w, cos_w, b.sin_o, b.cos_o);
  const float cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
  if (!(cos_p > b.cos_e)) return 0.f;
  const float result = b.power * cos_p / std::max(d2, b.radius2) * cos_pi;
  if (std::isnan(result)) return 0.f;
  return std::min(result, FLT_MAX);
}

uint32_t LightTree::first_part(float a, float b, uint32_t range) {
  if (!(a > 0.f) && !(b > 0.f)) return range / 2;
  if (!(a > 0.f)) return 0;
  if (!(b > 0.f)) return range;
  const double share = double(a) / (double(a) + double(b));
  const uint32_t part = uint32_t(std::min(double(range), std::floor(share * range + 0.5)));
  return range >= 2 ? std::clamp(part, 1u, range - 1) : part;
}

LightTree::Pick LightTree::sample(uint32_t k, uint32_t range, const LightContext& at) const {
  uint32_t node = 0;
  while (!nodes_[node].leaf) {
    const uint32_t a = node + 1, b = nodes_[node].child;
    const uint32_t part = first_part(importance(nodes_[a], at), importance(nodes_[b], at), range);
    if (k < part) {
      node = a, range = part;
    } else {
      k -= part, range -= part, node = b;
    }
  }
  return {nodes_[node].child, range};
}

uint32_t LightTree::units(uint32_t entry, uint32_t range, const LightContext& at) const {
  std::array<uint32_t, max_depth + 1> path;
  int n = 0;
  for (uint32_t node = leaf_[entry]; node != 0; node = parent_[node]) path[size_t(n++)] = node;
  uint32_t node = 0;
  while (n > 0 && range > 0) {
    const uint32_t next = path[size_t(--n)];
    const uint32_t a = node + 1, b = nodes_[node].child;
    const uint32_t part = first_part(importance(nodes_[a], at), importance(nodes_[b], at), range);
    range = next == a ? part : range - part;
    node = next;
  }
  return range;
}

}  // namespace dacrt
