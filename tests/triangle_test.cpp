// The shared ray/triangle test and the origin offset: watertightness on shared edges and vertices,
// no self-intersection of spawned rays, degenerate triangles, huge and tiny coordinates.
#include "dacrt/tracer/triangle.h"

#include <doctest/doctest.h>

#include <bit>

#include "test_geometry.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/tracer/triangle_block.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

size_t misses(const char* backend, const Geometry& g, const RayBatch& rays) {
  HitBatch hits;
  Backend::create(backend, g)->intersect(rays, hits);
  size_t n = 0;
  for (size_t i = 0; i < rays.size(); ++i) n += !hits.hit(i);
  return n;
}

// Rays from points inside a closed mesh must all hit it.
void check_closed_from_inside(const Geometry& g, const glm::vec3& center, float radius) {
  RayBatch rays;
  Pcg32 rng(5);
  for (int i = 0; i < 20000; ++i)
    rays.push(center + 0.25f * radius * random_in(rng, glm::vec3(-1.f), glm::vec3(1.f)),
              random_direction(rng), 0.f, INFINITY, uint32_t(i));
  for (const char* name : {"brute", "dacrt"}) {
    INFO(name);
    CHECK(misses(name, g, rays) == 0);
  }
}

}  // namespace

TEST_CASE("a jittered closed sphere is watertight from inside, near the origin and far from it") {
  for (glm::vec3 center : {glm::vec3(0.f), glm::vec3(1e5f, -1e5f, 1e5f)}) {
    INFO("center " << center.x);
    check_closed_from_inside(sphere(40, 80, center, 1.f, 0.3f, 7), center, 1.f);
    check_closed_from_inside(sphere(7, 9, center, 1.f, 0.5f, 8), center, 1.f);
  }
}

TEST_CASE("rays exactly through shared edges and vertices of a grid hit") {
  const int n = 16;
  Geometry g = quad_grid(n, 0.25f);  // edges and vertices at multiples of 0.25: exact in float
  RayBatch rays;
  uint32_t id = 0;
  for (int y = 0; y <= 4 * n; ++y)
    for (int x = 0; x <= 4 * n; ++x) {
      glm::vec3 p(x * 0.0625f, y * 0.0625f, 0.f);  // vertices, edge midpoints, quad diagonals
      if (p.x <= 0.f || p.y <= 0.f || p.x >= n * 0.25f || p.y >= n * 0.25f) continue;
      rays.push(p + glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), 0.f, INFINITY, id++);
      rays.push(p + glm::vec3(0.3f, -0.2f, 1), glm::vec3(-0.3f, 0.2f, -1), 0.f, INFINITY, id++);
    }
  for (const char* name : {"brute", "dacrt"}) {
    INFO(name << ", " << rays.size() << " rays");
    CHECK(misses(name, g, rays) == 0);
  }
}

