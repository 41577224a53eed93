// Split choice: binning the node's triangles (Wald 2007) and ray sampling (Nabata et al. 2013):
// α of every candidate split from a random subset of the node's rays, the cheapest split by
// C = C_T + C_I (α_L N_L + α_R N_R), the traversal order, and whether filtering a child can pay.
#include <algorithm>
#include <cmath>

#include "dacrt/tracer/dacrt/traversal.h"
#include "dacrt/tracer/partition.h"

namespace dacrt::kernel {

// α estimation: every sampled ray against both boxes of each of the n candidate splits. The
// split loop is branch-free over structure-of-arrays boxes so that it vectorises; it is the same
// conservative slab test as Ray::box_hits.
void Traversal::sample_splits(const Box* left, const Box* right, int n, uint32_t rb,
                              uint32_t samples, SplitScratch::Counts& c) {
  constexpr int max_splits = 256;
  alignas(32) float l_lo[3][max_splits], l_hi[3][max_splits];
  alignas(32) float r_lo[3][max_splits], r_hi[3][max_splits];
  for (int s = 0; s < n; ++s) c.left[s] = c.right[s] = c.left_first[s] = c.right_first[s] = 0;
  for (int s = 0; s < n; ++s)
    for (int a = 0; a < 3; ++a) {
      l_lo[a][s] = left[s].lo[a], l_hi[a][s] = left[s].hi[a];
      r_lo[a][s] = right[s].lo[a], r_hi[a][s] = right[s].hi[a];
    }
  for (uint32_t i = 0; i < samples; ++i) {
    const RayRef& r = rays[rb + i];
    float o[3], inv[3];
    const glm::vec3 inv_d = Ray::inverse(r.d);
    for (int a = 0; a < 3; ++a) o[a] = r.o[a], inv[a] = inv_d[a];
    const float t0 = r.tmin, t1 = r.far, pad = Ray::pad_for(r.o, k.magnitude);
    for (int s = 0; s < n; ++s) {
      float ln = t0, lf = t1, rn = t0, rf = t1;
      for (int a = 0; a < 3; ++a) {
        // (lo - pad - o) * inv, as in Ray::box_hits: the box bound first, then the shift.
        float la = (l_lo[a][s] - pad - o[a]) * inv[a], lb = (l_hi[a][s] + pad - o[a]) * inv[a];
        float ra = (r_lo[a][s] - pad - o[a]) * inv[a], rbb = (r_hi[a][s] + pad - o[a]) * inv[a];
        ln = std::max(ln, std::min(la, lb)), lf = std::min(lf, std::max(la, lb));
        rn = std::max(rn, std::min(ra, rbb)), rf = std::min(rf, std::max(ra, rbb));
      }
      const uint32_t hl = ln <= lf, hr = rn <= rf;
      c.left[s] += hl, c.right[s] += hr;
      c.left_first[s] += hl & (!hr | (ln <= rn));
      c.right_first[s] += hr & (!hl | (rn < ln));
    }
  }
  stats.box_tests += uint64_t(samples) * 2 * n;
}

// Moves a uniform random subset of `wanted` rays of [rb, re) to its front (a partial Fisher-Yates
// shuffle: the order of a range is free) and returns how many it moved; all rays if there are no
// more than wanted.
uint32_t Traversal::draw_samples(uint32_t rb, uint32_t re, uint32_t wanted) {
  const uint32_t nr = re - rb;
  if (nr <= wanted) return nr;
  for (uint32_t s = 0; s < wanted; ++s) std::swap(rays[rb + s], rays[rb + s + rng.below(nr - s)]);
  return wanted;
}

// Which of K bins a triangle centre falls into, on [lo, hi] along the binning axis. The same
// function bins and partitions, so they always agree. Centres are finite (TriangleRef::center
// clamps them), but hi − lo may still overflow: the map then works on halved coordinates (exact).
// NaN goes to bin 0, and no index leaves [0, K).
struct BinMap {
  float lo, scale, pre;
  int K;
  BinMap(float lo_, float hi, int bins) : K(bins) {
    pre = std::isfinite(hi - lo_) ? 1.f : 0.5f;
    lo = lo_ * pre;
    scale = float(K) / (hi * pre - lo);
  }
  bool valid() const { return scale > 0.f && std::isfinite(scale); }
  int operator()(float c) const {
    const float x = (c * pre - lo) * scale;
    return x >= 0.f ? int(std::min(x, float(K - 1))) : 0;
  }
};

namespace {

// Bins the triangles [tb, te) by their box centres along `axis` (Wald 2007): each bin's count,
// its triangles' box and its centres' box, so the children know theirs without another pass.
// Interleaved sets of bins, merged after: consecutive triangles in one bin would otherwise wait
// on each other's updates. Boxes are 4-wide vectors (x, y, z, unused) so that a triangle's
// decode and its four box updates are one instruction each; the values are exactly the scalar
// TriangleRef::hi and center.
void bin_triangles(const TriangleRef* tris, uint32_t tb, uint32_t te, int axis, const BinMap& map,
                   int K, SplitScratch::Bin* bins) {
  using Bin = SplitScratch::Bin;
  using f4 = float __attribute__((vector_size(16)));
  using i4 = int32_t __attribute__((vector_size(16)));
  struct VBin {
    f4 lo, hi, clo, chi;
  };
  // Lane-wise std::min(b, a) / std::max(b, a): the values the scalar Box::extend would give.
  auto vmin = [](f4 a, f4 b) { return a < b ? a : b; };
  auto vmax = [](f4 a, f4 b) { return b < a ? a : b; };
  constexpr int sets = 4;
  VBin vbins[sets][256];
  uint32_t count[sets][256];
  for (int set = 0; set < sets; ++set)
    for (int b = 0; b < K; ++b) {
      vbins[set][b] = {f4{} + inf, f4{} - inf, f4{} + inf, f4{} - inf};
      count[set][b] = 0;
    }
  for (uint32_t j = tb; j < te; ++j) {
    const TriangleRef& t = tris[j];
    const f4 tlo = {t.lo[0], t.lo[1], t.lo[2], 0.f};
    const f4 d = __builtin_convertvector((i4{t.ext[0], t.ext[1], t.ext[2], 0}), f4) * t.step();
    const f4 thi = tlo + d, c = TriangleRef::clamp_centre(tlo + 0.5f * d);
    const int b = map(c[axis]);
    VBin& v = vbins[j % sets][b];
    ++count[j % sets][b];
    v.lo = vmin(tlo, v.lo), v.hi = vmax(thi, v.hi);
    v.clo = vmin(c, v.clo), v.chi = vmax(c, v.chi);
  }
  for (int b = 0; b < K; ++b) {
    VBin v = vbins[0][b];
    uint32_t n = count[0][b];
    for (int set = 1; set < sets; ++set) {
      const VBin& w = vbins[set][b];
      v.lo = vmin(w.lo, v.lo), v.hi = vmax(w.hi, v.hi);
      v.clo = vmin(w.clo, v.clo), v.chi = vmax(w.chi, v.chi);
      n += count[set][b];
    }
    Bin& out = bins[b];
    out.count = n;
    for (int a = 0; a < 3; ++a) {
      out.box.lo[a] = v.lo[a], out.box.hi[a] = v.hi[a];
      out.centres.lo[a] = v.clo[a], out.centres.hi[a] = v.chi[a];
    }
  }
}

// The boxes and counts of every candidate split: split s puts bins [0, s) left and [s, K) right.
void sweep_bins(const SplitScratch::Bin* bins, int K, SplitScratch& out) {
  auto& left_box = out.left_box;
  auto& right_box = out.right_box;
  auto& left_n = out.left_n;
  auto& right_n = out.right_n;
  Box acc;
  uint32_t n = 0;
  for (int s = 1; s < K; ++s) {
    acc.extend(bins[s - 1].box), n += bins[s - 1].count;
    left_box[s] = acc, left_n[s] = n;
  }
  acc = Box();
  n = 0;
  for (int s = K - 1; s >= 1; --s) {
    acc.extend(bins[s].box), n += bins[s].count;
    right_box[s] = acc, right_n[s] = n;
  }
}

}  // namespace

// Bins the node's triangles, estimates α for every candidate split, and partitions the triangles
// by the cheapest one. Its large scratch arrays live only in this frame, never across the
// recursion, so deep trees cannot exhaust a worker thread's stack.
__attribute__((noinline)) Traversal::Split Traversal::choose_split(const Box& box,
                                                                   const Box& centres, uint32_t tb,
                                                                   uint32_t te, uint32_t rb,
                                                                   uint32_t re, bool by_area) {
  const DacrtParams& p = k.params;
  const uint32_t nt = te - tb, nr = re - rb;
  static thread_local SplitScratch scratch;
  stats.binned += nt;
  // References, not a structured binding: lambdas below use them (clang 14 cannot capture those).
  auto& bins = scratch.bins;
  auto& left_box = scratch.left_box;
  auto& right_box = scratch.right_box;
  auto& left_n = scratch.left_n;
  auto& right_n = scratch.right_n;
  auto& counts = scratch.counts;
  // Binning on triangle box centres along the longest axis of the centres' box.
  const int axis = centres.longest_axis();
  const int K = p.bins;
  const BinMap map(centres.lo[axis], centres.hi[axis], K);
  if (!map.valid()) return {};  // one centre: make a leaf
  auto bin_of = [&](const TriangleRef& t) { return map(t.center(axis, t.step())); };

  bin_triangles(tris, tb, te, axis, map, K, bins.data());
  sweep_bins(bins.data(), K, scratch);

  // Ray sampling. Above the threshold (or everywhere with small_nodes=all): α of each side of
  // every candidate from a random subset of the rays, and the split by C = C_T + C_I (α_L N_L +
  // α_R N_R). Ties (all α equal, e.g. every sampled ray starts inside the node) go to the better
  // SAH cost, which also picks the split when a node too large for a leaf must split anyway.
  // Small nodes (and dacrt-naive) pick the split by the SAH's area ratios.
  const bool all_splits = !by_area && samples_alpha(nr);
  uint32_t samples = 0;
  if (all_splits) {
    samples = alpha_samples(rb, re);
    sample_splits(&left_box[1], &right_box[1], K - 1, rb, samples, counts);
  }
  // The triangle tests of a leaf of n triangles, in whole blocks of leaf_lanes, for nodes of up to
  // two blocks (the last splits before the leaves) whose α is sampled: with many rays, whether
  // they enter both halves is known. (Costing the SAH's small nodes so made sponza 3 % slower.)
  const uint32_t lanes = uint32_t(p.leaf_lanes);
  auto tests = [lanes, small = all_splits && nt <= 2 * lanes](uint32_t n) {
    return small ? double((n + lanes - 1) / lanes * lanes) : double(n);
  };
  auto alpha_cost = [&](uint32_t hit_l, uint32_t hit_r, int split) {
    return p.cost_traversal + p.cost_intersect * (double(hit_l) / samples * tests(left_n[split]) +
                                                  double(hit_r) / samples * tests(right_n[split]));
  };
  double best_cost = INFINITY, best_area_cost = INFINITY;
  int best = 0;
  const double parent_area = box.half_area();
  // A child's share of the parent's area. Boxes of triangles whose extent overflows float have an
  // infinite (or NaN) area: such a child counts as the whole parent, a finite child inside an
  // infinite parent as nothing, so the split that sets the huge triangles apart wins.
  auto area_ratio = [&](const Box& child) {
    const double a = child.half_area();
    if (!(a < INFINITY)) return 1.0;
    if (!(parent_area < INFINITY)) return 0.0;
    return parent_area > 0 ? a / parent_area : 1.0;
  };
  for (int split = 1; split < K; ++split) {
    if (!left_n[split] || !right_n[split]) continue;
    double area_l = area_ratio(left_box[split]);
    double area_r = area_ratio(right_box[split]);
    double area_cost = p.cost_traversal + p.cost_intersect * (area_l * tests(left_n[split]) +
                                                              area_r * tests(right_n[split]));
    double cost =
        all_splits ? alpha_cost(counts.left[split - 1], counts.right[split - 1], split) : area_cost;
    if (cost < best_cost || (cost == best_cost && area_cost < best_area_cost))
      best_cost = cost, best_area_cost = area_cost, best = split;
  }
  if (best == 0) return {};
  uint32_t hit_l = 0, hit_r = 0, first_l = 0, first_r = 0;
  if (all_splits) {
    hit_l = counts.left[best - 1], hit_r = counts.right[best - 1];
    first_l = counts.left_first[best - 1], first_r = counts.right_first[best - 1];
  } else if (p.sampling) {
    // Small node: no α (filtering both children is then as cheap as estimating it, and a skip
    // almost never pays for few triangles).
    order_by_direction(rb, nr, axis, first_l, first_r);
  }
  const double leaf_cost = p.cost_intersect * tests(nt);
  if (best_cost >= leaf_cost && nt <= uint32_t(p.max_leaf_triangles)) return {};

  TriangleRef* tri_mid = block_partition_by(tris + tb, tris + te,
                                            [&](const TriangleRef& t) { return bin_of(t) < best; });
  const uint32_t tm = uint32_t(tri_mid - tris);
  Box left_centres, right_centres;
  for (int b = 0; b < K; ++b) (b < best ? left_centres : right_centres).extend(bins[b].centres);
  Split split{
      true,
      {{{left_box[best], left_centres, tb, tm, all_splits ? double(hit_l) / samples : -1.0},
        {right_box[best], right_centres, tm, te, all_splits ? double(hit_r) / samples : -1.0}}}};
  // Traversal order: first the child that more sampled rays enter first.
  if (p.sampling && first_r > first_l) std::swap(split.children[0], split.children[1]);
  return split;
}

void Traversal::order_kept(Split& split, int axis, uint32_t rb, uint32_t re) {
  const DacrtParams& p = k.params;
  const uint32_t nr = re - rb;
  Split::Child& a = split.children[0];
  Split::Child& b = split.children[1];
  a.alpha = b.alpha = -1.0;
  if (!p.sampling) return;  // dacrt-naive: left first, both filtered
  uint32_t first_l = 0, first_r = 0;
  if (samples_alpha(nr)) {
    // α of both children and who is entered first, from a sample of the rays, as in choose_split.
    static thread_local SplitScratch::Counts counts;
    const uint32_t samples = alpha_samples(rb, re);
    sample_splits(&a.box, &b.box, 1, rb, samples, counts);
    a.alpha = double(counts.left[0]) / samples, b.alpha = double(counts.right[0]) / samples;
    first_l = counts.left_first[0], first_r = counts.right_first[0];
  } else {
    order_by_direction(rb, nr, axis, first_l, first_r);
  }
  if (first_r > first_l) std::swap(a, b);
}

bool Traversal::samples_alpha(uint32_t nr) const {
  const DacrtParams& p = k.params;
  return p.sampling && (nr > uint32_t(p.sample_threshold) || !p.small_nodes_sah);
}

uint32_t Traversal::alpha_samples(uint32_t rb, uint32_t re) {
  const DacrtParams& p = k.params;
  return re - rb > uint32_t(p.sample_threshold) ? draw_samples(rb, re, p.sample_size) : re - rb;
}

// Without α: of up to 16 of the rays, those heading towards +axis enter the low (left) child
// first, the others the right one.
void Traversal::order_by_direction(uint32_t rb, uint32_t nr, int axis, uint32_t& first_l,
                                   uint32_t& first_r) const {
  const uint32_t n = std::min(nr, 16u);
  for (uint32_t i = 0; i < n; ++i) first_l += rays[rb + i].d[axis] >= 0.f;
  first_r = n - first_l;
}

// Filtering costs one box test per ray; it pays only if enough rays miss the child.
bool Traversal::skips_filter(const Split::Child& c) {
  const DacrtParams& p = k.params;
  const double threshold = p.filter_skip_alpha >= 0
                               ? p.filter_skip_alpha
                               : 1.0 - p.cost_traversal / (double(c.te - c.tb) * p.cost_intersect);
  return c.alpha >= 0.0 && c.alpha > threshold;
}

}  // namespace dacrt::kernel
