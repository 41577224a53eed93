// The light tree (see light_tree.h): its build, importance and exact descent.
#include "dacrt/integrators/light_tree.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <bit>
#include <numeric>

#include "dacrt/util/cpu.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define DACRT_LIGHT_TREE_X86 1
#endif

namespace dacrt {
namespace {

constexpr double pi = glm::pi<double>();

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

// The lane-by-lane importance and its AVX2 twin below compute the same operations in the same
// order (and -ffp-contract=off keeps every multiply and add apart), so both give the same bits.
// Comparisons are written as the vector instructions' (max(a, b) = a > b ? a : b): they differ
// from std::max only for NaN, which the end turns into 0 in both.
float vmax(float a, float b) { return a > b ? a : b; }
float vmin(float a, float b) { return a < b ? a : b; }

// cos(max(0, θa − θb)) and sin(max(0, θa − θb)) from both angles' sines and cosines (pbrt-v4's
// cosSubClamped and sinSubClamped).
float cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
  return cos_a > cos_b ? 1.f : cos_a * cos_b + sin_a * sin_b;
}
float sin_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
  return cos_a > cos_b ? 0.f : sin_a * cos_b - cos_a * sin_b;
}
float lane_sine(float cos) { return std::sqrt(vmax(1.f - cos * cos, 0.f)); }

// Lane i of node b's importance from `at` (see light_tree.h's top).
float lane_importance(const LightTree::Node& b, int i, const LightContext& at) {
  const float tx = at.p.x - b.cx[i], ty = at.p.y - b.cy[i], tz = at.p.z - b.cz[i];
  const float d2 = (tx * tx + ty * ty) + tz * tz;
  const float r2 = b.radius2[i];
  // The half angle the ball subtends from the point: every direction from inside it.
  const bool outside = d2 > r2;
  const float sin2 = r2 / d2;
  const float sin_b = outside ? std::sqrt(sin2) : 0.f;
  const float cos_b = outside ? std::sqrt(1.f - sin2) : -1.f;
  const bool away = d2 > 0.f;
  const float inv_d = away ? 1.f / std::sqrt(d2) : 0.f;
  float cos_pi = 1.f;
  if (at.n != glm::vec3(0.f)) {
    // The cosine at the point, towards the nearest direction of the ball (1 at the centre).
    const float cos_i = away ? -((tx * at.n.x + ty * at.n.y) + tz * at.n.z) * inv_d : 1.f;
    cos_pi = cos_sub_clamped(lane_sine(cos_i), cos_i, sin_b, cos_b);
  }
  // The least angle between the emitted directions and the point: θ' = max(0, θw − θo − θb).
  float cos_w = away ? ((b.wx[i] * tx + b.wy[i] * ty) + b.wz[i] * tz) * inv_d : 1.f;
  cos_w = std::bit_cast<float>(std::bit_cast<uint32_t>(cos_w) & b.sides[i]);
  const float sin_w = lane_sine(cos_w);
  const float cos_x = cos_sub_clamped(sin_w, cos_w, b.sin_o[i], b.cos_o[i]);
  const float sin_x = sin_sub_clamped(sin_w, cos_w, b.sin_o[i], b.cos_o[i]);
  const float cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
  const float result = b.power[i] * cos_p / vmax(d2, r2) * cos_pi;
  if (!(cos_pi > 0.f) || !(cos_p > b.cos_e[i]) || std::isnan(result)) return 0.f;
  return vmin(result, FLT_MAX);
}

// How a node splits `range` among its children by their importance: child i gets
// [bound[i], bound[i + 1]), bound[0] = 0 and bound[8] = range. One unit first to each child of
// positive importance (when the range has as many); the rest in proportion to the importance
// quantised to 2⁻²⁰ of the greatest, rounded at the cumulative sums (integers, so exact in any
// order: the parts add up to the range, and a child of importance 0 gets nothing). All in float
// and int32, eight lanes at once with AVX2, the same operations lane by lane otherwise. range
// ≤ 2²⁴ (the alias table's units: float holds it exactly).
constexpr float quanta = 0x1p20f;

// Equal parts of the range among the children, when none has positive importance.
void split_equally(uint32_t count, uint32_t range, uint32_t* bound) {
  bound[0] = 0;
  for (uint32_t i = 0; i < uint32_t(LightTree::width); ++i)
    bound[i + 1] = uint32_t(uint64_t(range) * std::min(i + 1, count) / count);
}