TEST_CASE("a ray spawned from a hit never hits its own triangle again") {
  // Scale and placement: tiny, unit and large triangles near the origin, and far from it (where a
  // float's ulp is 1/128, so the triangles there must stay much larger than that). Ordinary
  // triangles and long slivers (where the test's t is least accurate).
  // Origins from spawn_point and offset_ray_origin, as the integrators spawn them; scales of
  // 1e±30 too, where the float normal and the float edge functions over- or underflow.
  for (bool thin : {false, true}) {
    for (auto [scale, offset] :
         {std::pair{1e-3f, glm::vec3(0.f)}, std::pair{1.f, glm::vec3(0.f)},
          std::pair{1e4f, glm::vec3(0.f)}, std::pair{1.f, glm::vec3(1e5f)},
          std::pair{1e3f, glm::vec3(-1e5f, 1e5f, 3e5f)}, std::pair{1e-30f, glm::vec3(0.f)},
          std::pair{1e30f, glm::vec3(0.f)}}) {
      Geometry g = thin ? slivers(500, 34) : random_soup(500, 31);
      for (size_t i = 0; i < g.size(); ++i)
        for (int c = 0; c < 3; ++c)
          for (int a = 0; a < 3; ++a) g.corners[i][c][a] = g.corners[i][c][a] * scale + offset[a];
      RayBatch rays = surface_rays(g, 20000, 32);
      // Re-derive each origin as a hit: trace towards the surface point, then spawn from it.
      auto b = Backend::create("dacrt", g);
      Pcg32 rng(33);
      RayBatch spawned;
      std::vector<uint32_t> from;
      RayBatch probe = rays;
      for (size_t i = 0; i < probe.size(); ++i) {
        glm::vec3 d = random_direction(rng);
        probe.set(i, rays.origin(i) - d * scale, d, 0.f, INFINITY, uint32_t(i));
      }
      HitBatch hits;
      b->intersect(probe, hits);
      for (size_t i = 0; i < probe.size(); ++i) {
        if (!hits.hit(i)) continue;
        uint32_t tri = hits.prim[i];
        const SpawnPoint p =
            spawn_point(g.vertex(tri, 0), g.vertex(tri, 1), g.vertex(tri, 2), hits.u[i], hits.v[i]);
        glm::vec3 n = g.unit_normal(tri);
        glm::vec3 d = random_direction(rng);
        if (glm::dot(d, n) < 0.f) n = -n;  // leave on the side the new ray goes to
        if (std::abs(glm::dot(d, n)) < 1e-3f) continue;
        spawned.push(offset_ray_origin(p, n), d, 0.f, INFINITY, uint32_t(spawned.size()));
        from.push_back(tri);
      }
      INFO(std::string(thin ? "slivers" : "soup") << ", scale " << scale);
      REQUIRE(spawned.size() > 5000);
      for (const char* name : {"dacrt", "brute"}) {
        HitBatch again;
        Backend::create(name, g)->intersect(spawned, again);
        size_t self = 0;
        for (size_t i = 0; i < spawned.size(); ++i) self += again.prim[i] == from[i];
        INFO(std::string(name) << (thin ? ", slivers" : ", soup") << ", scale " << scale
                               << ", offset " << offset.x << ", " << spawned.size() << " rays");
        CHECK(self == 0);
      }
    }
  }
}

TEST_CASE("degenerate triangles never hit, and barycentrics and t are right") {
  Ray r = Ray::shear(glm::vec3(0.25f, 0.25f, 1.f), glm::vec3(0, 0, -1));
  TriangleHit h;
  glm::vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  REQUIRE(intersect_triangle(r, a, b, c, 0.f, INFINITY, h));
  CHECK(h.t == 1.f);
  CHECK(h.u == doctest::Approx(0.25f));
  CHECK(h.v == doctest::Approx(0.25f));
  // Back faces hit as well.
  CHECK(intersect_triangle(r, a, c, b, 0.f, INFINITY, h));
  // Outside [tmin, tmax].
  CHECK_FALSE(intersect_triangle(r, a, b, c, 0.f, 0.99f, h));
  CHECK_FALSE(intersect_triangle(r, a, b, c, 1.01f, 2.f, h));
  // Degenerate: a point, a segment, collinear corners, a triangle seen edge-on.
  CHECK_FALSE(intersect_triangle(r, a, a, a, 0.f, INFINITY, h));
  CHECK_FALSE(intersect_triangle(r, a, b, b, 0.f, INFINITY, h));
  CHECK_FALSE(intersect_triangle(r, a, b, 2.f * b, 0.f, INFINITY, h));
  CHECK_FALSE(intersect_triangle(r, glm::vec3(0.25f, 0, 0), glm::vec3(0.25f, 1, 0),
                                 glm::vec3(0.25f, 0, 2), 0.f, INFINITY, h));
  Geometry g;
  g.add(a, a, a, 0);
  g.add(a, b, 2.f * b, 0);
  g.add(glm::vec3(0.25f, 0.25f, 0), glm::vec3(0.25f, 0.25f, 0), glm::vec3(0.25f, 0.25f, 0), 0);
  RayBatch rays;
  rays.push(glm::vec3(0.25f, 0.25f, 1.f), glm::vec3(0, 0, -1), 0.f, INFINITY, 0);
  rays.push(glm::vec3(0.5f, 0.f, 1.f), glm::vec3(0, 0, -1), 0.f, INFINITY, 1);
  for (const char* name : {"brute", "dacrt"}) {
    HitBatch hits;
    Backend::create(name, g)->intersect(rays, hits);
    CHECK_FALSE(hits.hit(0));
    CHECK_FALSE(hits.hit(1));
  }
}

