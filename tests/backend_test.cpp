// The DACRT backends against the brute-force oracle: same closest hit (triangle, bit-identical t,
// u, v) and same occlusion answer for every ray, over several kinds of geometry and rays.
#include "dacrt/tracer/backend.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <cstring>

#include "allocations.h"
#include "dacrt/io/gltf.h"
#include "test_geometry.h"
#include "dacrt/tracer/dacrt/dacrt.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

HitBatch brute_hits(const Geometry& g, const RayBatch& rays, const HitFilter* filter = nullptr) {
  HitBatch hits;
  Backend::create("brute", g)->intersect(rays, hits, filter);
  return hits;
}

// Compares a backend with the oracle's answers; returns the number of rays compared.
size_t compare(const Geometry& g, const RayBatch& rays, const HitBatch& expected,
               const char* backend, const Options& options = {},
               const HitFilter* filter = nullptr) {
  auto tested = Backend::create(backend, g, options);
  HitBatch got;
  tested->intersect(rays, got, filter);
  REQUIRE(got.size() == rays.size());
  size_t mismatches = 0, hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    hits += expected.hit(i);
    bool same = expected.prim[i] == got.prim[i] && same_bits(expected.t[i], got.t[i]) &&
                (!expected.hit(i) ||
                 (same_bits(expected.u[i], got.u[i]) && same_bits(expected.v[i], got.v[i])));
    if (!same && ++mismatches <= 5)
      FAIL_CHECK(std::string(backend)
                 << " ray " << i << ": prim " << got.prim[i] << " t " << got.t[i]
                 << ", brute: prim " << expected.prim[i] << " t " << expected.t[i]);
  }
  CHECK(mismatches == 0);

  // A ray is occluded exactly when it has a closest hit in [tmin, tmax]: the oracle's closest hits
  // are the oracle for occlusion (brute's own occluded is checked against them elsewhere).
  std::vector<uint8_t> occ_got(rays.size(), 7);
  tested->occluded(rays, occ_got, filter);
  size_t occ_mismatches = 0;
  for (size_t i = 0; i < rays.size(); ++i) occ_mismatches += occ_got[i] != uint8_t(expected.hit(i));
  CHECK(occ_mismatches == 0);
  MESSAGE(std::string(backend) << ": " << rays.size() << " rays, " << hits << " hits, " << g.size()
                               << " triangles");
  return rays.size();
}

size_t compare_with_brute(const Geometry& g, const RayBatch& rays, const char* backend,
                          const Options& options = {}) {
  return compare(g, rays, brute_hits(g, rays), backend, options);
}

struct Case {
  const char* name;
  Geometry geometry;
};

std::vector<Case> cases() {
  std::vector<Case> c;
  c.push_back({"random soup", random_soup(1500, 11)});
  c.push_back({"closed sphere", sphere(24, 48, glm::vec3(0.5f), 0.5f)});
  c.push_back({"quad grid", quad_grid(24, 1.f / 24.f)});
  c.push_back({"long thin triangles", slivers(1200, 12)});
  c.push_back({"one centroid", one_centroid(400, 13)});
  c.push_back({"one box centre", one_box_center(400, 14)});
  return c;
}

}  // namespace

TEST_CASE("dacrt returns the brute-force closest hit and occlusion on a million rays") {
  size_t total = 0;
  uint64_t seed = 100;
  for (auto& c : cases()) {
    INFO(c.name);
    for (size_t n : {size_t(0), size_t(1), size_t(2), size_t(1000), size_t(100000)})
      total += compare_with_brute(c.geometry, random_rays(c.geometry, n, ++seed, RayType::bounce),
                                  "dacrt");
    total += compare_with_brute(c.geometry, surface_rays(c.geometry, 60000, ++seed), "dacrt");
    total += compare_with_brute(c.geometry, axis_rays(c.geometry, 40000, ++seed), "dacrt");
  }
  MESSAGE("rays compared: " << total);
  CHECK(total >= 1000000);
}

