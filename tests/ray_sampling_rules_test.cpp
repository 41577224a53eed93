// The three decisions ray sampling makes in the DACRT kernel (Nabata et al. 2013; DESIGN.md's
// kernel, steps 4 to 6): the split by α cost, the child entered first, and when a child's ray
// filter is skipped. They change how much work finds the hits, never which hits: the brute-force
// comparisons cannot see them. Here each is pinned on walls and parallel rays whose right
// decision is known, through the backend's counters.
#include <doctest/doctest.h>

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "dacrt/tracer/backend.h"
#include "dacrt/util/random.h"

using namespace dacrt;

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

// Walls of 16 triangles each (a 2 × 4 grid of quads) covering y, z ∈ [0, 1] in the planes x = xs.
Geometry walls(const std::vector<float>& xs) {
  Geometry g;
  for (float x : xs)
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 4; ++j) {
        const float y0 = 0.5f * float(i), y1 = y0 + 0.5f, z0 = 0.25f * float(j), z1 = z0 + 0.25f;
        g.add({x, y0, z0}, {x, y1, z0}, {x, y1, z1}, 0);
        g.add({x, y0, z0}, {x, y1, z1}, {x, y0, z1}, 0);
      }
  return g;
}

// n rays parallel to the x axis from x = from, through random points of the walls' square (off
// its edges), reaching t = tmax: of every ten, the first `forward` head along +x, the rest along
// -x.
RayBatch along_x(size_t n, float from, int forward = 10, float tmax = inf) {
  Pcg32 rng(7);
  RayBatch rays;
  for (size_t i = 0; i < n; ++i) {
    const float y = 0.05f + 0.9f * rng.uniform(), z = 0.05f + 0.9f * rng.uniform();
    const float dx = int(i % 10) < forward ? 1.f : -1.f;
    rays.push({from, y, z}, {dx, 0.f, 0.f}, 0.f, tmax, uint32_t(i));
  }
  return rays;
}

using Settings = std::vector<std::pair<const char*, const char*>>;

// The counters of one closest-hit call of `backend` with these options.
Stats traced(const Geometry& g, const RayBatch& rays, const Settings& settings,
             const char* backend = "dacrt") {
  Options options;
  for (const auto& [key, value] : settings) options.set(key, value);
  auto b = Backend::create(backend, g, options);
  HitBatch hits;
  b->intersect(rays, hits);
  return b->stats();
}

// α from 100 of 5000 rays (above sample_threshold), or from every one of 500 (small_nodes=all).
struct Sampling {
  size_t rays;
  const char* small_nodes;
};
const Sampling sampled{5000, "sah"}, every_ray{500, "all"};

}  // namespace

TEST_CASE("ray sampling: the split by α cost sets apart the only wall the rays reach") {
  // Walls at x = 0, 1, 2, 3; rays along +x from x = -1 stop at x = 0.5, so they reach the first
  // wall's box only. C = C_T + C_I (α_L N_L + α_R N_R) is 1 + 16 for the split 0 | 1 2 3, and its
  // right child, which no ray reaches, is filtered away whole: one node, 64 triangles binned, 16
  // tests per ray. By area (the SAH, dacrt-naive) the split is 0 1 | 2 3 and the rays test or
  // split the 32 of the left half; with α inverted it is 0 1 2 | 3; with α ignored no split is
  // cheaper than a leaf of all 64.
  const Geometry g = walls({0, 1, 2, 3});
  for (const Sampling& s : {sampled, every_ray}) {
    INFO(s.rays << " rays");
    const RayBatch rays = along_x(s.rays, -1.f, 10, 1.5f);
    const Stats st = traced(g, rays, {{"top_triangles", "0"}, {"small_nodes", s.small_nodes}});
    CHECK(st.nodes == 1);
    CHECK(st.binned == 64);
    CHECK(st.leaves == 1);
    CHECK(st.triangle_tests == 16 * s.rays);
    const Stats naive = traced(g, rays, {{"top_triangles", "0"}}, "dacrt-naive");
    CHECK(naive.binned > 64);  // the area heuristic's split is not the obvious one here
  }
}