TEST_CASE("huge and tiny coordinates") {
  for (float s : {1e-6f, 1e-3f, 1e3f, 1e6f}) {
    Geometry g = quad_grid(8, s);
    RayBatch rays;
    Pcg32 rng(9);
    for (int i = 0; i < 2000; ++i) {
      glm::vec3 p = random_in(rng, glm::vec3(0.f), glm::vec3(8.f * s, 8.f * s, 0.f));
      rays.push(p + glm::vec3(0, 0, s), glm::vec3(0.1f, -0.1f, -1.f), 0.f, INFINITY, uint32_t(i));
    }
    for (const char* name : {"brute", "dacrt"}) {
      HitBatch hits;
      Backend::create(name, g)->intersect(rays, hits);
      size_t misses = 0;
      for (size_t i = 0; i < rays.size(); ++i) {
        glm::vec3 p = rays.origin(i) + hits.t[i] * rays.direction(i);
        bool inside = p.x > 0 && p.y > 0 && p.x < 8 * s && p.y < 8 * s;
        misses += inside && !hits.hit(i);
        if (hits.hit(i)) CHECK(hits.t[i] == doctest::Approx(s).epsilon(1e-5));
      }
      INFO(name << " scale " << s);
      CHECK(misses == 0);
    }
  }
}

TEST_CASE("overlapping coplanar triangles: the lower index wins, in every backend") {
  Geometry g;
  for (int i = 0; i < 50; ++i)
    g.add(glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), uint32_t(i));
  RayBatch rays;
  Pcg32 rng(3);
  for (int i = 0; i < 5000; ++i)
    rays.push(glm::vec3(0.3f * rng.uniform(), 0.3f * rng.uniform(), 1.f), glm::vec3(0, 0, -1), 0.f,
              INFINITY, uint32_t(i));
  for (const char* name : {"brute", "dacrt", "dacrt-naive"}) {
    HitBatch hits;
    Backend::create(name, g)->intersect(rays, hits);
    size_t wrong = 0;
    for (size_t i = 0; i < rays.size(); ++i) wrong += hits.prim[i] != 0;
    INFO(name);
    CHECK(wrong == 0);
  }
}

TEST_CASE("100 000 triangles with one box centre: the recursion ends and the answer is exact") {
  Geometry g = one_box_center(100000, 77);
  RayBatch rays = random_rays(g, 300, 78, RayType::bounce);
  HitBatch expected, got;
  Backend::create("brute", g)->intersect(rays, expected);
  for (const char* name : {"dacrt", "dacrt-naive"}) {
    INFO(name);
    auto b = Backend::create(name, g);
    b->intersect(rays, got);
    size_t mismatches = 0;
    for (size_t i = 0; i < rays.size(); ++i)
      mismatches += got.prim[i] != expected.prim[i] || got.t[i] != expected.t[i];
    CHECK(mismatches == 0);
    CHECK(b->stats().nodes == 0);  // nothing to bin apart: one leaf
  }
}

TEST_CASE("watertight at every batch size, for every backend of ours") {
  Geometry g = sphere(16, 32, glm::vec3(0.f), 1.f, 0.4f, 11);
  Pcg32 rng(12);
  for (size_t n : {size_t(1), size_t(2), size_t(3), size_t(15), size_t(16), size_t(17), size_t(999),
                   size_t(1000), size_t(1001), size_t(5000), size_t(40000)}) {
    RayBatch rays;
    for (size_t i = 0; i < n; ++i)
      rays.push(0.2f * random_in(rng, glm::vec3(-1.f), glm::vec3(1.f)), random_direction(rng), 0.f,
                INFINITY, uint32_t(i));
    for (const char* name : {"brute", "dacrt", "dacrt-naive"}) {
      INFO(name << ", " << n << " rays");
      CHECK(misses(name, g, rays) == 0);
    }
  }
}