TEST_CASE("dacrt stays exact with every knob at its extremes, and so does dacrt-naive") {
  Geometry g = random_soup(3000, 21);
  RayBatch rays = random_rays(g, 30000, 22, RayType::bounce);
  const HitBatch expected = brute_hits(g, rays);
  std::vector<std::vector<std::pair<const char*, const char*>>> settings = {
      {{"bins", "2"}},
      {{"bins", "64"}, {"leaf_rays", "1"}, {"leaf_triangles", "1"}},
      {{"leaf_rays", "100000"}, {"leaf_work", "1"}},      // split down to single triangles
      {{"leaf_rays", "64"}, {"leaf_work", "100000000"}},  // few-ray leaves of any size
      {{"filter_skip", "0"}},                             // never filter
      {{"filter_skip", "1.5"}},                           // always filter
      {{"sample_size", "1"}, {"sample_threshold", "1"}},
      {{"simd", "none"}},     // the portable leaf test
      {{"group_rays", "0"}},  // one ray against a block of sixteen triangles in every leaf
      {{"group_rays", "1"}, {"leaf_rays", "64"}, {"leaf_work", "100000000"}},  // sixteen rays
      {{"simd", "none"}, {"leaf_rays", "64"}, {"leaf_work", "100000000"}},
      {{"small_nodes", "all"}},                                  // every ray samples every split
      {{"small_nodes", "all"}, {"sample_threshold", "100000"}},  // every node
      {{"max_depth", "3"}},
      {{"cost_traversal", "1000"}},  // leaves everywhere the size allows
      {{"cost_traversal", "1000"}, {"max_leaf_triangles", "100000"}},  // leaves everywhere
      {{"task_rays", "1"}, {"chunks", "64"}},         // as many chunks as threads, forks everywhere
      {{"task_rays", "1"}, {"filter_skip", "0"}},     // forks whose children take every ray
      {{"task_rays", "1"}, {"filter_skip", "0.5"}},   // forks where one child may
      {{"task_rays", "100000000"}, {"chunks", "1"}},  // one traversal on one thread
      {{"top_triangles", "0"}},                       // nothing kept: pure per-call DACRT
      {{"top_triangles", "1"}},                       // everything that splits is kept
      {{"top_triangles", "1"}, {"small_nodes", "all"}, {"task_rays", "1"}},
      {{"walk_rays", "0"}},                                  // no ray walks the kept top alone
      {{"walk_rays", "100000000"}},                          // every ray walks it from the root
      {{"walk_rays", "100000000"}, {"top_triangles", "1"}},  // down to leaves of one triangle
      {{"walk_rays", "100000000"}, {"top_triangles", "1024"}, {"max_depth", "2"}},
  };
  for (const auto& s : settings) {
    Options o;
    std::string label;
    for (auto [k, v] : s) o.set(k, v), label += std::string(k) + "=" + v + " ";
    INFO(label);
    compare(g, rays, expected, "dacrt", o);
  }
  compare(g, rays, expected, "dacrt-naive");
  compare_with_brute(sphere(24, 48, glm::vec3(0.5f), 0.5f), surface_rays(g, 20000, 23),
                     "dacrt-naive");
}

TEST_CASE("dacrt's leaves answer the same one ray at a time and sixteen rays at a time") {
  // group_rays=1 tests every leaf's rays sixteen at a time against one triangle at a time
  // (RayGroup), group_rays=0 one ray at a time against blocks of sixteen triangles: rays from
  // surfaces have lanes the vector test leaves to the scalar one (t within its error of 0), axis
  // rays have zero direction components, diagonal rays tied largest components (the shear's axis),
  // slivers and one-centroid soups have ties and edges.
  uint64_t seed = 700;
  for (auto& c : cases()) {
    for (const RayBatch& rays :
         {random_rays(c.geometry, 20000, ++seed, RayType::bounce),
          surface_rays(c.geometry, 20000, ++seed), axis_rays(c.geometry, 10000, ++seed)}) {
      const HitBatch expected = brute_hits(c.geometry, rays);
      Stats s[2];
      for (int grouped : {0, 1}) {
        Options o;
        o.set("group_rays", std::to_string(grouped));
        INFO(c.name << ", group_rays=" << grouped);
        compare(c.geometry, rays, expected, "dacrt", o);
        // The same recursion either way (one thread: no subtree is split between two), so the
        // same counters.
        auto b = Backend::create("dacrt", c.geometry, o);
        HitBatch h;
        tbb::task_arena(1).execute([&] { b->intersect(rays, h); });
        s[grouped] = b->stats();
      }
      INFO(c.name);
      CHECK(s[0].leaves == s[1].leaves);
      CHECK(s[0].triangle_tests == s[1].triangle_tests);
    }
  }
  Options bad;
  bad.set("group_rays", "-1");
  CHECK_THROWS_WITH_AS(Backend::create("dacrt", random_soup(10, 1), bad),
                       doctest::Contains("group_rays"), Error);
}

