// The path tracer on scenes with known answers: a closed furnace box and white spheres under a
// uniform environment or an environment map all render 1 everywhere; point, spot and directional
// lights light a Lambert plane as the spec says; cameras see nothing nearer than znear, and an
// orthographic one exactly its square. Checked per pixel against each pixel's own standard error,
// not against a hand-picked tolerance. Also: max depth 0, unknown integrators and cameras, and
// the stages a render skips. Alpha, transmission and the wavefront loop: alpha_test.cpp,
// transmission_test.cpp, wavefront_test.cpp.
#include "dacrt/integrators/integrator.h"

#include <doctest/doctest.h>

#include <cmath>

#include "dacrt/render/render_job.h"
#include "render_check.h"
#include "test_geometry.h"

using namespace dacrt;
using namespace dacrt::test;

TEST_CASE("furnace: inside a closed box of albedo 0.5 and emission 0.5, everything is 1") {
  Scene scene;
  scene.geometry = inward_box();
  Material wall = Material::lambert(glm::vec3(0.5f));
  wall.emission = glm::vec3(0.5f);
  scene.materials = {wall};
  scene.cameras = {looking_at(glm::vec3(0.2f, -0.1f, 0.3f), glm::vec3(1, 0.3f, -1), 1.4f)};
  RenderSettings s;
  s.environment = glm::vec3(0.f);  // its emitters alone (a sky of 1 stays beside glowing ones)
  // 1024 samples a pixel, not 64: the per-pixel z-test needs each pixel's own standard error, and
  // here a sample's distribution is skewed by Russian roulette (from depth 3 a path survives with
  // probability 1/8 and then carries about one unit more). At 64 spp a pixel sees 8 survivors on
  // average, and with 0 or 1 of them (probability 1.9e-3, about 0.7 of the 384 pixels of a 24×16
  // image) its mean is low and its sample variance lower still: z ≈ -5 to -7 for an unbiased
  // estimate. At 1024 spp (128 survivors) the pixel's z is close to normal.
  s.width = 12, s.height = 8, s.spp = 1024, s.seed = 3;
  for (SamplerKind sampler : {SamplerKind::independent, SamplerKind::sobol}) {
    s.sampler = sampler;
    INFO("sampler " << sampler_name(sampler));
    Result r = render(scene, s);
    check_renders(r.film, 1.0);
    CHECK(r.stats.by_type[size_t(RayType::shadow)].rays > 0);
    CHECK(r.stats.dropped_samples == 0);
  }
  // Faces pointing away do not emit: from outside, the box is black but for what it reflects of
  // a black world.
  scene.cameras = {looking_at(glm::vec3(3, 2, 4), glm::vec3(0), 0.8f)};
  s.spp = 4;
  Result outside = render(scene, s);
  for (size_t p = 0; p < outside.film.pixels(); ++p) CHECK(outside.film.mean_and_error(p).x == 0.0);
}

namespace {

// A white Lambert sphere of radius 1 at the origin, seen from 3.5 away: under a uniform sky of 1
// every pixel is 1 (KHR_materials_specular's factor 0 leaves the glTF BRDF's Lambert base).
Scene white_sphere() {
  Scene scene;
  scene.geometry = sphere(32, 64, glm::vec3(0.f), 1.f);
  scene.materials = {Material::lambert(glm::vec3(1.f))};
  scene.cameras = {looking_at(glm::vec3(0, 0.5f, 3.5f), glm::vec3(0), 0.9f)};
  return scene;
}

}  // namespace

TEST_CASE("furnace: a white diffuse sphere under a uniform environment of 1 renders 1") {
  Scene scene = white_sphere();
  RenderSettings s;
  s.width = 32, s.height = 32, s.spp = 16, s.environment = glm::vec3(1.f);
  // BSDF sampling alone here (next-event estimation of the sky: the test below).
  s.sample_environment = RenderSettings::EnvironmentSampling::off;
  Result r = render(scene, s);
  check_renders(r.film, 1.0);
  // Nothing emits: no shadow rays at all, and the render says so.
  CHECK(r.stats.by_type[size_t(RayType::shadow)].rays == 0);
  REQUIRE(r.stats.skipped.size() == 5);
  CHECK(r.stats.skipped[0].find("shadow") != std::string::npos);
  CHECK(r.stats.skipped[1].find("texture lookups") != std::string::npos);
  CHECK(r.stats.skipped[2].find("vertex colours") != std::string::npos);
  CHECK(r.stats.skipped[3].find("alpha tests") != std::string::npos);
  CHECK(r.stats.skipped[4].find("transmission") != std::string::npos);
  // An albedo of 0.5 lets through half per bounce: a convex sphere sends every bounce ray to the
  // sky, so the sphere's pixels are 0.5 and the background 1.
  scene.materials[0].base_color = glm::vec3(0.5f);
  Result half = render(scene, s);
  size_t centre = size_t(16) * 32 + 16;
  CHECK(half.film.mean_and_error(centre).x == doctest::Approx(0.5).epsilon(1e-5));
  CHECK(half.film.mean_and_error(0).x == doctest::Approx(1.0));
}