void split_lanes(const float* importance, uint32_t count, uint32_t range, uint32_t* bound) {
  constexpr int width = LightTree::width;
  float most = importance[0];
  uint32_t n_positive = 0;
  for (int i = 0; i < width; ++i) {
    most = vmax(most, importance[i]);
    n_positive += importance[i] > 0.f ? 1 : 0;
  }
  if (!(most > 0.f)) return split_equally(count, range, bound);
  const uint32_t reserved = range >= n_positive ? 1 : 0;
  const uint32_t rest = range - reserved * n_positive;
  std::array<int32_t, width> sums, seen;
  int32_t sum = 0, seen_sum = 0;
  for (int i = 0; i < width; ++i) {
    sums[size_t(i)] = sum += int32_t(std::floor(importance[i] / most * quanta));
    seen_sum += importance[i] > 0.f ? int32_t(reserved) : 0;
    seen[size_t(i)] = seen_sum;
  }
  const int32_t total = sum;
  const float scale = float(rest) / float(total);
  bound[0] = 0;
  for (int i = 0; i < width; ++i) {
    int32_t b = int32_t(std::floor(float(sums[size_t(i)]) * scale + 0.5f));
    b = std::min(b, int32_t(rest));
    if (sums[size_t(i)] == total) b = int32_t(rest);
    bound[i + 1] = uint32_t(b + seen[size_t(i)]);
  }
}

#ifdef DACRT_LIGHT_TREE_X86
#define DACRT_AVX2 __attribute__((target("avx2")))

DACRT_AVX2 inline __m256 sine8(__m256 cos) {
  const __m256 one = _mm256_set1_ps(1.f);
  return _mm256_sqrt_ps(_mm256_max_ps(_mm256_sub_ps(one, _mm256_mul_ps(cos, cos)),
                                      _mm256_setzero_ps()));
}
// a > b ? if_greater : fa · fb + sa · sb (cos_sub_clamped's and sin_sub_clamped's shape).
DACRT_AVX2 inline __m256 sub_clamped8(__m256 a, __m256 b, __m256 if_greater, __m256 p, __m256 q,
                                      __m256 r, __m256 s, bool minus) {
  const __m256 x = _mm256_mul_ps(p, q), y = _mm256_mul_ps(r, s);
  const __m256 v = minus ? _mm256_sub_ps(x, y) : _mm256_add_ps(x, y);
  return _mm256_blendv_ps(v, if_greater, _mm256_cmp_ps(a, b, _CMP_GT_OQ));
}