TEST_CASE("hit filters (alpha tests): dacrt and dacrt-naive see through what brute sees through") {
  // Forks everywhere on two threads, so filtered hits also meet the concurrent subtrees.
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  size_t total_changed = 0;
  for (auto& c : cases()) {
    INFO(std::string(c.name));
    const Geometry& g = c.geometry;
    const TestFilter filter(g.size());
    for (const RayBatch& rays :
         {random_rays(g, 20000, 31, RayType::bounce), surface_rays(g, 20000, 32, true)}) {
      const HitBatch plain = brute_hits(g, rays), expected = brute_hits(g, rays, &filter);
      size_t plain_hits = 0, filtered_hits = 0;
      for (size_t i = 0; i < rays.size(); ++i)
        plain_hits += plain.hit(i), filtered_hits += expected.hit(i);
      // The filter matters: some rays pass through to another triangle or out of the scene.
      size_t changed = 0;
      for (size_t i = 0; i < rays.size(); ++i) changed += plain.prim[i] != expected.prim[i];
      MESSAGE(std::string(c.name) << ": " << plain_hits << " hits, " << filtered_hits
                                  << " after filtering, " << changed << " changed");
      CHECK(changed * 20 >= plain_hits);
      total_changed += changed;
      compare(g, rays, expected, "dacrt", {}, &filter);
      Options forks;
      forks.set("task_rays", "64");
      forks.set("chunks", "1");
      compare(g, rays, expected, "dacrt", forks, &filter);
      Options scalar;
      scalar.set("simd", "none");
      compare(g, rays, expected, "dacrt", scalar, &filter);
      Options walk;  // every ray walks the kept top on its own
      walk.set("walk_rays", "100000000");
      compare(g, rays, expected, "dacrt", walk, &filter);
      compare(g, rays, expected, "dacrt-naive", {}, &filter);
    }
    CHECK(filter.calls > 0);
  }
  CHECK(total_changed > 1000);
}

TEST_CASE("brute's occlusion agrees with its closest hit, with and without a hit filter") {
  for (auto& c : cases()) {
    INFO(c.name);
    RayBatch rays = surface_rays(c.geometry, 3000, 41);
    const TestFilter filter(c.geometry.size());
    const HitFilter* none = nullptr;
    for (const HitFilter* f : {none, static_cast<const HitFilter*>(&filter)}) {
      auto brute = Backend::create("brute", c.geometry);
      HitBatch hits;
      brute->intersect(rays, hits, f);
      std::vector<uint8_t> occ(rays.size());
      brute->occluded(rays, occ, f);
      size_t mismatches = 0;
      for (size_t i = 0; i < rays.size(); ++i) mismatches += occ[i] != uint8_t(hits.hit(i));
      CHECK(mismatches == 0);
    }
  }
}

TEST_CASE("backends are created by name and reject what they do not know") {
  Geometry g = quad_grid(2);
  for (const char* name : {"dacrt", "dacrt-naive", "brute"}) CHECK(Backend::create(name, g));
  CHECK_THROWS_AS(Backend::create("no-such-backend", g), Error);
  Options bad;
  bad.set("binz", "4");
  CHECK_THROWS_WITH_AS(Backend::create("dacrt", g, bad), doctest::Contains("binz"), Error);
  Options nan;
  nan.set("bins", "many");
  CHECK_THROWS_AS(Backend::create("dacrt", g, nan), Error);
}

TEST_CASE("an empty scene misses every ray") {
  Geometry empty;
  RayBatch rays = random_rays(quad_grid(2), 100, 3, RayType::primary);
  for (const char* name : {"dacrt", "brute"}) {
    auto b = Backend::create(name, empty);
    HitBatch hits;
    b->intersect(rays, hits);
    std::vector<uint8_t> occ(rays.size(), 1);
    b->occluded(rays, occ);
    for (size_t i = 0; i < rays.size(); ++i) {
      CHECK_FALSE(hits.hit(i));
      CHECK(occ[i] == 0);
    }
  }
}