TEST_CASE(
    "the vector triangle filters (8 and 16 lanes) keep every lane the scalar test accepts, and "
    "their sure lanes are its hits") {
  if (!avx2_available()) {
    MESSAGE("skipped: this CPU has no AVX2, so leaves use the scalar test only");
    return;
  }
  struct Case {
    const char* name;
    Geometry g;
    RayBatch rays;
  };
  std::vector<Case> cases;
  {
    Geometry soup = random_soup(400, 91);
    RayBatch r = random_rays(soup, 3000, 92, RayType::bounce);
    cases.push_back({"soup", soup, r});
  }
  {
    Geometry grid = quad_grid(8);  // rays through its shared edges and vertices
    cases.push_back({"grid, axis-parallel", grid, axis_rays(grid, 3000, 93)});
    cases.push_back({"grid, from the surface", grid, surface_rays(grid, 3000, 94)});
    // From 2^-30 to 2^-6 off the plane, both ways along the ray (tmin -inf): t crosses the float
    // test's error bound, where float and double t differ, so a vector bound that is not the
    // scalar one gives sure lanes with the wrong t.
    RayBatch near;
    near.type = RayType::bounce;
    Pcg32 rng(97);
    for (uint32_t i = 0; i < 3000; ++i) {
      const uint32_t tri = rng.below(uint32_t(grid.size()));
      float u = rng.uniform(), v = rng.uniform();
      if (u + v > 1.f) u = 1.f - u, v = 1.f - v;
      const glm::vec3 p = grid.vertex(tri, 0) + u * (grid.vertex(tri, 1) - grid.vertex(tri, 0)) +
                          v * (grid.vertex(tri, 2) - grid.vertex(tri, 0));
      const float off = std::ldexp(rng.uniform() < 0.5f ? -1.f : 1.f, -6 - int(rng.below(25)));
      near.push(p + glm::vec3(0.f, 0.f, off), random_direction(rng), -INFINITY, INFINITY, i);
    }
    cases.push_back({"grid, near the surface", grid, near});
  }
  {
    Geometry thin = slivers(400, 95);
    cases.push_back({"slivers", thin, surface_rays(thin, 3000, 96, true)});
  }
  // The lanes' answers with AVX2 and with AVX-512.
  for (const Case& c : cases)
    for (const int width : {8, 16})
      for (const bool wide : {false, true}) {
        if (wide && (width == 8 || !avx512_available())) continue;
        if (!wide && !avx2_available()) continue;
        INFO(std::string(c.name) << ", blocks of " << width << (wide ? ", AVX-512" : ", AVX2"));
        size_t accepted = 0, candidates = 0, dropped = 0, tested = 0, sure = 0, wrong_sure = 0;
        size_t exact = 0, wrong_exact = 0;
        for (size_t j0 = 0; j0 < c.g.size(); j0 += width) {
          uint32_t ids[16];
          const int n = int(std::min<size_t>(width, c.g.size() - j0));
          for (int l = 0; l < n; ++l) ids[l] = uint32_t(j0 + l);
          TriangleBlock block;
          block.load(c.g, ids, n);
          for (size_t i = 0; i < c.rays.size(); ++i) {
            const Ray ray = Ray::shear(c.rays, i);
            BlockHits bh{};
            if (wide)
              block_hits_avx512(block, ray, c.rays.tmin[i], c.rays.tmax[i], bh);
            else
              block_hits_avx2(block, ray, c.rays.tmin[i], c.rays.tmax[i], bh);
            CHECK((bh.sure & bh.unsure) == 0u);
            CHECK((bh.sure & bh.exact) == 0u);
            CHECK((bh.exact & bh.unsure) == 0u);
            const uint32_t mask = bh.sure | bh.exact | bh.unsure;
            if (wide)
              CHECK(block_candidates_avx512(block, ray, c.rays.tmin[i], c.rays.tmax[i]) == mask);
            for (int l = 0; l < n; ++l) {
              TriangleHit h;
              const bool hit =
                  intersect_triangle(ray, c.g.vertex(ids[l], 0), c.g.vertex(ids[l], 1),
                                     c.g.vertex(ids[l], 2), c.rays.tmin[i], c.rays.tmax[i], h);
              const bool kept = (mask >> l) & 1u;
              accepted += hit, candidates += kept, dropped += hit && !kept, ++tested;
              // A sure lane is the scalar test's hit, bit for bit.
              if (bh.sure >> l & 1u) {
                ++sure;
                const float u = bh.e1[l] / bh.det[l], v = bh.e2[l] / bh.det[l];
                wrong_sure += !hit ||
                              std::bit_cast<uint32_t>(h.t) != std::bit_cast<uint32_t>(bh.t[l]) ||
                              std::bit_cast<uint32_t>(h.u) != std::bit_cast<uint32_t>(u) ||
                              std::bit_cast<uint32_t>(h.v) != std::bit_cast<uint32_t>(v);
              }
              // An exact lane's answer (t in double) is the scalar test's, bit for bit.
              if (bh.exact >> l & 1u) {
                ++exact;
                TriangleHit e;
                const bool exact_hit = exact_lane_hit(
                    bh, l, ray, c.g.vertex(ids[l], 0), c.g.vertex(ids[l], 1),
                    c.g.vertex(ids[l], 2), c.rays.tmin[i], c.rays.tmax[i], e);
                wrong_exact += exact_hit != hit ||
                               (hit && (std::bit_cast<uint32_t>(h.t) != std::bit_cast<uint32_t>(e.t) ||
                                        std::bit_cast<uint32_t>(h.u) != std::bit_cast<uint32_t>(e.u) ||
                                        std::bit_cast<uint32_t>(h.v) != std::bit_cast<uint32_t>(e.v)));
              }
            }
            CHECK((mask >> n) == 0u);  // unused lanes are never reported
          }
        }
        CHECK(dropped == 0);
        CHECK(accepted > 0);
        CHECK(wrong_sure == 0);
        CHECK(wrong_exact == 0);
        // Rays leaving a surface meet their own triangle at t within its error of 0: exact lanes.
        const std::string name = c.name;
        if (name == "grid, from the surface" || name == "grid, near the surface") CHECK(exact > 0);
        // On general triangles most hits skip the scalar test.
        if (std::string(c.name) == "soup") CHECK(sure > accepted * 9 / 10);
        INFO("accepted " << accepted << ", candidates " << candidates << ", tested " << tested);
        // A filter, not a pass-through: on general triangles almost every candidate is a hit.
        // (Rays in the grid's plane see every triangle edge-on, all edge functions zero: all
        // candidates.)
        if (std::string(c.name) == "soup") CHECK(candidates < accepted + tested / 100);
      }
}