// lane_importance for the eight lanes at once.
DACRT_AVX2 inline __m256 importance8(const LightTree::Node& b, const LightContext& at) {
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.f);
  const __m256 tx = _mm256_sub_ps(_mm256_set1_ps(at.p.x), _mm256_load_ps(b.cx));
  const __m256 ty = _mm256_sub_ps(_mm256_set1_ps(at.p.y), _mm256_load_ps(b.cy));
  const __m256 tz = _mm256_sub_ps(_mm256_set1_ps(at.p.z), _mm256_load_ps(b.cz));
  const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(tx, tx), _mm256_mul_ps(ty, ty)),
                                  _mm256_mul_ps(tz, tz));
  const __m256 r2 = _mm256_load_ps(b.radius2);
  const __m256 outside = _mm256_cmp_ps(d2, r2, _CMP_GT_OQ);
  const __m256 sin2 = _mm256_div_ps(r2, d2);
  const __m256 sin_b = _mm256_blendv_ps(zero, _mm256_sqrt_ps(sin2), outside);
  const __m256 cos_b =
      _mm256_blendv_ps(_mm256_set1_ps(-1.f), _mm256_sqrt_ps(_mm256_sub_ps(one, sin2)), outside);
  const __m256 away = _mm256_cmp_ps(d2, zero, _CMP_GT_OQ);
  const __m256 inv_d = _mm256_blendv_ps(zero, _mm256_div_ps(one, _mm256_sqrt_ps(d2)), away);
  __m256 cos_pi = one;
  if (at.n != glm::vec3(0.f)) {
    const __m256 dot = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(tx, _mm256_set1_ps(at.n.x)),
                      _mm256_mul_ps(ty, _mm256_set1_ps(at.n.y))),
        _mm256_mul_ps(tz, _mm256_set1_ps(at.n.z)));
    const __m256 minus_dot = _mm256_xor_ps(dot, _mm256_set1_ps(-0.f));
    const __m256 cos_i = _mm256_blendv_ps(one, _mm256_mul_ps(minus_dot, inv_d), away);
    cos_pi = sub_clamped8(cos_i, cos_b, one, cos_i, cos_b, sine8(cos_i), sin_b, false);
  }
  const __m256 wdot = _mm256_add_ps(
      _mm256_add_ps(_mm256_mul_ps(_mm256_load_ps(b.wx), tx), _mm256_mul_ps(_mm256_load_ps(b.wy), ty)),
      _mm256_mul_ps(_mm256_load_ps(b.wz), tz));
  __m256 cos_w = _mm256_blendv_ps(one, _mm256_mul_ps(wdot, inv_d), away);
  cos_w = _mm256_and_ps(cos_w, _mm256_load_ps(reinterpret_cast<const float*>(b.sides)));
  const __m256 sin_w = sine8(cos_w);
  const __m256 cos_o = _mm256_load_ps(b.cos_o), sin_o = _mm256_load_ps(b.sin_o);
  const __m256 cos_x = sub_clamped8(cos_w, cos_o, one, cos_w, cos_o, sin_w, sin_o, false);
  const __m256 sin_x = sub_clamped8(cos_w, cos_o, zero, sin_w, cos_o, cos_w, sin_o, true);
  const __m256 cos_p = sub_clamped8(cos_x, cos_b, one, cos_x, cos_b, sin_x, sin_b, false);
  const __m256 result = _mm256_mul_ps(
      _mm256_div_ps(_mm256_mul_ps(_mm256_load_ps(b.power), cos_p), _mm256_max_ps(d2, r2)),
      cos_pi);
  const __m256 valid =
      _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(cos_pi, zero, _CMP_GT_OQ),
                                  _mm256_cmp_ps(cos_p, _mm256_load_ps(b.cos_e), _CMP_GT_OQ)),
                    _mm256_cmp_ps(result, result, _CMP_ORD_Q));
  return _mm256_and_ps(valid, _mm256_min_ps(result, _mm256_set1_ps(FLT_MAX)));
}

DACRT_AVX2 void importances_avx2(const LightTree::Node& b, const LightContext& at, float* out) {
  _mm256_storeu_ps(out, importance8(b, at));
}

// Inclusive prefix sums of eight lanes (exact: integers).
DACRT_AVX2 inline __m256i prefix8(__m256i x) {
  const __m256i zero = _mm256_setzero_si256();
  x = _mm256_add_epi32(x, _mm256_blend_epi32(_mm256_permutevar8x32_epi32(
                                                 x, _mm256_setr_epi32(0, 0, 1, 2, 3, 4, 5, 6)),
                                             zero, 0x01));
  x = _mm256_add_epi32(x, _mm256_blend_epi32(_mm256_permutevar8x32_epi32(
                                                 x, _mm256_setr_epi32(0, 0, 0, 1, 2, 3, 4, 5)),
                                             zero, 0x03));
  x = _mm256_add_epi32(x, _mm256_blend_epi32(_mm256_permutevar8x32_epi32(
                                                 x, _mm256_setr_epi32(0, 0, 0, 0, 0, 1, 2, 3)),
                                             zero, 0x0f));
  return x;
}

DACRT_AVX2 inline float max8(__m256 x) {
  __m128 m = _mm_max_ps(_mm256_castps256_ps128(x), _mm256_extractf128_ps(x, 1));
  m = _mm_max_ps(m, _mm_movehl_ps(m, m));
  m = _mm_max_ss(m, _mm_shuffle_ps(m, m, 1));
  return _mm_cvtss_f32(m);
}