TEST_CASE("NaN, inf, zero-direction and inactive rays miss without harm") {
  Geometry g = quad_grid(8, 0.125f);
  RayBatch rays = degenerate_rays();
  for (const char* name : {"dacrt", "dacrt-naive", "brute"}) {
    INFO(name);
    auto b = Backend::create(name, g);
    HitBatch hits;
    b->intersect(rays, hits);
    std::vector<uint8_t> occ(rays.size(), 7);
    b->occluded(rays, occ);
    for (size_t i = 0; i < rays.size(); ++i) {
      INFO("ray " << i);
      CHECK(hits.hit(i) == (i < 2));
      CHECK(occ[i] == (i < 2));
      if (i < 2) CHECK(hits.t[i] == 1.f);
    }
  }
}

TEST_CASE("dacrt builds the same recursion with AVX-512, AVX2 and scalar tests") {
  // The vector box and triangle tests reproduce the scalar ones bit for bit, so every filtering
  // decision, and with it every counter, is the same (on one thread: a subtree another thread
  // takes while its sibling runs is traversed in two parts, which changes the counters). Where
  // the CPU lacks a level, the next narrower one runs and the test still holds.
  Geometry g = random_soup(5000, 61);
  // Axis-parallel rays have zero direction components: the clamped inverse.
  for (const RayBatch& rays :
       {random_rays(g, 50000, 62, RayType::bounce), axis_rays(g, 30000, 63)}) {
    const char* levels[] = {"auto", "avx2", "none"};
    Stats s[3];
    HitBatch h[3];
    for (int i = 0; i < 3; ++i) {
      Options o;
      o.set("simd", levels[i]);
      auto b = Backend::create("dacrt", g, o);
      tbb::task_arena(1).execute([&] { b->intersect(rays, h[i]); });
      s[i] = b->stats();
    }
    for (int i = 0; i < 2; ++i) {
      INFO("simd=" << levels[i] << " vs none");
      CHECK(s[i].nodes == s[2].nodes);
      CHECK(s[i].leaves == s[2].leaves);
      CHECK(s[i].box_tests == s[2].box_tests);
      CHECK(s[i].triangle_tests == s[2].triangle_tests);
      CHECK(s[i].filter_skips == s[2].filter_skips);
      CHECK(h[i].prim == h[2].prim);
      CHECK(h[i].t == h[2].t);
    }
    CHECK(s[2].nodes > 100);
  }
}

TEST_CASE("dacrt's parallel subtrees give the closest hits of one thread") {
  // With task_rays=64 nearly every node forks: its second child runs as a task, beside the first
  // child when another thread takes it, and the rays both children need visit it afterwards.
  Geometry g = random_soup(4000, 81);
  for (const RayBatch& rays : {random_rays(g, 20000, 82, RayType::bounce),
                               surface_rays(g, 20000, 83, true), axis_rays(g, 20000, 84)}) {
    const HitBatch expected = brute_hits(g, rays);
    for (const char* name : {"dacrt", "dacrt-naive"}) {
      for (int threads : {1, 2, 4}) {
        INFO(std::string(name) << ", " << threads << " threads");
        Options o;
        o.set("task_rays", "64");
        o.set("chunks", "1");  // one traversal: the other threads only get work by stealing
        // (A fresh task_arena would do for the thread count, but in it the spawned subtrees
        // were never stolen: its workers come too late for calls this short.)
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        compare(g, rays, expected, name, o);
      }
    }
  }
  // The concurrent path is taken (and so tested above) whenever another thread is free; on a
  // loaded machine it may take a few calls.
  auto b = Backend::create("dacrt", g, [] {
    Options o;
    o.set("task_rays", "64");
    o.set("chunks", "1");
    return o;
  }());
  RayBatch rays = random_rays(g, 20000, 90, RayType::bounce);
  HitBatch hits;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 4);
  for (int call = 0; call < 50 && b->stats().tasks == 0; ++call) b->intersect(rays, hits);
  CHECK(b->stats().tasks > 0);
}