// An edge function that rounds to 0 in float but not in double: the scalar test decides in double
// (here: the origin is just outside, a miss), so the lane must go to it, not be taken as sure.
TEST_CASE("a lane whose edge function rounds to zero is never a sure hit of the vector test") {
  if (!avx2_available()) {
    MESSAGE("skipped: this CPU has no AVX2");
    return;
  }
  const float e = 0x1p-23f;
  Geometry g;
  // The sheared corners (ray along +z from z = -1): e0 = cx·by − cy·bx = −2^-46 exactly, 0 in
  // float; e1 and e2 are positive.
  g.add({-1.f, 1.f, 1.f}, {1.f, 1.f + e, 1.f}, {-(1.f + e), -(1.f + 2.f * e), 1.f}, 0);
  const Ray r = Ray::shear(glm::vec3(0.f, 0.f, -1.f), glm::vec3(0.f, 0.f, 1.f));
  TriangleHit h;
  CHECK_FALSE(
      intersect_triangle(r, g.vertex(0, 0), g.vertex(0, 1), g.vertex(0, 2), 0.f, INFINITY, h));
  const uint32_t ids[1] = {0};
  TriangleBlock block;
  block.load(g, ids, 1);
  for (const bool wide : {false, true}) {
    if (wide && !avx512_available()) continue;
    INFO((wide ? "AVX-512" : "AVX2"));
    BlockHits bh{};
    if (wide)
      block_hits_avx512(block, r, 0.f, INFINITY, bh);
    else
      block_hits_avx2(block, r, 0.f, INFINITY, bh);
    CHECK(bh.sure == 0u);
    CHECK(bh.exact == 0u);
    CHECK(bh.unsure == 1u);
  }
}

