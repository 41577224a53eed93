// The equirectangular environment map: its axes, its importance sampling (χ² against its pdf),
// and that what it samples integrates to what it holds.
#include "dacrt/scene/environment.h"

#include <doctest/doctest.h>

#include <glm/gtc/constants.hpp>

#include "chi2.h"
#include "dacrt/util/error.h"
#include "dacrt/util/random.h"

using namespace dacrt;

namespace {

bool near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) {
  return glm::all(glm::lessThanEqual(glm::abs(a - b), glm::vec3(eps)));
}

// A 24 × 12 map with smooth variation, a bright patch and black pixels; with `black_poles` the
// top and bottom rows are black (the χ² grid cannot integrate the pdf's 1/sin θ at the poles).
Image test_map(bool black_poles) {
  Image image(24, 12);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      float* p = image.pixel(x, y);
      const float base = 0.2f + 0.1f * float((x * 7 + y * 3) % 5);
      p[0] = base, p[1] = 0.5f * base, p[2] = 0.25f * base;
      if (x >= 15 && x < 17 && y >= 3 && y < 5) p[0] = p[1] = p[2] = 40.f;  // a sun
      if ((x + y) % 7 == 0) p[0] = p[1] = p[2] = 0.f;
      if (black_poles && (y == 0 || y == image.height - 1)) p[0] = p[1] = p[2] = 0.f;
    }
  return image;
}

// The four numbers EnvironmentMap::sample takes, in a fixed order.
glm::vec4 uniforms(Pcg32& rng) {
  const float a = rng.uniform(), b = rng.uniform(), c = rng.uniform();
  return {a, b, c, rng.uniform()};
}

}  // namespace

TEST_CASE("environment map axes: +Y up, the image centre towards -Z, u growing towards +X") {
  CHECK(near(EnvironmentMap::from_uv({0.5f, 0.5f}), {0, 0, -1}));
  CHECK(near(EnvironmentMap::from_uv({0.75f, 0.5f}), {1, 0, 0}));
  CHECK(near(EnvironmentMap::from_uv({0.25f, 0.5f}), {-1, 0, 0}));
  CHECK(near(EnvironmentMap::from_uv({0.3f, 0.f}), {0, 1, 0}));
  CHECK(near(EnvironmentMap::from_uv({0.3f, 1.f}), {0, -1, 0}));
  Pcg32 rng(1);
  for (int k = 0; k < 1000; ++k) {
    const glm::vec2 uv(rng.uniform(), 0.01f + 0.98f * rng.uniform());
    CHECK(glm::length(EnvironmentMap::to_uv(EnvironmentMap::from_uv(uv)) - uv) < 1e-4f);
  }
}

TEST_CASE("environment map sampling follows its pdf (χ²)") {
  const EnvironmentMap map(test_map(true), "test");
  const double p = dacrt::test::chi2_p_value(
      [&](Pcg32& rng) -> std::optional<glm::vec3> {
        const auto s = map.sample(uniforms(rng));
        if (!(s.pdf > 0.f)) return std::nullopt;
        return s.direction;
      },
      [&](const glm::vec3& d) { return map.pdf(d); }, 5, 500000, /*sub=*/128);
  CHECK(p > 0.01);
  // Every sample carries the radiance and the density of the direction it returns, and black
  // pixels are never sampled.
  Pcg32 rng(6);
  for (int k = 0; k < 20000; ++k) {
    const auto s = map.sample(uniforms(rng));
    REQUIRE(s.pdf > 0.f);
    CHECK(s.pdf == map.pdf(s.direction));
    CHECK(s.radiance == map.radiance(s.direction));
    CHECK(s.radiance != glm::vec3(0.f));
  }
}

