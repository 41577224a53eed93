// Solid-angle sampling of triangle emitters (integrators/spherical_triangle.h and its use in
// integrators/light_sampling.cpp): known solid angles, directions uniform over the spherical
// triangle (χ²), the pdf 1/Ω, and next-event estimation with MIS by area and by solid angle giving
// the analytic direct light of a big near emitter, solid angle with less variance.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>
#include <vector>

#include "chi2.h"
#include "dacrt/integrators/light_sampling.h"
#include "dacrt/integrators/spherical_triangle.h"
#include "test_geometry.h"
#include "dacrt/util/random.h"

using namespace dacrt;

namespace {

// Barycentric (b1, b2) of the point where the ray o + t·d meets the plane of (p0, p1, p2), or
// false if it does not meet it in front.
bool plane_barycentric(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& p0,
                       const glm::dvec3& p1, const glm::dvec3& p2, double& b1, double& b2,
                       double& t) {
  const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, n = glm::cross(e1, e2);
  t = glm::dot(n, p0 - o) / glm::dot(n, d);
  if (!(t > 0.0)) return false;
  const glm::dvec3 r = o + t * d - p0;
  const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  const double r1 = glm::dot(r, e1), r2 = glm::dot(r, e2), det = d11 * d22 - d12 * d12;
  b1 = (d22 * r1 - d12 * r2) / det;
  b2 = (d11 * r2 - d12 * r1) / det;
  return true;
}

// The irradiance at the origin (normal n) from a polygon of radiance 1 (Lambert's formula).
double polygon_irradiance(const std::vector<glm::dvec3>& v, const glm::dvec3& n) {
  double sum = 0.0;
  for (size_t i = 0; i < v.size(); ++i) {
    const glm::dvec3 a = glm::normalize(v[i]), b = glm::normalize(v[(i + 1) % v.size()]);
    sum += std::acos(glm::dot(a, b)) * glm::dot(n, glm::normalize(glm::cross(a, b)));
  }
  return 0.5 * std::abs(sum);
}

}  // namespace

TEST_CASE("solid angle: the octant is π/2, a far triangle A cos / d², a corner 0") {
  const glm::dvec3 o(0.0);
  CHECK(triangle_solid_angle(o, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}) ==
        doctest::Approx(glm::half_pi<double>()).epsilon(1e-12));
  CHECK(triangle_solid_angle(o, {0, 0, 5}, {0, 3, 0}, {7, 0, 0}) ==
        doctest::Approx(glm::half_pi<double>()).epsilon(1e-12));
  // A triangle of area 0.5·1e-3² facing o from 1 away, tilted by 60°.
  const double s = 1e-3, c = 0.5, sn = std::sqrt(0.75);
  const double far = triangle_solid_angle(o, {0, 0, 1}, {s * c, 0, 1 + s * sn}, {0, s, 1});
  CHECK(far == doctest::Approx(0.5 * s * s * c).epsilon(1e-5));
  CHECK(triangle_solid_angle(o, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}) == 0.0);
}

TEST_CASE("solid angle: directions are uniform over a big near spherical triangle (χ²)") {
  // The triangle is cut into 8² similar sub-triangles; each gets its own solid angle's share.
  const glm::dvec3 o(0.1, 0.0, -0.2), p0(-1.0, 0.4, -1.0), p1(2.0, 0.6, -0.5), p2(-0.5, 0.3, 2.0);
  const glm::dvec3 a = glm::normalize(p0 - o), b = glm::normalize(p1 - o),
                   c = glm::normalize(p2 - o);
  const double omega = spherical_triangle_area(a, b, c);
  REQUIRE(omega > 1.0);
  constexpr int n = 8, cells = n * n;
  const auto corner = [&](int i, int j) {
    return p0 + (double(i) / n) * (p1 - p0) + (double(j) / n) * (p2 - p0);
  };
  // Cell k: the upward sub-triangle at (i, j) is 2·(i·n + j), the downward one 2·(i·n + j) + 1.
  std::vector<double> expected(2 * cells, 0.0);
  double total = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      expected[size_t(2 * (i * n + j))] =
          triangle_solid_angle(o, corner(i, j), corner(i + 1, j), corner(i, j + 1)) / omega;
      if (i + j + 2 <= n)
        expected[size_t(2 * (i * n + j) + 1)] =
            triangle_solid_angle(o, corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)) /
            omega;
    }
  for (double e : expected) total += e;
  CHECK(total == doctest::Approx(1.0).epsilon(1e-9));

  constexpr int samples = 200000;
  std::vector<double> count(expected.size(), 0.0);
  Pcg32 rng(11);
  int outside = 0;
  for (int k = 0; k < samples; ++k) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const glm::dvec3 d = sample_spherical_triangle(a, b, c, omega, u1, u2);
    double b1, b2, t;
    if (!plane_barycentric(o, d, p0, p1, p2, b1, b2, t) || b1 < -1e-9 || b2 < -1e-9 ||
        b1 + b2 > 1.0 + 1e-9) {
      ++outside;
      continue;
    }
    const double x = std::clamp(b1, 0.0, 1.0) * n, y = std::clamp(b2, 0.0, 1.0) * n;
    int i = std::min(n - 1, int(x)), j = std::min(n - 1 - i, int(y));
    const bool down = (x - i) + (y - j) > 1.0 && i + j + 2 <= n;
    ++count[size_t(2 * (i * n + j) + (down ? 1 : 0))];
  }
  CHECK(outside == 0);
  double chi2 = 0.0;
  int dof = -1;
  for (size_t k = 0; k < expected.size(); ++k) {
    if (expected[k] <= 0.0) continue;
    const double e = expected[k] * samples;
    REQUIRE(e > 5.0);
    chi2 += (count[k] - e) * (count[k] - e) / e;
    ++dof;
  }
  const double p = dacrt::test::chi2_survival(chi2, dof);
  INFO("χ² " << chi2 << " with " << dof << " degrees of freedom, p " << p);
  CHECK(p > 0.01);
}