TEST_CASE("a uniform environment sampled as a light: unbiased, and where the scene is open") {
  using Mode = RenderSettings::EnvironmentSampling;
  const Scene scene = white_sphere();
  RenderSettings s;
  s.width = 16, s.height = 16, s.spp = 256, s.environment = glm::vec3(1.f);
  auto shadow_rays = [](const Result& r) { return r.stats.by_type[size_t(RayType::shadow)].rays; };
  auto says_skipped = [](const Result& r) {
    for (const std::string& what : r.stats.skipped)
      if (what.find("environment light samples") != std::string::npos) return true;
    return false;
  };
  // The white furnace with light samples and MIS still renders 1 (now with noise: per pixel
  // against its own standard error).
  s.sample_environment = Mode::on;
  Result on = render(scene, s);
  check_renders(on.film, 1.0);
  CHECK(shadow_rays(on) > 0);
  CHECK_FALSE(says_skipped(on));
  for (Mode mode : {Mode::off, Mode::automatic}) {
    s.sample_environment = mode;
    Result r = render(scene, s);
    check_renders(r.film, 1.0);
    // Nothing else is a light: automatic leaves the sky to BSDF sampling too, and says so.
    CHECK(shadow_rays(r) == 0);
    CHECK(says_skipped(r) == (mode == Mode::automatic));
  }
  // With a light beside it, the open sphere's sky is sampled too; inside a closed box no bounce
  // ray escapes, and automatic leaves it to BSDF sampling.
  PunctualLight light;
  light.position = glm::vec3(0.f, 3.f, 0.f);
  s.lights = {light};
  s.spp = 2;
  s.sample_environment = Mode::automatic;
  CHECK_FALSE(says_skipped(render(scene, s)));
  Scene box;
  box.geometry = inward_box();
  box.materials = {Material::lambert(glm::vec3(0.5f))};
  box.cameras = {looking_at(glm::vec3(0.2f, -0.1f, 0.3f), glm::vec3(1, 0.3f, -1), 1.4f)};
  s.lights = {};
  CHECK(says_skipped(render(box, s)));  // (no light)
  light.position = glm::vec3(0.1f);
  s.lights = {light};
  CHECK(says_skipped(render(box, s)));  // closed
  s.sample_environment = Mode::on;
  CHECK_FALSE(says_skipped(render(box, s)));
}

TEST_CASE("furnace: a smooth white metal sphere under a uniform environment of 1 renders 1") {
  // glTF metallic 1, roughness 0, base colour 1: a mirror whose Fresnel is 1 at every angle; every
  // camera ray that meets the sphere leaves it for the sky after one reflection.
  Scene scene;
  scene.geometry = sphere(32, 64, glm::vec3(0.f), 1.f);
  Material mirror;
  mirror.metallic = 1.f, mirror.roughness = 0.f;
  scene.materials = {mirror};
  scene.cameras = {looking_at(glm::vec3(0, 0.5f, 3.5f), glm::vec3(0), 0.9f)};
  RenderSettings s;
  s.width = 32, s.height = 32, s.spp = 8, s.environment = glm::vec3(1.f);
  s.sample_environment = RenderSettings::EnvironmentSampling::off;  // (exact: BSDF sampling only)
  Result r = render(scene, s);
  size_t far_off = 0;
  for (size_t p = 0; p < r.film.pixels(); ++p)
    far_off += std::abs(r.film.mean_and_error(p).x - 1.0) > 2e-3;
  CHECK(far_off == 0);
  // A rough white metal loses what single scattering cannot return: darker, never brighter.
  scene.materials[0].roughness = 1.f;
  Result rough = render(scene, s);
  const size_t centre = size_t(16) * 32 + 16;
  CHECK(rough.film.mean_and_error(centre).x < 0.99);
  for (size_t p = 0; p < rough.film.pixels(); ++p) {
    const glm::dvec2 m = rough.film.mean_and_error(p);
    CHECK(m.x <= 1.0 + 5.0 * m.y + 1e-5);
  }
}

