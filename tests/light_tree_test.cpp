// The light tree (integrators/light_tree.h) and LightSampler's choice by it: from any point, the
// probabilities pmf() gives sum to 1 and are the ones the choice realises (exhaustively over every
// k of a small range, and by χ² over the path's numbers), on small random scenes; and a scene of
// many lamps converges to the same image by the tree as by power.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "chi2.h"
#include "dacrt/integrators/light_sampling.h"
#include "dacrt/integrators/lights.h"
#include "dacrt/util/random.h"
#include "lit_scene.h"
#include "render_check.h"

using namespace dacrt;

namespace {

glm::vec3 in_box(Pcg32& rng, float half) {
  return {half * (2.f * rng.uniform() - 1.f), half * (2.f * rng.uniform() - 1.f),
          half * (2.f * rng.uniform() - 1.f)};
}

glm::vec3 unit(Pcg32& rng) {
  const float z = 2.f * rng.uniform() - 1.f, phi = 6.2831853f * rng.uniform();
  const float r = std::sqrt(std::max(0.f, 1.f - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// `triangles` emissive triangles of random size, place, facing and brightness (some two-sided,
// some black), and a point, a spot and a directional light.
Scene random_lamps(Pcg32& rng, int triangles) {
  Scene scene;
  for (int m = 0; m < 4; ++m) {
    Material lamp = Material::lambert(glm::vec3(0.f));
    lamp.emission = m == 3 ? glm::vec3(0.f) : glm::vec3(0.5f + 3.f * rng.uniform(), 1.f, 2.f);
    lamp.double_sided = m == 1;
    scene.materials.push_back(lamp);
  }
  for (int t = 0; t < triangles; ++t) {
    const glm::vec3 c = in_box(rng, 4.f);
    const float size = 0.05f + 0.5f * rng.uniform() * rng.uniform();
    scene.geometry.add(c + size * unit(rng), c + size * unit(rng), c + size * unit(rng),
                       uint32_t(rng.uniform() * 4.f) % 4);
  }
  PunctualLight point, spot, sun;
  point.position = in_box(rng, 3.f), point.intensity = glm::vec3(2.f);
  spot.type = PunctualLight::Type::spot, spot.position = in_box(rng, 3.f);
  spot.direction = unit(rng), spot.cos_inner = 0.9f, spot.cos_outer = 0.6f;
  spot.intensity = glm::vec3(5.f);
  sun.type = PunctualLight::Type::directional, sun.direction = unit(rng);
  sun.intensity = glm::vec3(0.3f);
  scene.lights = {point, spot, sun};
  return scene;
}

// A shading point: anywhere in or around the lamps, with a normal or (a transmissive surface)
// none.
LightContext random_context(Pcg32& rng) {
  LightContext at{in_box(rng, 6.f), unit(rng)};
  if (rng.uniform() < 0.25f) at.n = glm::vec3(0.f);
  return at;
}

}  // namespace

TEST_CASE("light tree: every k of a range picks the leaf whose units() it counts") {
  Pcg32 rng(7);
  for (int scene_index = 0; scene_index < 6; ++scene_index) {
    std::vector<LightTree::Bounds> leaves;
    const int n = 2 + scene_index * 7;
    for (int i = 0; i < n; ++i) {
      LightTree::Bounds b;
      b.lo = in_box(rng, 4.f), b.hi = b.lo + 0.3f * rng.uniform() * glm::vec3(1.f);
      b.power = 0.01f + rng.uniform() * rng.uniform();
      b.w = unit(rng);
      b.cos_o = i % 5 == 0 ? -1.f : 1.f;
      b.two_sided = i % 3 == 0;
      leaves.push_back(b);
    }
    LightTree tree(leaves);
    for (int point = 0; point < 20; ++point) {
      const LightContext at = random_context(rng);
      tree.set_vectorised(point % 2 == 0);  // (where the CPU has AVX2; lane by lane else)
      const uint32_t range = 1u << (6 + point % 7);
      std::vector<uint32_t> count(size_t(n), 0);
      for (uint32_t k = 0; k < range; ++k) {
        const LightTree::Pick p = tree.sample(k, range, at);
        ++count[p.entry];
        if (p.units != tree.units(p.entry, range, at)) FAIL_CHECK("sample's units differ");
      }
      uint64_t sum = 0;
      for (int e = 0; e < n; ++e) {
        sum += tree.units(uint32_t(e), range, at);
        CHECK(count[size_t(e)] == tree.units(uint32_t(e), range, at));
      }
      CHECK(sum == range);
    }
  }
}

TEST_CASE("light tree sampler: pmf sums to 1 from any point and the picks follow it (χ²)") {
  Pcg32 rng(11);
  int tested = 0;
  for (int scene_index = 0; scene_index < 5; ++scene_index) {
    const Scene scene = random_lamps(rng, 3 + 11 * scene_index);
    const LightSampler lights(scene, scene.lights, LightPicking::tree);
    REQUIRE(lights.tree());
    const size_t n = lights.entries();
    for (int point = 0; point < 8; ++point) {
      const LightContext at = random_context(rng);
      double sum = 0.0;
      std::vector<double> pmf(n);
      for (size_t e = 0; e < n; ++e) sum += pmf[e] = lights.entry_pmf(e, at);
      CHECK(sum == 1.0);  // (multiples of 2⁻²⁴: exact)
      // The emissive triangles' pmf() is their entries'.
      for (size_t e = 0; e < lights.triangles(); ++e)
        CHECK(lights.pmf(lights.triangle(e), at) == float(pmf[e]));
      constexpr int samples = 100000;
      std::vector<double> observed(n, 0.0);
      for (int s = 0; s < samples; ++s) {
        const LightSampler::Choice c = lights.pick(rng.uniform(), at);
        observed[c.entry] += 1.0;
        if (c.pmf != float(pmf[c.entry])) FAIL_CHECK("a pick's pmf is not pmf()'s");
        if (!(c.pmf > 0.f)) FAIL_CHECK("an entry of pmf 0 was picked");
      }
      // Pearson's χ², cells expecting fewer than 5 pooled.
      double chi2 = 0.0, pooled_expected = 0.0, pooled_observed = 0.0;
      int cells = 0;
      for (size_t e = 0; e < n; ++e) {
        const double expected = pmf[e] * samples;
        if (expected < 5.0) {
          pooled_expected += expected, pooled_observed += observed[e];
          continue;
        }
        chi2 += (observed[e] - expected) * (observed[e] - expected) / expected, ++cells;
      }
      if (pooled_expected >= 5.0)
        chi2 += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) /
                pooled_expected,
            ++cells;
      if (cells < 2) continue;
      ++tested;
      const double p = test::chi2_survival(chi2, cells - 1);
      INFO("scene " << scene_index << ", point " << point << ": χ² " << chi2 << " over " << cells
                    << " cells");
      CHECK(p > 0.01 / 40);  // Šidák-ish: 40 tests at 1 %
    }
  }
  CHECK(tested > 30);
}

TEST_CASE("light sampler: auto picks by power below the threshold and by the tree from it") {
  Pcg32 rng(3);
  const Scene few = random_lamps(rng, 2);  // (with three punctual lights: below the threshold)
  CHECK(!LightSampler(few, few.lights).tree());
  CHECK(LightSampler(few, few.lights, LightPicking::tree).tree());
  const Scene many = random_lamps(rng, 2 * int(LightSampler::tree_threshold));
  CHECK(LightSampler(many, many.lights).tree());
  CHECK(!LightSampler(many, many.lights, LightPicking::power).tree());
}

TEST_CASE("light sampling: beside a sampled environment auto chooses as without one") {
  Pcg32 rng(4);
  const Scene few = random_lamps(rng, 2);
  const Scene many = random_lamps(rng, 2 * int(LightSampler::tree_threshold));
  Image sky(1, 1);
  sky.rgb = {0.5f, 0.5f, 0.5f};
  const EnvironmentMap map(sky, "sky");
  CHECK(LightSampling(many, many.lights, nullptr).by_point());
  CHECK(LightSampling(many, many.lights, &map).by_point());
  CHECK(!LightSampling(few, few.lights, &map).by_point());
  CHECK(!LightSampling(many, many.lights, &map, TriangleSampling::solid_angle_if_large,
                       LightPicking::power)
             .by_point());
  // The map keeps its half of the shadow rays: the emitters' pmf is the tree's, halved.
  const LightSampling with_map(many, many.lights, &map);
  const LightContext at{glm::vec3(0.5f), glm::vec3(0.f, 0.f, 1.f)};
  double sum = 0.0;
  for (size_t e = 0; e < with_map.sampler().triangles(); ++e) {
    const uint32_t tri = with_map.sampler().triangle(e);
    const Geometry& g = many.geometry;
    const float pdf = with_map.emitter_pdf(glm::vec3(0.5f), tri, 1.f, 1.f, g.area(tri), at);
    sum += with_map.sampler().pmf(tri, at);
    if (pdf > 0.f && with_map.sampled_solid_angle(glm::vec3(0.5f), tri) == 0.0)
      CHECK(pdf == doctest::Approx(0.5 * with_map.sampler().pmf(tri, at) / g.area(tri)));
  }
  CHECK(sum > 0.0);
}

namespace {

// Emitters of every kind the tree bounds: triangles' boxes, points (an empty box), spots (a cone
// and a falloff), one- and two-sided, some of power near the least float.
std::vector<LightTree::Bounds> random_bounds(Pcg32& rng, int n) {
  std::vector<LightTree::Bounds> leaves;
  for (int i = 0; i < n; ++i) {
    LightTree::Bounds b;
    b.lo = in_box(rng, 4.f);
    b.hi = b.lo + (i % 4 == 0 ? glm::vec3(0.f) : 0.4f * rng.uniform() * glm::vec3(1.f, 0.5f, 2.f));
    b.power = i % 9 == 0 ? 1e-37f : 0.01f + rng.uniform() * rng.uniform();
    b.w = unit(rng);
    b.cos_o = i % 5 == 0 ? -1.f : i % 5 == 1 ? 0.8f : 1.f;
    b.cos_e = i % 7 == 0 ? 0.9f : 0.f;
    b.two_sided = i % 3 == 0;
    leaves.push_back(b);
  }
  return leaves;
}

}  // namespace

TEST_CASE("light tree: eight children at once (AVX2) give lane by lane's bits") {
  LightTree probe;
  probe.set_vectorised(true);
  if (!probe.vectorised()) {
    MESSAGE("no AVX2 on this CPU: one way only");
    return;
  }
  Pcg32 rng(21);
  size_t differ = 0, compared = 0, positive = 0;
  for (int scene_index = 0; scene_index < 6; ++scene_index) {
    const std::vector<LightTree::Bounds> leaves = random_bounds(rng, 3 + 40 * scene_index);
    LightTree tree(leaves);
    for (int point = 0; point < 200; ++point) {
      LightContext at = random_context(rng);
      // Some points on an emitter's centre or corner, inside its box or on its plane.
      const LightTree::Bounds& b = leaves[size_t(point) % leaves.size()];
      if (point % 4 == 1) at.p = 0.5f * (b.lo + b.hi);
      if (point % 4 == 2) at.p = b.lo;
      for (uint32_t node = 0; node < tree.nodes(); ++node) {
        float lanes[LightTree::width], simd[LightTree::width];
        tree.set_vectorised(false);
        tree.child_importance(node, at, lanes);
        tree.set_vectorised(true);
        tree.child_importance(node, at, simd);
        for (int i = 0; i < LightTree::width; ++i, ++compared) {
          differ += std::memcmp(&lanes[i], &simd[i], sizeof(float)) != 0;
          positive += lanes[i] > 0.f;
        }
      }
      for (const uint32_t range : {1u << 24, 1000u, 7u}) {
        for (uint32_t e = 0; e < leaves.size(); ++e) {
          tree.set_vectorised(false);
          const uint32_t a = tree.units(e, range, at);
          tree.set_vectorised(true);
          if (a != tree.units(e, range, at)) ++differ;
        }
        for (uint32_t k = 0; k < range; k += range / 97 + 1) {
          tree.set_vectorised(false);
          const LightTree::Pick a = tree.sample(k, range, at);
          tree.set_vectorised(true);
          const LightTree::Pick b = tree.sample(k, range, at);
          if (a.entry != b.entry || a.units != b.units) ++differ;
        }
      }
    }
  }
  CHECK(differ == 0);
  CHECK(positive > compared / 4);
}

TEST_CASE("light tree: a node has up to eight children, so thousands of emitters take few levels") {
  std::vector<LightTree::Bounds> grid;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      LightTree::Bounds b;
      b.lo = glm::vec3(float(i), float(j), 2.f), b.hi = b.lo + glm::vec3(0.1f, 0.1f, 0.f);
      b.power = 1.f, b.w = glm::vec3(0.f, 0.f, -1.f);
      grid.push_back(b);
    }
  const LightTree tree(grid);
  CHECK(tree.size() == 4096);
  CHECK(tree.depth() <= 4);  // (binary: 12 levels at least)
  CHECK(tree.nodes() < 4096 / 2);  // (binary: 4095 inner nodes)
}

TEST_CASE("light tree: a child of positive importance gets a unit, one of none gets none") {
  std::vector<LightTree::Bounds> leaves(4);
  for (LightTree::Bounds& b : leaves) b.w = glm::vec3(0.f, 0.f, -1.f), b.power = 1.f;
  leaves[0].lo = leaves[0].hi = glm::vec3(0.f, 0.f, 1.f);  // overhead
  leaves[1].lo = leaves[1].hi = glm::vec3(3e3f, 0.f, 1.f), leaves[1].power = 1e-20f;  // far, dim
  leaves[2].lo = leaves[2].hi = glm::vec3(0.f, 1.f, 1.f), leaves[2].w = glm::vec3(0.f, 0.f, 1.f);
  leaves[3].lo = leaves[3].hi = glm::vec3(0.f, -1.f, -1.f);  // below the point's horizon
  LightTree tree(leaves);
  for (const bool simd : {false, true}) {
    tree.set_vectorised(simd);
    const LightContext at{glm::vec3(0.f), glm::vec3(0.f, 0.f, 1.f)};
    CHECK(LightTree::importance(leaves[1], at) > 0.f);
    CHECK(tree.units(1, 1u << 24, at) == 1);
    CHECK(tree.units(2, 1u << 24, at) == 0);  // facing away
    CHECK(tree.units(3, 1u << 24, at) == 0);
    CHECK(tree.units(0, 1u << 24, at) == (1u << 24) - 1);
    CHECK(tree.units(1, 1, at) == 0);  // (a range of one unit: the greatest takes it)
    CHECK(tree.units(0, 1, at) == 1);
    // From where none can light: equal parts.
    const LightContext under{glm::vec3(0.f, 0.f, 5.f), glm::vec3(0.f, 0.f, 1.f)};
    uint32_t sum = 0;
    for (uint32_t e = 0; e < 4; ++e) {
      CHECK(tree.units(e, 1000, under) >= 1000 / 4);
      sum += tree.units(e, 1000, under);
    }
    CHECK(sum == 1000);
  }
}

namespace {

// A floor, half Lambert and half glossy metal (where BSDF sampling finds the lamps and MIS
// weighs what it finds), under a grid of small lamps of varied power, some facing sideways; with
// a glossy box, so paths bounce.
Scene lamp_grid() {
  Scene scene = test::lit_plane();
  scene.materials[0] = Material::lambert(glm::vec3(0.6f));
  Material metal;
  metal.base_color = glm::vec3(0.8f), metal.roughness = 0.1f;
  scene.materials.push_back(metal);
  scene.geometry.material[1] = 1;
  const Geometry box = test::inward_box();
  for (size_t t = 0; t < box.size(); ++t) {
    auto v = [&](int k) { return 0.4f * box.vertex(t, k) + glm::vec3(0.2f, -0.3f, 0.2f); };
    scene.geometry.add(v(0), v(2), v(1), 1);
  }
  Pcg32 rng(5);
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      Material lamp = Material::lambert(glm::vec3(0.f));
      lamp.emission = glm::vec3(0.5f + 8.f * rng.uniform() * rng.uniform());
      lamp.double_sided = (i + j) % 7 == 0;
      const uint32_t m = uint32_t(scene.materials.size());
      scene.materials.push_back(lamp);
      const glm::vec3 c(-2.f + 0.4f * float(i), -2.f + 0.4f * float(j), 0.6f + rng.uniform());
      const glm::vec3 n = (i * j) % 5 == 0 ? glm::vec3(0.6f, 0.f, 0.8f) : glm::vec3(0.f, 0.f, -1.f);
      const glm::vec3 a = glm::normalize(glm::cross(n, glm::vec3(0.3f, 1.f, 0.2f)));
      const glm::vec3 b = glm::cross(n, a);
      const float s = 0.12f;
      // Facing n: (a, b, n) right-handed, so a × b = n; the triangles are wound to match.
      scene.geometry.add(c - s * a - s * b, c + s * a - s * b, c + s * a + s * b, m);
      scene.geometry.add(c - s * a - s * b, c + s * a + s * b, c - s * a + s * b, m);
    }
  return scene;
}

}  // namespace