// split_lanes (below) of the eight lanes at once; false when no child has positive importance.
DACRT_AVX2 bool split_avx2(__m256 importance, uint32_t range, uint32_t* bound) {
  const float most = max8(importance);
  if (!(most > 0.f)) return false;
  const __m256 q = _mm256_floor_ps(_mm256_mul_ps(_mm256_div_ps(importance, _mm256_set1_ps(most)),
                                                 _mm256_set1_ps(quanta)));
  const __m256 positive = _mm256_cmp_ps(importance, _mm256_setzero_ps(), _CMP_GT_OQ);
  const uint32_t n_positive = uint32_t(__builtin_popcount(unsigned(_mm256_movemask_ps(positive))));
  const uint32_t reserved = range >= n_positive ? 1 : 0;
  const uint32_t rest = range - reserved * n_positive;
  const __m256i sums = prefix8(_mm256_cvttps_epi32(q));
  const __m256i seen = prefix8(_mm256_and_si256(_mm256_castps_si256(positive),
                                                _mm256_set1_epi32(int(reserved))));
  const int total = _mm256_extract_epi32(sums, 7);
  const float scale = float(rest) / float(total);
  __m256i b = _mm256_cvttps_epi32(_mm256_floor_ps(_mm256_add_ps(
      _mm256_mul_ps(_mm256_cvtepi32_ps(sums), _mm256_set1_ps(scale)), _mm256_set1_ps(0.5f))));
  const __m256i all = _mm256_set1_epi32(int(rest));
  b = _mm256_min_epi32(b, all);
  b = _mm256_blendv_epi8(b, all, _mm256_cmpeq_epi32(sums, _mm256_set1_epi32(total)));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(bound + 1), _mm256_add_epi32(b, seen));
  bound[0] = 0;
  return true;
}

DACRT_AVX2 void level_avx2(const LightTree::Node& n, const LightContext& at, uint32_t range,
                           uint32_t* bound) {
  if (!split_avx2(importance8(n, at), range, bound)) split_equally(n.count, range, bound);
}
#else
void importances_avx2(const LightTree::Node&, const LightContext&, float*) {}
void level_avx2(const LightTree::Node&, const LightContext&, uint32_t, uint32_t*) {}
#endif

}  // namespace

// The binary tree the build makes, before it is collapsed.
struct LightTree::Binary {
  Bounds bounds;
  uint32_t right = 0;  // an inner node's second child (its first is the next node)
  uint32_t entry = 0;  // a leaf's
  uint32_t leaves = 1;
  bool leaf = true;
};

LightTree::LightTree(std::span<const Bounds> emitters) {
  if (emitters.empty()) return;
  std::vector<uint32_t> order(emitters.size());
  std::iota(order.begin(), order.end(), 0u);
  std::vector<Binary> binary;
  binary.reserve(2 * emitters.size());
  build(binary, order, 0, order.size(), emitters, 0);
  leaf_.assign(emitters.size(), 0);
  nodes_.reserve(binary.size() / 4 + 1);
  collapse(binary, 0, 0);
  up_.assign(nodes_.size(), 0);
  for (uint32_t i = 0; i < nodes_.size(); ++i)
    for (uint32_t lane = 0; lane < nodes_[i].count; ++lane)
      if (!(nodes_[i].child[lane] & leaf_bit)) up_[nodes_[i].child[lane]] = i * width + lane;
  avx2_ = avx2_available();
}

void LightTree::set_vectorised(bool on) { avx2_ = on && avx2_available(); }