TEST_CASE("cameras see nothing nearer than their znear") {
  Scene scene;
  scene.geometry = quad_grid(1);  // [0, 1]² at z = 0, facing +z
  Material light = Material::lambert(glm::vec3(0.f));
  light.emission = glm::vec3(1.f);
  scene.materials = {light};
  RenderSettings s;
  s.environment = glm::vec3(0.f);  // its emitters alone (a sky of 1 stays beside glowing ones)
  s.width = s.height = 8, s.spp = 1, s.max_depth = 0;
  for (const bool orthographic : {false, true})
    for (const float znear : {0.f, 1.9f, 2.05f, 2.1f}) {
      INFO("orthographic " << orthographic << ", znear " << znear);
      // 2 in front of the quad: the near plane is a plane, so at 2.05 even the corner pixels,
      // which meet the quad 2.06 away along their rays (perspective), see nothing.
      Camera cam = looking_at(glm::vec3(0.5f, 0.5f, 2.f), glm::vec3(0.5f, 0.5f, 0.f), 0.4f);
      cam.orthographic = orthographic;
      cam.ymag = 0.4f;
      cam.znear = znear;
      scene.cameras = {cam};
      Result r = render(scene, s);
      for (size_t p = 0; p < r.film.pixels(); ++p)
        CHECK(r.film.mean_and_error(p).x == (znear < 2.f ? 1.0 : 0.0));
    }
}

TEST_CASE("an orthographic camera sees parallel rays: a unit quad covers exactly its pixels") {
  // ymag 1 over 16 × 16 pixels: 8 pixels per unit, whatever the distance.
  Scene scene;
  scene.geometry = quad_grid(1);  // [0, 1]² at z = 0, facing +z
  Material light = Material::lambert(glm::vec3(0.f));
  light.emission = glm::vec3(1.f);
  scene.materials = {light};
  for (float distance : {2.f, 50.f}) {
    Camera cam = looking_at(glm::vec3(0.5f, 0.5f, distance), glm::vec3(0.5f, 0.5f, 0.f), 1.f);
    cam.orthographic = true;
    cam.ymag = 1.f;
    scene.cameras = {cam};
    RenderSettings s;
    s.environment = glm::vec3(0.f);  // its emitters alone (a sky of 1 stays beside glowing ones)
    s.width = s.height = 16, s.spp = 4;
    Result r = render(scene, s);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        INFO("distance " << distance << ", pixel " << x << ", " << y);
        const bool inside = x >= 4 && x < 12 && y >= 4 && y < 12;
        CHECK(r.film.mean_and_error(size_t(y) * 16 + x).x == (inside ? 1.0 : 0.0));
      }
  }
}

// The mean over pixel (x, y) of lit_plane() of f at the plane point it sees.
template <typename F>
double pixel_mean(int x, int y, F f) {
  double sum = 0.0;
  constexpr int n = 16;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      sum += f(glm::vec3(-1.f + (x + (i + 0.5f) / n) / 8.f, 1.f - (y + (j + 0.5f) / n) / 8.f, 0.f));
  return sum / (n * n);
}