TEST_CASE("environment map: radiance over pdf integrates to 4π times the average") {
  const EnvironmentMap map(test_map(false), "test");
  Pcg32 rng(8);
  constexpr int n = 400000;
  glm::dvec3 sum(0.0), sum2(0.0);
  for (int k = 0; k < n; ++k) {
    const auto s = map.sample(uniforms(rng));
    if (!(s.pdf > 0.f)) continue;
    const glm::dvec3 v = glm::dvec3(s.radiance) / double(s.pdf);
    sum += v, sum2 += v * v;
  }
  const glm::dvec3 mean = sum / double(n);
  const glm::dvec3 error = glm::sqrt((sum2 / double(n) - mean * mean) / double(n));
  const glm::dvec3 expected = 4.0 * glm::pi<double>() * glm::dvec3(map.average());
  for (int c = 0; c < 3; ++c) CHECK(std::abs(mean[c] - expected[c]) <= 5.0 * error[c] + 1e-4);
  // A uniform map: the average is the value.
  Image one(8, 4);
  std::fill(one.rgb.begin(), one.rgb.end(), 1.f);
  CHECK(near(EnvironmentMap(one, "one").average(), glm::vec3(1.f)));
}

TEST_CASE("environment map: bad images are errors naming the file") {
  Image bad = test_map(false);
  bad.pixel(3, 2)[1] = -1.f;
  CHECK_THROWS_WITH_AS(EnvironmentMap(bad, "sky.exr"),
                       "sky.exr: environment pixel (3, 2) has G = -1 (negative)", Error);
  bad.pixel(3, 2)[1] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH_AS(EnvironmentMap(bad, "sky.exr"), doctest::Contains("G = nan (not a number)"),
                       Error);
  bad.pixel(3, 2)[1] = 1.f;
  bad.pixel(3, 2)[2] = std::numeric_limits<float>::infinity();
  CHECK_THROWS_WITH_AS(EnvironmentMap(bad, "sky.exr"), doctest::Contains("B = inf (infinite)"),
                       Error);
  // Finite but so bright that the paths carrying it overflow float: said as such (it was called
  // "negative or not finite").
  bad.pixel(3, 2)[2] = 1.f;
  bad.pixel(3, 2)[0] = 3.4e38f;
  CHECK_THROWS_WITH_AS(EnvironmentMap(bad, "sky.exr"),
                       "sky.exr: environment pixel (3, 2) has R = 3.4e+38 (above 1e18, the "
                       "brightest radiance accepted)",
                       Error);
  bad.pixel(3, 2)[0] = 1e18f;  // the limit itself is accepted
  CHECK_NOTHROW(EnvironmentMap(bad, "sky.exr"));
  CHECK_THROWS_WITH_AS(EnvironmentMap(Image(), "empty.exr"), doctest::Contains("empty.exr"), Error);
  // All black is valid: nothing to sample.
  const EnvironmentMap black(Image(4, 2), "black");
  CHECK(black.black());
  CHECK(black.pdf(glm::vec3(0, 0, -1)) == 0.f);
}

TEST_CASE("environment map: a constant map is sampled uniformly over the sphere, from u.x and u.y") {
  Image sky(16, 8);
  for (int y = 0; y < sky.height; ++y)
    for (int x = 0; x < sky.width; ++x) {
      float* p = sky.pixel(x, y);
      p[0] = 0.5f, p[1] = 1.f, p[2] = 2.f;
    }
  const EnvironmentMap map(sky, "sky");
  REQUIRE(map.constant());
  const double p = dacrt::test::chi2_p_value(
      [&](Pcg32& rng) -> std::optional<glm::vec3> { return map.sample(uniforms(rng)).direction; },
      [&](const glm::vec3& d) { return map.pdf(d); }, 5, 200000, /*sub=*/16);
  CHECK(p > 0.01);
  Pcg32 rng(3);
  for (int k = 0; k < 1000; ++k) {
    const glm::vec4 u = uniforms(rng);
    const auto s = map.sample(u);
    CHECK(s.pdf == doctest::Approx(0.25 / glm::pi<double>()).epsilon(1e-6));
    CHECK(s.radiance == glm::vec3(0.5f, 1.f, 2.f));
    CHECK(s.direction.y == doctest::Approx(1.f - 2.f * u.x).epsilon(1e-5));
    // The point inside a pixel (u.z, u.w) plays no part: the pair (u.x, u.y) alone, as the
    // sampler's 2D pattern draws it, keeps its stratification.
    CHECK(map.sample({u.x, u.y, 1.f - u.z, 0.5f}).direction == s.direction);
  }
  sky.pixel(3, 5)[1] = 1.5f;
  CHECK_FALSE(EnvironmentMap(sky, "sky").constant());
}