uint32_t LightTree::build(std::vector<Binary>& out, std::vector<uint32_t>& order, size_t first,
                          size_t last, std::span<const Bounds> emitters, int depth) {
  const uint32_t index = uint32_t(out.size());
  out.emplace_back();
  if (last - first == 1) {
    const uint32_t e = order[first];
    out[index].bounds = emitters[e];
    out[index].entry = e;
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
  build(out, order, first, mid, emitters, depth + 1);
  const uint32_t right = build(out, order, mid, last, emitters, depth + 1);
  out[index].bounds = all;
  out[index].right = right;
  out[index].leaves = uint32_t(last - first);
  out[index].leaf = false;
  return index;
}

// A node of up to eight children from the binary tree below binary node `root`: its two
// children, then, while there are fewer than eight, the inner child of the most leaves replaced
// by its own two (in place, so the children keep the binary tree's order).
uint32_t LightTree::collapse(const std::vector<Binary>& binary, uint32_t root, int depth) {
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.emplace_back();
  depth_ = std::max(depth_, depth);
  std::array<uint32_t, width> lanes{};
  uint32_t count = 0;
  if (binary[root].leaf) {
    lanes[count++] = root;  // (a tree of one emitter)
  } else {
    lanes[count++] = root + 1, lanes[count++] = binary[root].right;
    while (count < width) {
      int widest = -1;
      for (uint32_t i = 0; i < count; ++i)
        if (!binary[lanes[i]].leaf &&
            (widest < 0 || binary[lanes[i]].leaves > binary[lanes[size_t(widest)]].leaves))
          widest = int(i);
      if (widest < 0) break;
      const uint32_t open = lanes[size_t(widest)];
      std::copy_backward(lanes.begin() + widest + 1, lanes.begin() + count,
                         lanes.begin() + count + 1);
      lanes[size_t(widest)] = open + 1, lanes[size_t(widest) + 1] = binary[open].right;
      ++count;
    }
  }
  Node& n = nodes_[index];
  n.count = count;
  for (uint32_t i = 0; i < uint32_t(width); ++i) {
    // Lanes past the children: nowhere to emit (cos_p ≤ 1 < cos_e), importance 0.
    Bounds b;
    b.cos_e = 2.f;
    if (i < count) b = binary[lanes[i]].bounds;
    const glm::vec3 c = 0.5f * (b.lo + b.hi), half = 0.5f * (b.hi - b.lo);
    n.cx[i] = c.x, n.cy[i] = c.y, n.cz[i] = c.z;
    n.radius2[i] = (half.x * half.x + half.y * half.y) + half.z * half.z;
    n.wx[i] = b.w.x, n.wy[i] = b.w.y, n.wz[i] = b.w.z;
    n.power[i] = i < count ? b.power : 0.f;
    n.cos_o[i] = b.cos_o, n.sin_o[i] = sine(b.cos_o), n.cos_e[i] = b.cos_e;
    n.sides[i] = b.two_sided ? 0x7fffffffu : 0xffffffffu;
    n.child[i] = 0;
    if (i < count && binary[lanes[i]].leaf) {
      n.child[i] = binary[lanes[i]].entry | leaf_bit;
      leaf_[binary[lanes[i]].entry] = index * width + i;
    }
  }
  for (uint32_t i = 0; i < count; ++i)
    if (!binary[lanes[i]].leaf) {
      const uint32_t child = collapse(binary, lanes[i], depth + 1);
      nodes_[index].child[i] = child;  // (nodes_ may have moved: no reference kept)
    }
  return index;
}

float LightTree::importance(const Bounds& b, const LightContext& at) {
  LightTree t;
  Binary leaf;
  leaf.bounds = b;
  t.leaf_.assign(1, 0);
  t.collapse({leaf}, 0, 0);
  return lane_importance(t.nodes_[0], 0, at);
}

void LightTree::importances(const Node& n, const LightContext& at, float out[width]) const {
  if (avx2_) return importances_avx2(n, at, out);
  for (int i = 0; i < width; ++i) out[i] = lane_importance(n, i, at);
}

void LightTree::level(const Node& n, const LightContext& at, uint32_t range,
                      uint32_t bound[width + 1]) const {
  if (avx2_) return level_avx2(n, at, range, bound);
  float importance[width];
  for (int i = 0; i < width; ++i) importance[i] = lane_importance(n, i, at);
  split_lanes(importance, n.count, range, bound);
}

void LightTree::child_importance(uint32_t node, const LightContext& at, float out[width]) const {
  importances(nodes_[node], at, out);
}

LightTree::Pick LightTree::sample(uint32_t k, uint32_t range, const LightContext& at) const {
  uint32_t node = 0;
  for (;;) {
    const Node& n = nodes_[node];
    uint32_t bound[width + 1];
    level(n, at, range, bound);
    uint32_t lane = 0;  // (bound[lane + 1] > k from the first child of a part on)
    for (int i = 1; i < width; ++i) lane += bound[i] <= k ? 1 : 0;
    k -= bound[lane], range = bound[lane + 1] - bound[lane];
    if (n.child[lane] & leaf_bit) return {n.child[lane] & ~leaf_bit, range};
    node = n.child[lane];
  }
}

uint32_t LightTree::units(uint32_t entry, uint32_t range, const LightContext& at) const {
  std::array<uint32_t, max_depth + 1> path;  // node × 8 + lane, from the leaf up
  int n = 0;
  for (uint32_t at_lane = leaf_[entry];; at_lane = up_[at_lane / width]) {
    path[size_t(n++)] = at_lane;
    if (at_lane / width == 0) break;
  }
  while (n > 0 && range > 0) {
    const uint32_t node_lane = path[size_t(--n)];
    const Node& node = nodes_[node_lane / width];
    uint32_t bound[width + 1];
    level(node, at, range, bound);
    const uint32_t lane = node_lane % width;
    range = bound[lane + 1] - bound[lane];
  }
  return range;
}

}  // namespace dacrt