TEST_CASE("punctual lights: point, spot and directional light a Lambert plane as the spec says") {
  RenderSettings s;
  s.environment = glm::vec3(0.f);  // its lights alone (a sky of 1 stays beside the file's lights)
  s.width = s.height = 16, s.spp = 64;
  const double brdf = 0.5 / glm::pi<double>();
  SUBCASE("a point light: I cos θ / d²") {
    Scene scene = lit_plane();
    PunctualLight l;
    l.intensity = glm::vec3(2.f);
    l.position = glm::vec3(0.3f, -0.2f, 1.f);
    scene.lights = {l};
    Result r = render(scene, s);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        const double expected = pixel_mean(x, y, [&](glm::vec3 p) {
          const glm::vec3 to = l.position - p;
          const double d2 = glm::dot(to, to);
          return brdf * 2.0 * (to.z / std::sqrt(d2)) / d2;
        });
        const glm::dvec2 m = r.film.mean_and_error(size_t(y) * 16 + x);
        INFO("pixel " << x << ", " << y);
        CHECK(std::abs(m.x - expected) <= 5.0 * m.y + 2e-3 * expected);
      }
    // Within a range the spec's window clamp(1 − (d/range)⁴, 0, 1) dims it.
    scene.lights[0].range = 2.f;
    Result windowed = render(scene, s);
    for (int y = 0; y < 16; y += 5)
      for (int x = 0; x < 16; x += 5) {
        const double expected = pixel_mean(x, y, [&](glm::vec3 p) {
          const glm::vec3 to = l.position - p;
          const double d2 = glm::dot(to, to), q = d2 / 4.0;
          return brdf * 2.0 * (to.z / std::sqrt(d2)) / d2 * std::clamp(1.0 - q * q, 0.0, 1.0);
        });
        const glm::dvec2 m = windowed.film.mean_and_error(size_t(y) * 16 + x);
        INFO("pixel " << x << ", " << y);
        CHECK(std::abs(m.x - expected) <= 5.0 * m.y + 2e-3 * expected);
      }
    // With a range of 0.5 the plane, 1 away, gets nothing.
    scene.lights[0].range = 0.5f;
    Result out_of_range = render(scene, s);
    for (size_t p = 0; p < out_of_range.film.pixels(); ++p)
      CHECK(out_of_range.film.mean_and_error(p).x == 0.0);
  }
  SUBCASE("a directional light: E cos θ everywhere, and a blocker's shadow") {
    Scene scene = lit_plane();
    PunctualLight l;
    l.type = PunctualLight::Type::directional;
    l.intensity = glm::vec3(1.5f);
    l.direction = glm::vec3(0.6f, 0.f, -0.8f);
    scene.lights = {l};
    Result r = render(scene, s);
    for (size_t p = 0; p < r.film.pixels(); ++p)
      CHECK(r.film.mean_and_error(p).x == doctest::Approx(brdf * 1.5 * 0.8).epsilon(1e-5));
    // A square at z = 0.5 over [-0.25, 0.25]²: its shadow falls 0.375 further along +x.
    const glm::vec3 a(-0.25f, -0.25f, 0.5f), b(0.25f, -0.25f, 0.5f), c(0.25f, 0.25f, 0.5f),
        d(-0.25f, 0.25f, 0.5f);
    scene.geometry.add(a, b, c, 0);
    scene.geometry.add(a, c, d, 0);
    s.max_depth = 1;  // direct light only: the blocker's underside reflects the lit plane
    Result shadowed = render(scene, s);
    // Pixels 10..12 cover x in [0.25, 0.625], 6..9 y in [-0.25, 0.25].
    for (int y = 6; y < 10; ++y)
      for (int x = 10; x < 13; ++x) {
        INFO("pixel " << x << ", " << y);
        CHECK(shadowed.film.mean_and_error(size_t(y) * 16 + x).x == 0.0);
      }
    CHECK(shadowed.film.mean_and_error(size_t(8) * 16 + 15).x ==
          doctest::Approx(brdf * 1.5 * 0.8).epsilon(1e-5));
  }
  SUBCASE("a spot light: full inside the inner cone, nothing outside the outer one") {
    Scene scene = lit_plane();
    PunctualLight l;
    l.type = PunctualLight::Type::spot;
    l.intensity = glm::vec3(1.f);
    l.position = glm::vec3(0.f, 0.f, 1.f);
    l.direction = glm::vec3(0.f, 0.f, -1.f);
    l.cos_inner = std::cos(glm::radians(20.f)), l.cos_outer = std::cos(glm::radians(30.f));
    scene.lights = {l};
    Result r = render(scene, s);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        // Pixel centres farther than tan 30° + a pixel diagonal are dark; nearer than tan 20° minus
        // one are fully lit, as by a point light.
        const glm::vec3 centre(-1.f + (x + 0.5f) / 8.f, 1.f - (y + 0.5f) / 8.f, 0.f);
        const float r_xy = glm::length(glm::vec2(centre));
        const glm::dvec2 m = r.film.mean_and_error(size_t(y) * 16 + x);
        INFO("pixel " << x << ", " << y);
        if (r_xy > std::tan(glm::radians(30.f)) + 0.09f) CHECK(m.x == 0.0);
        if (r_xy < std::tan(glm::radians(20.f)) - 0.09f) {
          const double expected = pixel_mean(x, y, [&](glm::vec3 p) {
            const glm::vec3 to = l.position - p;
            const double d2 = glm::dot(to, to);
            return brdf * (to.z / std::sqrt(d2)) / d2;
          });
          CHECK(std::abs(m.x - expected) <= 5.0 * m.y + 2e-3 * expected);
        }
      }
  }
}