TEST_CASE("dacrt's working memory, as allocated, stays within the bound it states before tracing") {
  // Every byte the call allocates is counted (tests/allocations.cpp): the ray records, the
  // triangle records of each chunk, the kept top levels, and whatever else it allocates.
  Geometry g = random_soup(20000, 71);
  for (size_t n : {size_t(1000), size_t(100000)}) {
    RayBatch rays = random_rays(g, n, 72, RayType::bounce);
    for (const char* name : {"dacrt", "dacrt-naive"}) {
      for (int threads : {1, 2, 4}) {
        INFO(std::string(name) << ", " << n << " rays, " << threads << " threads");
        HitBatch hits;
        hits.resize(n);  // the output is not the kernel's memory
        uint64_t first = 0, later = 0;
        std::unique_ptr<Backend> b;
        tbb::task_arena(threads).execute([&] {
          AllocationWatch watch;  // the build (records, kept top) and the first call
          b = Backend::create(name, g);
          b->intersect(rays, hits);
          first = watch.peak();
          AllocationWatch again;  // records kept: a later call allocates little
          b->intersect(rays, hits);
          later = again.peak();
        });
        MESSAGE(std::string(name) << ", " << n << " rays, " << threads << " threads: first call "
                                  << first << " B allocated at most (bound "
                                  << dacrt_memory_bound(n, g.size()) << "), next " << later
                                  << " B");
        CHECK(first <= dacrt_memory_bound(n, g.size()));
        // And the bound is not loose: the rays' and at least one chunk's records are there.
        CHECK(first >= 36 * n + 20 * g.size());
        CHECK(later <= first);
        CHECK(b->stats().peak_bytes <= dacrt_memory_bound(n, g.size()));
      }
      // The budget: at most 48 bytes per ray and 48 per triangle.
      CHECK(dacrt_memory_bound(n, g.size()) <= 48 * n + 48 * g.size());
    }
  }
}

TEST_CASE("dacrt stays exact at extreme scales and far from the origin") {
  // The kernel's triangle records store boxes as 8-bit multiples of a power of two, rounded up;
  // near the float range's ends and for small triangles far out that rounding must stay outward.
  // (Below ~1e-19 the edge functions' products underflow and nothing can be hit at all.)
  for (auto [scale, offset] :
       {std::pair{1e-15f, 0.f}, std::pair{1e-6f, 1e-4f}, std::pair{1e12f, 0.f},
        std::pair{1e15f, 0.f} /* the float t overflows: decided in double */, std::pair{1.f, 1e7f},
        std::pair{10.f, -3e5f}}) {
    INFO("scale " << scale << ", offset " << offset);
    Geometry g = random_soup(1000, 81);
    for (auto& corners : g.corners)
      for (glm::vec3& p : corners) p = p * scale + offset;
    RayBatch rays = random_rays(random_soup(1000, 81), 8000, 82, RayType::bounce);
    for (size_t i = 0; i < rays.size(); ++i)  // the same rays, scaled with the scene
      rays.set(i, rays.origin(i) * scale + glm::vec3(offset), rays.direction(i), 0.f, INFINITY,
               uint32_t(i));
    const HitBatch expected = brute_hits(g, rays);
    size_t hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) hits += expected.hit(i);
    CHECK(hits > 500);
    compare(g, rays, expected, "dacrt");
    compare(g, rays, expected, "dacrt-naive");
  }
}

TEST_CASE("dacrt stays exact with triangles whose extent overflows float") {
  // A box of such a triangle has an infinite extent and an infinite centre: binning must neither
  // index out of bounds with NaN nor lose the triangle. Mixed with ordinary triangles, alone, and
  // with the huge coordinates on every axis.
  for (int axis = 0; axis < 3; ++axis)
    for (size_t ordinary : {size_t(0), size_t(1), size_t(2000)}) {
      INFO("axis " << axis << ", " << ordinary << " ordinary triangles");
      Geometry g = random_soup(ordinary, 91);
      const float big = 3e38f;
      for (int k = 0; k < 3;
           ++k) {  // three huge triangles through the unit cube, at different depths
        glm::vec3 a(0.2f * k, 0.1f, 0.3f), b = a, c = a;
        a[axis] = -big, b[axis] = big, c[(axis + 1) % 3] += 0.5f;
        g.add(a, b, c, 0);
      }
      RayBatch rays = random_rays(random_soup(1000, 91), 20000, 92, RayType::bounce);
      const HitBatch expected = brute_hits(g, rays);
      size_t huge_hits = 0;
      for (size_t i = 0; i < rays.size(); ++i)
        huge_hits += expected.hit(i) && expected.prim[i] >= ordinary;
      CHECK(huge_hits > 100);
      compare(g, rays, expected, "dacrt");
      compare(g, rays, expected, "dacrt-naive");
    }
}