TEST_CASE("light tree: a floor under 100 lamps converges to the image picking by power gives") {
  const Scene scene = lamp_grid();
  RenderSettings s;
  s.width = s.height = 32;
  s.spp = 512;
  s.environment = glm::vec3(0.f);
  s.light_sampler = LightPicking::power;
  const test::Result power = test::render(scene, s);
  s.light_sampler = LightPicking::tree;
  const test::Result tree = test::render(scene, s);
  CHECK(power.stats.light_sampler == "power");
  CHECK(tree.stats.light_sampler == "tree");
  // Pixel by pixel, and the image means, within their joint noise.
  double a = 0.0, b = 0.0, var = 0.0;
  size_t outliers = 0;
  for (size_t p = 0; p < power.film.pixels(); ++p) {
    const glm::dvec2 x = power.film.mean_and_error(p), y = tree.film.mean_and_error(p);
    a += x.x, b += y.x, var += x.y * x.y + y.y * y.y;
    if (std::abs(x.x - y.x) > 5.0 * std::sqrt(x.y * x.y + y.y * y.y) + 1e-6) ++outliers;
  }
  const double n = double(power.film.pixels()), error = std::sqrt(var) / n;
  INFO("by power " << a / n << ", by the tree " << b / n << " ± " << error);
  CHECK(outliers == 0);
  CHECK(std::abs(a - b) / n <= 4.0 * error);
  CHECK(a / n > 50.0 * error);  // light enough to tell
}