TEST_CASE("furnace: under an environment map of 1, a white diffuse sphere renders 1") {
  // The map is sampled by next-event estimation and reached by BRDF sampling, weighed by MIS:
  // unbiased, so still 1 within the noise.
  Scene scene;
  scene.geometry = sphere(32, 64, glm::vec3(0.f), 1.f);
  scene.materials = {Material::lambert(glm::vec3(1.f))};
  scene.cameras = {looking_at(glm::vec3(0, 0.5f, 3.5f), glm::vec3(0), 0.9f)};
  Image one(16, 8);
  std::fill(one.rgb.begin(), one.rgb.end(), 1.f);
  RenderSettings s;
  s.width = 24, s.height = 24, s.spp = 32;
  s.environment_map = std::make_shared<const EnvironmentMap>(one, "one");
  Result r = render(scene, s);
  check_renders(r.film, 1.0);
  CHECK(r.stats.by_type[size_t(RayType::shadow)].rays > 0);
  REQUIRE(r.stats.skipped.size() == 4);  // shading work only: the map needs shadow rays
  CHECK(r.stats.skipped[0].find("shadow") == std::string::npos);
  // With a light in the scene next-event estimation samples the map only half of the time, and
  // every pdf in the MIS weights must say so. This light shines from behind, on nothing the
  // camera sees (visible normals all have z > 0.14): the image stays 1.
  PunctualLight behind;
  behind.type = PunctualLight::Type::directional;
  behind.direction = glm::vec3(0.f, 0.f, 1.f);
  behind.intensity = glm::vec3(5.f);
  scene.lights = {behind};
  Result shared = render(scene, s);
  check_renders(shared.film, 1.0);
  // A map that is bright in one small patch: importance sampling finds it.
  Image patch(32, 16);
  for (int y = 5; y < 7; ++y)
    for (int x = 20; x < 22; ++x)
      patch.pixel(x, y)[0] = patch.pixel(x, y)[1] = patch.pixel(x, y)[2] = 50.f;
  s.environment_map = std::make_shared<const EnvironmentMap>(patch, "patch");
  scene.lights.clear();
  Result sampled = render(scene, s);
  double sum = 0.0, var = 0.0;
  for (size_t p = 0; p < sampled.film.pixels(); ++p) {
    const glm::dvec2 m = sampled.film.mean_and_error(p);
    sum += m.x, var += m.y * m.y;
  }
  CHECK(sum > 0.0);
  CHECK(std::sqrt(var) < 0.05 * sum);
}

TEST_CASE("max depth 0 shows emitters only, and unknown integrators and cameras are errors") {
  Scene scene;
  scene.geometry = inward_box();
  Material wall = Material::lambert(glm::vec3(0.9f));
  wall.emission = glm::vec3(0.25f);
  scene.materials = {wall};
  scene.cameras = {looking_at(glm::vec3(0.f), glm::vec3(0, 0, -1), 1.f)};
  RenderSettings s;
  s.width = s.height = 8, s.spp = 2, s.max_depth = 0;
  Result r = render(scene, s);
  for (size_t p = 0; p < r.film.pixels(); ++p)
    CHECK(r.film.mean_and_error(p).x == doctest::Approx(0.25));
  CHECK(r.stats.by_type[size_t(RayType::bounce)].rays == 0);
  auto b = Backend::create("dacrt", scene.geometry);
  s.integrator = "nope";
  CHECK_THROWS_AS(Integrator::create(scene, make_shot(scene, s), *b, s), Error);
  s.integrator = "path";
  s.camera = 1;
  CHECK_THROWS_AS(RenderJob(scene, *b, s), Error);
}

TEST_CASE("what the render skips follows the materials the triangles use, not the file's list") {
  Scene scene;
  scene.geometry = quad_grid(1);
  Material unused = Material::lambert(glm::vec3(0.5f));
  unused.alpha_mode = Material::AlphaMode::mask;
  unused.transmission = 1.f;
  scene.materials = {Material::lambert(glm::vec3(0.5f)), unused};  // triangles use material 0
  scene.cameras = {looking_at(glm::vec3(0.5f, 0.5f, 2.f), glm::vec3(0.5f, 0.5f, 0.f), 0.9f)};
  RenderSettings s;
  s.width = s.height = 4, s.spp = 1, s.environment = glm::vec3(1.f);
  const auto skipped = render(scene, s).stats.skipped;
  auto has = [&](const char* what) {
    return std::any_of(skipped.begin(), skipped.end(),
                       [&](const std::string& x) { return x.find(what) == 0; });
  };
  CHECK(has("alpha tests"));
  CHECK(has("transmission"));
  scene.geometry.material[0] = 1;  // now one triangle uses it
  const auto used = render(scene, s).stats.skipped;
  CHECK(std::none_of(used.begin(), used.end(),
                     [](const std::string& x) { return x.find("alpha tests") == 0; }));
}