TEST_CASE("the kept top levels serve every later call exactly, whatever its rays") {
  // The top is built once, on the first call's records, and later calls, chunks and forks only
  // reorder below it: batches of every size and kind in a row on one backend must all match brute.
  for (auto& c : cases()) {
    for (const char* top : {"1", "16", "256"}) {
      for (const char* name : {"dacrt", "dacrt-naive"}) {
        const std::string label = std::string(c.name) + ", top_triangles=" + top + ", " + name;
        INFO(label);
        Options o;
        o.set("top_triangles", top);
        o.set("task_rays", "64");
        // With 16, nodes of up to 8 rays send them through the kept top one at a time (walk).
        o.set("walk_rays", std::string(top) == "16" ? "8" : "0");
        auto b = Backend::create(name, c.geometry, o);
        uint64_t seed = 700;
        std::vector<RayBatch> batches;
        for (size_t n : {size_t(20000), size_t(1), size_t(3), size_t(100), size_t(5000)})
          batches.push_back(random_rays(c.geometry, n, ++seed, RayType::bounce));
        batches.push_back(surface_rays(c.geometry, 5000, ++seed, true));
        batches.push_back(axis_rays(c.geometry, 5000, ++seed));
        size_t wrong = 0;
        for (const RayBatch& rays : batches) {
          const HitBatch expected = brute_hits(c.geometry, rays);
          HitBatch got;
          std::vector<uint8_t> occluded(rays.size());
          b->intersect(rays, got);
          b->occluded(rays, occluded);
          for (size_t i = 0; i < rays.size(); ++i)
            wrong += got.prim[i] != expected.prim[i] || !same_bits(got.t[i], expected.t[i]) ||
                     occluded[i] != uint8_t(expected.hit(i));
        }
        CHECK(wrong == 0);
        // Every scene here has more than 256 triangles, and but one has distinct centres (its
        // triangles share one box centre: no split exists, so nothing can be kept).
        if (std::string(c.name) != "one box centre")
          CHECK(b->stats().kept_nodes > 0);
        else
          CHECK(b->stats().kept_nodes == 0);
      }
    }
  }
  // Two calls at once: the second finds the records in use and traces with its own, unkept.
  Geometry g = random_soup(3000, 31);
  auto b = Backend::create("dacrt", g);
  RayBatch r1 = random_rays(g, 20000, 32, RayType::bounce),
           r2 = random_rays(g, 20000, 33, RayType::bounce);
  const HitBatch e1 = brute_hits(g, r1), e2 = brute_hits(g, r2);
  for (int round = 0; round < 5; ++round) {
    HitBatch h1, h2;
    tbb::parallel_invoke([&] { b->intersect(r1, h1); }, [&] { b->intersect(r2, h2); });
    CHECK(h1.prim == e1.prim);
    CHECK(h2.prim == e2.prim);
  }
  Options none;
  none.set("top_triangles", "0");
  CHECK(Backend::create("dacrt", g, none)->stats().kept_nodes == 0);
}

TEST_CASE("dacrt counts the rays that enter its leaves") {
  // Ten triangles are one leaf: every ray of a call enters it, once. Above that, each ray enters
  // at least one leaf unless every box filters it out, and no more leaves than the call visits.
  for (const char* name : {"dacrt", "dacrt-naive"}) {
    INFO(name);
    Geometry small = random_soup(10, 51);
    RayBatch rays = random_rays(small, 5000, 52, RayType::bounce);
    auto b = Backend::create(name, small);
    HitBatch h;
    b->intersect(rays, h);
    b->intersect(rays, h);
    CHECK(b->stats().leaves == 2);
    CHECK(b->stats().leaf_rays == 2 * rays.size());
    Geometry g = random_soup(20000, 53);
    RayBatch more = random_rays(g, 20000, 54, RayType::bounce);
    auto c = Backend::create(name, g);
    c->intersect(more, h);
    const Stats s = c->stats();
    CHECK(s.leaf_rays > s.leaves);
    // A leaf tests each of its rays against each of its triangles, at most leaf_triangles (16)
    // unless the depth bound or a failed split stops earlier.
    CHECK(s.triangle_tests <= 64 * s.leaf_rays);
  }
}