TEST_CASE("ray sampling: the child the sampled rays reach first is entered first") {
  // Walls at x = 0 and x = 3, every ray through both. Entered first, the near wall gives every ray
  // its hit, and the far wall's filter then drops them all (filter_skip=2: never skipped, so that
  // filtering shows the order): one leaf, each ray tested against 16 triangles. The far wall
  // first would test every ray in both leaves. Along +x the near wall is the left child, along -x
  // the right one. Both ways of choosing: sampled α (the rays' first entries), and below
  // sample_threshold with small_nodes=sah the direction of the node's first 16 rays; both in a
  // split chosen per call (top_triangles=0) and in a kept one (top_triangles=32: the root).
  const Geometry g = walls({0, 3});
  for (const char* top : {"0", "32"})
    for (size_t n : {sampled.rays, size_t(500)})
      for (float from : {-1.f, 5.f}) {
        INFO("top_triangles=" << std::string(top) << ", " << n << " rays from x = " << from);
        const RayBatch rays = along_x(n, from, from < 0 ? 10 : 0);
        const Stats s = traced(g, rays,
                               {{"top_triangles", top},
                                {"max_leaf_triangles", "1"},  // split although α is 1 on both sides
                                {"filter_skip", "2"}});
        CHECK(s.nodes == 1);
        CHECK(s.kept_nodes == (top == std::string("0") ? 0 : 1));
        CHECK(s.leaves == 1);
        CHECK(s.leaf_rays == n);
        CHECK(s.triangle_tests == 16 * n);
      }
}

TEST_CASE(
    "ray sampling: a child's ray filter is skipped exactly when its α says filtering cannot pay") {
  // Walls at x = 0 and x = 3, 16 triangles each: the paper's rule skips a child's filter when its
  // α exceeds 1 − C_T / (N_child C_I) = 15/16; filter_skip=F when it exceeds F. A child that is
  // filtered gets only the rays that reach its box, one that is not gets them all: leaf_rays
  // shows which child was filtered, filter_skips how many were skipped.
  const Geometry g = walls({0, 3});
  for (const Sampling& s : {sampled, every_ray}) {
    const size_t n = s.rays;
    INFO(n << " rays");
    // Every ray through both walls (from x = -1 along +x): α = 1 on both sides, neither filtered.
    const RayBatch through = along_x(n, -1.f);
    Stats st = traced(g, through, {{"max_leaf_triangles", "1"}, {"small_nodes", s.small_nodes}});
    CHECK(st.nodes == 1);
    CHECK(st.filter_skips == 2);
    CHECK(st.leaf_rays == 2 * n);
    CHECK(traced(g, through, {{"max_leaf_triangles", "1"}}, "dacrt-naive").filter_skips == 0);
    // From between the walls, half each way: α = 1/2 on both sides, each child gets its half.
    st = traced(g, along_x(n, 1.5f, 5), {{"small_nodes", s.small_nodes}});
    CHECK(st.nodes == 1);
    CHECK(st.filter_skips == 0);
    CHECK(st.leaf_rays == n);
    // Seven of ten towards x = 0 (α = 0.7 there, 0.3 at x = 3): under the paper's 15/16 both are
    // filtered. With C_T = 8 its threshold is 1 − 8/16 = 1/2, as is filter_skip=0.5's: the near
    // wall takes every ray unfiltered, the far one only its three in ten.
    const RayBatch most = along_x(n, 1.5f, 3);
    st = traced(g, most, {{"small_nodes", s.small_nodes}});
    CHECK(st.filter_skips == 0);
    CHECK(st.leaf_rays == n);
    for (const auto& [key, value] : Settings{{"cost_traversal", "8"}, {"filter_skip", "0.5"}}) {
      INFO(std::string(key) << "=" << std::string(value));
      st = traced(g, most, {{"small_nodes", s.small_nodes}, {key, value}});
      CHECK(st.filter_skips == 1);
      CHECK(st.leaf_rays == n + 3 * n / 10);
    }
  }
}