namespace {

// A Lambert point at the origin facing +y under a big, near, double-sided quad of radiance 1
// at height 0.2 (two triangles, each ~2 sr from the origin).
struct NearLight {
  Scene scene;
  std::vector<glm::dvec3> quad = {
      {-1.0, 0.2, -1.0}, {-1.0, 0.2, 1.2}, {1.5, 0.2, 1.2}, {1.5, 0.2, -1.0}};
  NearLight() {
    Material light = Material::lambert(glm::vec3(0.f));
    light.emission = glm::vec3(1.f);
    light.double_sided = true;
    scene.materials = {light};
    const auto v = [&](int k) { return glm::vec3(quad[size_t(k)]); };
    scene.geometry.add(v(0), v(1), v(2), 0);
    scene.geometry.add(v(0), v(2), v(3), 0);
  }
};

struct Estimate {
  double mean, variance;  // of one sample
};

// Next-event estimation plus BSDF sampling, MIS-weighted: one sample of each per estimate.
Estimate direct_light(const Scene& scene, TriangleSampling triangles, int samples) {
  const LightSampling lights(scene, scene.lights, nullptr, triangles);
  const glm::vec3 p(0.f), up(0.f, 1.f, 0.f);
  const Frame frame(up);
  const ShadingPoint x{
      up, frame, GltfBrdf(Material::lambert(glm::vec3(1.f)).brdf()), frame.to_local(up), p,
      p,  false};
  Pcg32 rng(5);
  auto random = [&](Dimension) { return rng.uniform(); };
  const Geometry& g = scene.geometry;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < samples; ++k) {
    double value = 0.0;
    ShadowRay shadow;
    if (lights.sample(p, x, random, shadow)) value += shadow.contribution.x;
    const float u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    if (const auto s = x.brdf.sample(x.wo, u0, u1, u2)) {
      const glm::dvec3 wi(frame.to_world(s->wi));
      for (uint32_t tri = 0; tri < g.size(); ++tri) {
        double b1, b2, t;
        if (!plane_barycentric(glm::dvec3(p), wi, glm::dvec3(g.vertex(tri, 0)),
                               glm::dvec3(g.vertex(tri, 1)), glm::dvec3(g.vertex(tri, 2)), b1, b2,
                               t) ||
            b1 < 0.0 || b2 < 0.0 || b1 + b2 > 1.0)
          continue;
        const float cos_light = std::abs(glm::dot(glm::normalize(g.normal(tri)), glm::vec3(wi)));
        value +=
            s->weight.x * lights.emitter_weight(s->pdf, tri, p, float(t), cos_light, g.area(tri));
      }
    }
    sum += value, sum2 += value * value;
  }
  const double mean = sum / samples;
  return {mean, (sum2 / samples - mean * mean)};
}

}  // namespace