TEST_CASE("a call with few rays pays for its rays, not for every triangle, once the top is kept") {
  // Counted, not timed: the triangle records a call bins. Without the kept top, a one-ray call
  // bins every triangle at the root and most of them again at each level near it; with it, only
  // the frontier nodes its ray reaches.
  Geometry g = random_soup(100000, 41);
  RayBatch big = random_rays(g, 50000, 42, RayType::bounce);
  RayBatch one = random_rays(g, 1, 43, RayType::bounce);
  uint64_t binned[2];
  for (int kept = 0; kept < 2; ++kept) {
    Options o;
    o.set("top_triangles", kept ? "1024" : "0");
    auto b = Backend::create("dacrt", g, o);
    HitBatch h;
    b->intersect(big, h);
    const Stats before = b->stats();
    for (int call = 0; call < 10; ++call) b->intersect(one, h);
    const Stats after = b->stats();
    binned[kept] = (after.binned - before.binned) / 10;
    MESSAGE("top_triangles=" << (kept ? 1024 : 0) << ": a one-ray call bins " << binned[kept]
                             << " triangle records and visits "
                             << (after.kept_nodes - before.kept_nodes) / 10 << " kept nodes");
    CHECK((after.kept_nodes > before.kept_nodes) == bool(kept));
  }
  CHECK(binned[0] >= 100000);
  CHECK(binned[1] <= 100000 / 10);
}

TEST_CASE("dacrt costs small leaves in whole blocks of 16 triangles: the Cornell box is one leaf") {
  // 32 triangles, rays from the walls: split in two halves of 16, most rays enter both, so one
  // leaf (two blocks) is cheaper; counting tests one by one (leaf_lanes=1, the paper's model) it
  // splits. Either way the hits are brute force's.
  const Geometry g = load_gltf(DACRT_SOURCE_DIR "/scenes/cornell-box.gltf").geometry;
  REQUIRE(g.size() == 32);
  const RayBatch rays = surface_rays(g, 20000, 71, true);
  HitBatch reference;
  Backend::create("brute", g)->intersect(rays, reference);
  Stats s[2];
  for (int i = 0; i < 2; ++i) {
    Options o;
    o.set("leaf_lanes", i == 0 ? "16" : "1");
    auto b = Backend::create("dacrt", g, o);
    HitBatch h;
    tbb::task_arena(1).execute([&] { b->intersect(rays, h); });
    s[i] = b->stats();
    CHECK(h.prim == reference.prim);
    CHECK(h.t == reference.t);
  }
  CHECK(s[0].nodes == 0);
  CHECK(s[0].leaves == 1);
  CHECK(s[1].nodes > 0);
  CHECK(s[0].triangle_tests > s[1].triangle_tests);  // more tests, in fewer leaves and blocks
  Options zero;
  zero.set("leaf_lanes", "0");
  CHECK_THROWS_WITH_AS(Backend::create("dacrt", g, zero), doctest::Contains("leaf_lanes"), Error);
}

TEST_CASE("dead rays spread over many blocks of a large batch: the live ones keep their hits") {
  // DACRT builds its ray records block by block (16384 rays) and moves the blocks together when
  // some rays are not live (NaN, empty interval): every ray must keep its own answer.
  const Geometry g = random_soup(500, 81);
  RayBatch rays = random_rays(g, 70000, 82, RayType::bounce);
  for (size_t i = 0; i < rays.size(); i += 7) rays.tmin[i] = std::nanf("");
  for (size_t i = 3; i < rays.size(); i += 11) rays.tmax[i] = -1.f;
  HitBatch reference, hits;
  Backend::create("brute", g)->intersect(rays, reference);
  for (const char* name : {"dacrt", "dacrt-naive"}) {
    INFO(name);
    Backend::create(name, g)->intersect(rays, hits);
    CHECK(hits.prim == reference.prim);
    CHECK(hits.t == reference.t);
    size_t dead_hits = 0, live_hits = 0;
    for (size_t i = 0; i < rays.size(); ++i)
      (i % 7 == 0 || i % 11 == 3 ? dead_hits : live_hits) += hits.prim[i] != HitBatch::miss;
    CHECK(dead_hits == 0);
    CHECK(live_hits > 2000);  // (3181 of the 52 000 live rays hit the soup)
  }
}