// A ray lying in the plane of two triangles (the grazing plane of tests/stress.h, plane ray 1019):
// the sheared triangles are segments, their edge functions and det rounding noise, and the double
// t of intersect_triangle was their ratio: 0.57 for the triangle wholly behind the origin, which
// DACRT's box test then culled while brute force kept it. t must lie where the ray is inside the
// triangle's box.
TEST_CASE("a ray in a triangle's plane never hits it at a t outside the triangle's box") {
  const glm::vec3 o(0.f), d(-70.f, 52.f, -39.f);
  Geometry g;
  g.add({40.f, -40.f, 30.f}, {50.f, -32.f, 24.f}, {40.f, -32.f, 24.f}, 0);     // behind the origin
  g.add({-60.f, 32.f, -24.f}, {-50.f, 40.f, -30.f}, {-60.f, 40.f, -30.f}, 0);  // ahead, t 0.76
  const Ray r = Ray::shear(o, d);
  TriangleHit h;
  CHECK_FALSE(
      intersect_triangle(r, g.vertex(0, 0), g.vertex(0, 1), g.vertex(0, 2), 0.f, INFINITY, h));
  RayBatch rays;
  rays.push(o, d, 0.f, INFINITY, 0);
  HitBatch expect;
  Backend::create("brute", g)->intersect(rays, expect);
  CHECK(expect.prim[0] == 1);
  for (const char* name : {"dacrt", "dacrt-naive"}) {
    HitBatch got;
    Backend::create(name, g)->intersect(rays, got);
    INFO(name);
    CHECK(got.prim[0] == expect.prim[0]);
    CHECK(got.t[0] == expect.t[0]);
  }
}

// Normals and areas at any scale: the float cross product of the edges overflows beyond ~1e19 and
// underflows below ~1e-19 (NaN normals in shading, zero or infinite emitter areas); the edges of
// a triangle spanning ±2e38 are infinite themselves.
TEST_CASE("unit normals and areas of tiny, huge and FLT_MAX-wide triangles") {
  const glm::dvec3 tilt = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  for (const double scale : {1e-36, 1e-30, 1e-20, 1.0, 1e20, 1e30, 1e38}) {
    // A right triangle of legs `scale` in the plane of normal `tilt`.
    const glm::dvec3 t1 = glm::normalize(glm::cross(tilt, glm::dvec3(1, 0, 0)));
    const glm::dvec3 t2 = glm::cross(tilt, t1);
    Geometry g;
    g.add(glm::vec3(-scale * t1), glm::vec3(scale * t1), glm::vec3(scale * t2), 0);
    INFO("scale " << scale);
    const glm::vec3 n = g.unit_normal(0);
    CHECK(std::abs(glm::length(glm::dvec3(n)) - 1.0) < 1e-6);
    CHECK(glm::dot(glm::dvec3(n), tilt) > 1.0 - 1e-6);
    CHECK(g.area(0) == doctest::Approx(scale * scale).epsilon(1e-5));
  }
  Geometry g;
  g.add({-3e38f, -3e38f, -3e38f}, {3e38f, -3e38f, 3e38f}, {0.f, 3e38f, 0.f}, 0);
  REQUIRE(!std::isfinite(glm::length(g.normal(0))));
  const glm::dvec3 expected = glm::normalize(glm::cross(glm::dvec3(6, 0, 6), glm::dvec3(3, 6, 3)));
  CHECK(glm::dot(glm::dvec3(g.unit_normal(0)), expected) > 1.0 - 1e-6);
  CHECK(g.area(0) == doctest::Approx(0.5 * glm::length(glm::cross(glm::dvec3(6e38, 0, 6e38),
                                                                  glm::dvec3(3e38, 6e38, 3e38))))
                         .epsilon(1e-5));
}