TEST_CASE("solid angle: next-event estimation's pdf towards a big near emitter is 1/Ω") {
  const NearLight near;
  const LightSampling lights(near.scene, near.scene.lights, nullptr),
      by_area(near.scene, near.scene.lights, nullptr, TriangleSampling::area);
  const Geometry& g = near.scene.geometry;
  const glm::vec3 o(0.f);
  for (uint32_t tri = 0; tri < 2; ++tri) {
    const double omega =
        triangle_solid_angle(glm::dvec3(o), glm::dvec3(g.vertex(tri, 0)),
                             glm::dvec3(g.vertex(tri, 1)), glm::dvec3(g.vertex(tri, 2)));
    REQUIRE(omega > LightSampling::min_solid_angle);
    REQUIRE(omega < LightSampling::max_solid_angle);
    CHECK(lights.sampled_solid_angle(o, tri) == omega);
    CHECK(by_area.sampled_solid_angle(o, tri) == 0.0);
    // The light is picked with probability ½ (equal powers); the pdf does not depend on where
    // the direction meets the triangle.
    const float pmf = 0.5f;
    CHECK(lights.emitter_pdf(o, tri, 0.3f, 0.6f, g.area(tri)) == float(pmf / omega));
    CHECK(by_area.emitter_pdf(o, tri, 0.3f, 0.6f, g.area(tri)) ==
          doctest::Approx(pmf * 0.09f / (0.6f * g.area(tri))));
    // From far away (Ω below the bound) both sample by area.
    const glm::vec3 far(0.f, -300.f, 0.f);
    CHECK(lights.sampled_solid_angle(far, tri) == 0.0);
  }
}

// sampled_solid_angle skips the exact Ω where a ball around the triangle, or the triangle's area
// over its least distance (A / (D − r)²), already bounds it below min_solid_angle: the decision
// must be the exact one's, from points near and far, and near the corners and edges, where the
// second bound is closest to Ω. Besides the big quad, a sliver 10 long and 0.1 wide: its area is
// small for the solid angle it subtends from nearby.
TEST_CASE("solid angle: the bounding-ball shortcuts decide as the exact solid angle does") {
  const NearLight near;
  Scene sliver;
  sliver.materials = near.scene.materials;
  const std::vector<glm::dvec3> strip = {{0, 0, 0}, {10, 0, 0}, {10, 0.1, 0}, {0, 0.1, 0}};
  sliver.geometry.add(glm::vec3(strip[0]), glm::vec3(strip[1]), glm::vec3(strip[2]), 0);
  for (const auto& [scene, quad] : {std::pair{&near.scene, &near.quad}, {&sliver, &strip}}) {
    const LightSampling lights(*scene, scene->lights, nullptr);
    const Geometry& g = scene->geometry;
    std::vector<glm::vec3> around = {glm::vec3(
        0.25 * ((*quad)[0] + (*quad)[1] + (*quad)[2] + (*quad)[3]))};  // the quad's centre
    for (size_t k = 0; k < 4; ++k) {
      around.push_back(glm::vec3((*quad)[k]));
      around.push_back(glm::vec3(0.5 * ((*quad)[k] + (*quad)[(k + 1) % 4])));
    }
    Pcg32 rng(17);
    int large = 0, small = 0;
    for (int i = 0; i < 200000; ++i) {
      // Distances from 0.01 to 100 from the quad's centre, log-uniform, in every direction; or
      // from 0.01 to 3 from a corner or an edge's midpoint.
      const bool centre = i % 2 == 0;
      const double r = std::pow(10.0, -2.0 + (centre ? 4.0 : 2.5) * double(rng.uniform()));
      const glm::vec3 o =
          around[centre ? 0 : 1 + size_t(i / 2) % 8] + float(r) * test::random_direction(rng);
      for (uint32_t tri = 0; tri < g.size(); ++tri) {
        const double omega =
            triangle_solid_angle(glm::dvec3(o), glm::dvec3(g.vertex(tri, 0)),
                                 glm::dvec3(g.vertex(tri, 1)), glm::dvec3(g.vertex(tri, 2)));
        const bool sampled =
            omega > LightSampling::min_solid_angle && omega < LightSampling::max_solid_angle;
        const double got = lights.sampled_solid_angle(o, tri);
        INFO("triangles " << g.size() << ", point " << o.x << ", " << o.y << ", " << o.z);
        if (sampled) {
          ++large;
          REQUIRE(got == omega);
        } else {
          ++small;
          REQUIRE(got == 0.0);
        }
      }
    }
    // Both sides of the threshold, many times over.
    CHECK(large > 5000);
    CHECK(small > 5000);
  }
}

TEST_CASE(
    "solid angle: area and solid-angle sampling of a big near emitter agree with the "
    "analytic direct light, solid angle with less variance") {
  const NearLight near;
  const double expected = polygon_irradiance(near.quad, {0, 1, 0}) / glm::pi<double>();
  constexpr int samples = 200000;
  const Estimate area = direct_light(near.scene, TriangleSampling::area, samples);
  const Estimate solid = direct_light(near.scene, TriangleSampling::solid_angle_if_large, samples);
  MESSAGE("direct light " << expected << ": by area " << area.mean << " (variance " << area.variance
                          << "), by solid angle " << solid.mean << " (variance " << solid.variance
                          << ")");
  CHECK(std::abs(area.mean - expected) <= 4.0 * std::sqrt(area.variance / samples));
  CHECK(std::abs(solid.mean - expected) <= 4.0 * std::sqrt(solid.variance / samples));
  CHECK(solid.variance < 0.75 * area.variance);  // measured: 0.56×
}
