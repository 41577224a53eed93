// The path tracer on scenes with known answers: a closed furnace box and a white sphere under a
// uniform environment both render 1 everywhere. Checked per pixel against each pixel's own
// standard error, not against a hand-picked tolerance.
#include "integrators/integrator.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "render/render_job.h"
#include "test_geometry.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

struct Result {
  Film film;
  RenderStats stats;
};

Result render(const Scene& scene, RenderSettings s, const char* backend = "dacrt",
              const char* integrator = "path") {
  auto b = Backend::create(backend, scene.geometry);
  RenderJob job(scene, *b, s, integrator);
  Film film = job.film();
  Progress quiet("test", 1, false);
  job.run(film, 0, uint32_t(s.spp), quiet);
  return {std::move(film), job.stats()};
}

// Every pixel within z standard errors of `expected` (z = 5: a false alarm over a few thousand
// pixels has probability ~1e-3), and the image mean within 4 of its own standard error. The
// pixel's standard error is its own samples' (s / √n), so that z is near normal only when every
// pixel has enough samples of each kind its estimator mixes (see the closed box below).
void check_renders(const Film& film, double expected, double z = 5.0) {
  double sum = 0.0, var = 0.0;
  size_t outliers = 0;
  for (size_t p = 0; p < film.pixels(); ++p) {
    glm::dvec2 m = film.mean_and_error(p);
    sum += m.x;
    var += m.y * m.y;
    if (std::abs(m.x - expected) > z * m.y + 1e-5) {
      if (++outliers <= 3) MESSAGE("pixel " << p << ": " << m.x << " ± " << m.y);
    }
  }
  double mean = sum / film.pixels(), error = std::sqrt(var) / film.pixels();
  INFO("image mean " << mean << " ± " << error);
  CHECK(outliers == 0);
  CHECK(std::abs(mean - expected) <= 4.0 * error + 1e-5);
}

}  // namespace

TEST_CASE("furnace: inside a closed box of albedo 0.5 and emission 0.5, everything is 1") {
  Scene scene;
  scene.geometry = inward_box();
  Material wall = Material::lambert(glm::vec3(0.5f));
  wall.emission = glm::vec3(0.5f);
  scene.materials = {wall};
  scene.cameras = {looking_at(glm::vec3(0.2f, -0.1f, 0.3f), glm::vec3(1, 0.3f, -1), 1.4f)};
  RenderSettings s;
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

TEST_CASE("furnace: a white diffuse sphere under a uniform environment of 1 renders 1") {
  Scene scene;
  scene.geometry = sphere(32, 64, glm::vec3(0.f), 1.f);
  // KHR_materials_specular's factor 0 leaves the glTF BRDF's Lambert base: white renders 1.
  scene.materials = {Material::lambert(glm::vec3(1.f))};
  scene.cameras = {looking_at(glm::vec3(0, 0.5f, 3.5f), glm::vec3(0), 0.9f)};
  RenderSettings s;
  s.width = 32, s.height = 32, s.spp = 16, scene.environment = glm::vec3(1.f);
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
  s.width = 32, s.height = 32, s.spp = 8, scene.environment = glm::vec3(1.f);
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

// A Lambert square of albedo 0.5 in z = 0 ([-2, 2]², facing +z) seen from straight above by an
// orthographic camera whose 16 × 16 pixels cover [-1, 1]²: a pixel's value is the direct light
// on the part of the plane it sees, times 0.5 / π (bounces leave for a black sky).
Scene lit_plane() {
  Scene scene;
  const glm::vec3 a(-2, -2, 0), b(2, -2, 0), c(2, 2, 0), d(-2, 2, 0);
  scene.geometry.add(a, b, c, 0);
  scene.geometry.add(a, c, d, 0);
  scene.materials = {Material::lambert(glm::vec3(0.5f))};
  Camera cam = looking_at(glm::vec3(0, 0, 5), glm::vec3(0), 1.f);
  cam.orthographic = true;
  cam.ymag = 1.f;
  scene.cameras = {cam};
  return scene;
}

// The mean over pixel (x, y) of f at the plane point it sees.
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
  scene.environment_map = std::make_shared<const EnvironmentMap>(one, "one");
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
  scene.environment_map = std::make_shared<const EnvironmentMap>(patch, "patch");
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

TEST_CASE("renders are deterministic: same image for any threads and backend, any wavefront") {
  // Large enough for many blocks of every parallel stage (compaction, roulette, film), with
  // roulette, bounces and next-event estimation; one face emits.
  Scene scene;
  scene.geometry = inward_box();
  Material wall;
  wall.base_color = glm::vec3(0.7f, 0.5f, 0.3f);
  scene.materials = {wall, wall};
  scene.materials[1].emission = glm::vec3(2.f);
  for (size_t i = 0; i < 2; ++i) scene.geometry.material[i] = 1;  // one face emits
  scene.cameras = {looking_at(glm::vec3(0.f), glm::vec3(0, 0, -1), 1.2f)};
  RenderSettings s;
  s.width = 64, s.height = 48, s.spp = 16, s.seed = 9;
  s.wavefront = 20000;  // regeneration: paths end and new samples take their slots
  auto image = [&](const char* backend, int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return render(scene, s, backend).film.resolve().rgb;
  };
  const std::vector<float> reference = image("dacrt", 2);
  CHECK(image("dacrt", 1) == reference);
  CHECK(image("dacrt", 4) == reference);
  CHECK(image("dacrt-naive", 3) == reference);
  CHECK(image("brute", 2) == reference);
  // Other wavefront sizes change only the order of each pixel's sums.
  for (size_t wavefront : {size_t(1), size_t(777), size_t(0) /* auto: the whole frame */}) {
    INFO("wavefront " << wavefront);
    s.wavefront = wavefront;
    const std::vector<float> other = image("dacrt", 2);
    REQUIRE(other.size() == reference.size());
    double worst = 0.0;
    for (size_t k = 0; k < other.size(); ++k)
      worst = std::max(worst, std::abs(double(other[k]) - reference[k]) /
                                  std::max(1e-3, double(std::abs(reference[k]))));
    CHECK(worst < 1e-5);
  }
  s.wavefront = 20000;
  s.seed = 10;
  CHECK(image("dacrt", 2) != reference);
  // The statistics count each ray type, and regeneration kept the bounce batches few.
  Result a = render(scene, s, "dacrt");
  CHECK(a.stats.by_type[size_t(RayType::primary)].rays == 64u * 48u * 16u);
  CHECK(a.stats.paths == 64u * 48u * 16u);
  CHECK(a.stats.wavefront == 20000u);
  uint64_t by_bounce = 0;
  for (const auto& b : a.stats.by_bounce) by_bounce += b.rays;
  CHECK(by_bounce == a.stats.by_type[size_t(RayType::bounce)].rays);
  CHECK(a.stats.by_type[size_t(RayType::bounce)].rays > 64u * 48u * 16u);
  CHECK(a.stats.by_type[size_t(RayType::shadow)].rays > 64u * 48u * 16u / 2);
}

TEST_CASE(
    "stream regeneration keeps batches full: only the frame's last paths trace small batches") {
  // 24 576 paths in a wavefront of 4096. Without regeneration each of the 6 wavefronts would drain
  // to its longest path in ever smaller batches; with it, small batches come only at the end of
  // the frame. Measured: the share of bounce rays traced in calls of under a quarter wavefront.
  Scene scene;
  scene.geometry = inward_box();
  Material wall = Material::lambert(glm::vec3(0.8f));
  scene.materials = {wall, wall};
  scene.materials[1].emission = glm::vec3(1.f);
  scene.geometry.material[0] = 1;
  scene.cameras = {looking_at(glm::vec3(0.f), glm::vec3(0, 0, -1), 1.2f)};
  RenderSettings s;
  s.width = 64, s.height = 48, s.spp = 8;
  s.wavefront = 4096;
  Result r = render(scene, s);
  uint64_t all = 0, small = 0;
  for (uint32_t n : r.stats.bounce_batches) all += n, small += n < 1024 ? n : 0;
  MESSAGE(r.stats.bounce_calls << " bounce calls, " << all << " bounce rays, " << small
                               << " of them in calls under 1024 rays");
  CHECK(all == r.stats.by_type[size_t(RayType::bounce)].rays);
  CHECK(r.stats.bounce_batches.size() == r.stats.bounce_calls);
  CHECK(double(small) < 0.05 * double(all));
  CHECK(r.stats.by_bounce.size() > 8);  // paths do go deep: the test is not trivially met
}

TEST_CASE("the default wavefront follows the memory budget") {
  RenderSettings s;
  CHECK(resolve_wavefront(s, 1000) == 1000u);  // the whole frame, when it fits
  CHECK(resolve_wavefront(s, uint64_t(1) << 40) == s.wavefront_budget / path_state_bytes);
  s.wavefront_budget = 100 * path_state_bytes;
  CHECK(resolve_wavefront(s, 1000) == 100u);
  s.wavefront = 7;
  CHECK(resolve_wavefront(s, 1000) == 7u);
  CHECK(resolve_wavefront(s, 5) == 5u);
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
  CHECK_THROWS_AS(Integrator::create("nope", scene, *b, s), Error);
  s.camera = 1;
  CHECK_THROWS_AS(Integrator::create("path", scene, *b, s), Error);
}

// A black alpha-tested square [0, 1]² at z = 0 in front of an emitter of radiance 1 at z = −1,
// seen straight on by an orthographic camera whose 8 × 8 pixels cover the square: a pixel shows 1
// where rays pass the square and 0 where they stop on it.
Scene alpha_scene(Material::AlphaMode mode, float alpha) {
  Scene scene;
  scene.geometry = quad_grid(1);  // material 0
  const Geometry back = quad_grid(1, 3.f);
  for (size_t t = 0; t < back.size(); ++t)
    scene.geometry.add(back.vertex(t, 0) + glm::vec3(-1, -1, -1),
                       back.vertex(t, 1) + glm::vec3(-1, -1, -1),
                       back.vertex(t, 2) + glm::vec3(-1, -1, -1), 1);
  Material front = Material::lambert(glm::vec3(0.f));
  front.alpha_mode = mode;
  front.alpha = alpha;
  Material light = Material::lambert(glm::vec3(0.f));
  light.emission = glm::vec3(1.f);
  scene.materials = {front, light};
  Camera cam = looking_at(glm::vec3(0.5f, 0.5f, 3.f), glm::vec3(0.5f, 0.5f, 0.f), 1.f);
  cam.orthographic = true;
  cam.ymag = 0.5f;
  scene.cameras = {cam};
  return scene;
}

TEST_CASE("alpha MASK: rays pass where the coverage is below the cutoff, in every backend") {
  // Coverage = x through the vertex colours' alpha; the cutoff 0.5 opens the left half.
  Scene scene = alpha_scene(Material::AlphaMode::mask, 1.f);
  for (size_t t = 0; t < scene.geometry.size(); ++t)
    for (int k = 0; k < 3; ++k)
      scene.colors.push_back(glm::vec4(1.f, 1.f, 1.f, t < 2 ? scene.geometry.vertex(t, k).x : 1.f));
  RenderSettings s;
  s.width = s.height = 8, s.spp = 4, s.max_depth = 0;
  for (const char* backend : {"dacrt", "brute", "dacrt-naive"}) {
    INFO(backend);
    Result r = render(scene, s, backend);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        if (x == 3 || x == 4) continue;  // the cutoff runs along their shared edge
        INFO("pixel " << x << ", " << y);
        CHECK(r.film.mean_and_error(size_t(y) * 8 + x).x == (x < 3 ? 1.0 : 0.0));
      }
    CHECK(std::find(r.stats.skipped.begin(), r.stats.skipped.end(),
                    "alpha tests (every material is opaque)") == r.stats.skipped.end());
  }
  // OPAQUE ignores the same coverage.
  scene.materials[0].alpha_mode = Material::AlphaMode::opaque;
  Result opaque = render(scene, s);
  for (size_t p = 0; p < opaque.film.pixels(); ++p) CHECK(opaque.film.mean_and_error(p).x == 0.0);
}

TEST_CASE("alpha BLEND: a surface of alpha 0.3 lets 0.7 through, the same for every backend") {
  Scene scene = alpha_scene(Material::AlphaMode::blend, 0.3f);
  RenderSettings s;
  s.width = s.height = 8, s.spp = 256, s.max_depth = 0;
  Result r = render(scene, s);
  check_renders(r.film, 0.7);
  Result brute = render(scene, s, "brute");
  CHECK(r.film.resolve().rgb == brute.film.resolve().rgb);
}

TEST_CASE("alpha BLEND: shadow rays see through it as camera rays do") {
  // lit_plane under a directional light straight down (E = 1: radiance 0.5 / π), with a black
  // square of alpha 0.3 between them and the camera: 0.7 of the camera rays reach the plane,
  // and 0.7 of the light does.
  Scene scene = lit_plane();
  const glm::vec3 a(-3, -3, 0.5f), b(3, -3, 0.5f), c(3, 3, 0.5f), d(-3, 3, 0.5f);
  scene.geometry.add(a, b, c, 1);
  scene.geometry.add(a, c, d, 1);
  Material veil = Material::lambert(glm::vec3(0.f));
  veil.alpha_mode = Material::AlphaMode::blend;
  veil.alpha = 0.3f;
  veil.double_sided = true;
  scene.materials.push_back(veil);
  PunctualLight sun;
  sun.type = PunctualLight::Type::directional;
  sun.direction = glm::vec3(0, 0, -1);
  scene.lights = {sun};
  RenderSettings s;
  s.width = s.height = 16, s.spp = 256;
  Result r = render(scene, s);
  CHECK(r.stats.by_type[size_t(RayType::shadow)].rays > 0);
  check_renders(r.film, 0.7 * 0.7 * 0.5 / glm::pi<double>());
}

namespace {

// The unit square of quad_grid(1) as a thin dielectric sheet (no camera yet).
Scene sheet_scene(const glm::vec3& color, float roughness, float transmission) {
  Scene scene;
  scene.geometry = quad_grid(1);
  Material sheet;
  sheet.base_color = color;
  sheet.metallic = 0.f;
  sheet.roughness = roughness;
  sheet.transmission = transmission;
  scene.materials = {sheet};
  return scene;
}

}  // namespace

TEST_CASE("transmission: a smooth white thin sheet under a uniform sky of 1 renders 1") {
  Scene scene = sheet_scene(glm::vec3(1.f), 0.f, 1.f);
  scene.cameras = {looking_at(glm::vec3(0.5f, 0.2f, 2.f), glm::vec3(0.5f, 0.5f, 0.f), 0.8f)};
  RenderSettings s;
  s.width = s.height = 16, s.spp = 32, scene.environment = glm::vec3(1.f);
  Result r = render(scene, s);
  check_renders(r.film, 1.0);
  // (Without the rays that cross to the far side the sheet would show only its Fresnel
  // reflection, ~0.04.) A transmissive scene does not skip transmission; an opaque one does.
  const std::string skip = "transmission (no transmissive material)";
  CHECK(std::find(r.stats.skipped.begin(), r.stats.skipped.end(), skip) == r.stats.skipped.end());
  scene.materials[0].transmission = 0.f;
  Result opaque = render(scene, s);
  CHECK(std::find(opaque.stats.skipped.begin(), opaque.stats.skipped.end(), skip) !=
        opaque.stats.skipped.end());
}

TEST_CASE("transmission: next-event estimation lights a rough sheet through its back") {
  // An orthographic camera looks straight at a rough white sheet (transmission 1) lit by a
  // directional light of irradiance 1: from behind, shining towards the camera, the sheet shows
  // f_t(wo, −wo) = (1 − F0) D(n) V; from the front, f_r = F0 D(n) V (no diffuse left).
  for (const bool behind : {true, false}) {
    INFO((behind ? "behind" : "in front"));
    Scene scene = sheet_scene(glm::vec3(1.f), 0.5f, 1.f);
    Camera cam = looking_at(glm::vec3(0.5f, 0.5f, 3.f), glm::vec3(0.5f, 0.5f, 0.f), 1.f);
    cam.orthographic = true;
    cam.ymag = 0.25f;
    scene.cameras = {cam};
    PunctualLight sun;
    sun.type = PunctualLight::Type::directional;
    sun.direction = glm::vec3(0, 0, behind ? 1.f : -1.f);
    scene.lights = {sun};
    RenderSettings s;
    s.width = s.height = 8, s.spp = 16, s.max_depth = 1;
    Result r = render(scene, s);
    const float alpha = 0.25f, f0 = 0.04f;
    const double lobe = ggx_d(1.f, alpha) * ggx_visibility(1.f, 1.f, alpha);
    const double expected = (behind ? 1.0 - f0 : f0) * lobe;
    for (size_t p = 0; p < r.film.pixels(); ++p)
      CHECK(r.film.mean_and_error(p).x == doctest::Approx(expected).epsilon(1e-4));
  }
}

TEST_CASE("alpha: an emitter shines only as much as it covers, in next-event estimation too") {
  // lit_plane with a downward emitter of radiance 4 beside the camera's view: opaque it lights
  // the plane; as a MASK of alpha 0 it is not there at all; as a BLEND of alpha 0.25, a quarter.
  auto render_with = [](Material::AlphaMode mode, float alpha) {
    Scene scene = lit_plane();
    const glm::vec3 a(1.5f, -0.5f, 1), b(2.5f, -0.5f, 1), c(2.5f, 0.5f, 1), d(1.5f, 0.5f, 1);
    scene.geometry.add(a, c, b, 1);  // facing −z
    scene.geometry.add(a, d, c, 1);
    Material light = Material::lambert(glm::vec3(0.f));
    light.emission = glm::vec3(4.f);
    light.alpha_mode = mode;
    light.alpha = alpha;
    scene.materials.push_back(light);
    RenderSettings s;
    s.width = s.height = 16, s.spp = 64;
    Result r = render(scene, s);
    double sum = 0.0, var = 0.0;
    for (size_t p = 0; p < r.film.pixels(); ++p) {
      const glm::dvec2 m = r.film.mean_and_error(p);
      sum += m.x, var += m.y * m.y;
    }
    return std::pair{sum / double(r.film.pixels()), std::sqrt(var) / double(r.film.pixels())};
  };
  const auto [opaque, opaque_error] = render_with(Material::AlphaMode::opaque, 1.f);
  CHECK(opaque > 100.0 * opaque_error);
  CHECK(render_with(Material::AlphaMode::mask, 0.f).first == 0.0);
  const auto [quarter, quarter_error] = render_with(Material::AlphaMode::blend, 0.25f);
  INFO("opaque " << opaque << " ± " << opaque_error << ", blend " << quarter << " ± "
                 << quarter_error);
  CHECK(std::abs(quarter - 0.25 * opaque) <= 4.0 * std::hypot(quarter_error, 0.25 * opaque_error));
}

TEST_CASE("transmission: next-event estimation through a rough sheet agrees with BSDF sampling") {
  // A rough white sheet (transmission 0.7) under a sky of 1: as a uniform environment only BSDF
  // sampling finds it; as a constant map next-event estimation samples it too, on both sides,
  // weighed by MIS. Each pixel must agree within the two renders' errors.
  Scene scene = sheet_scene(glm::vec3(0.9f, 0.6f, 0.3f), 0.4f, 0.7f);
  scene.cameras = {looking_at(glm::vec3(0.5f, -0.3f, 1.5f), glm::vec3(0.5f, 0.5f, 0.f), 0.9f)};
  RenderSettings s;
  s.width = s.height = 12, s.spp = 256;
  scene.environment = glm::vec3(1.f);
  Result uniform = render(scene, s);
  Image one(4, 2);
  std::fill(one.rgb.begin(), one.rgb.end(), 1.f);
  scene.environment_map = std::make_shared<const EnvironmentMap>(one, "one");
  Result mapped = render(scene, s);
  size_t outliers = 0;
  double sum_a = 0.0, sum_b = 0.0, var = 0.0;
  for (size_t p = 0; p < uniform.film.pixels(); ++p) {
    const glm::dvec2 a = uniform.film.mean_and_error(p), b = mapped.film.mean_and_error(p);
    sum_a += a.x, sum_b += b.x, var += a.y * a.y + b.y * b.y;
    if (std::abs(a.x - b.x) > 5.0 * std::hypot(a.y, b.y) + 1e-5 && ++outliers <= 3)
      MESSAGE("pixel " << p << ": " << a.x << " ± " << a.y << " vs " << b.x << " ± " << b.y);
  }
  // The image means too: a biased weight can hide in noisy pixels but not in their mean (a MIS
  // weight of 1 for next-event estimation through the sheet was seen failing: 0.98 vs 0.86).
  const double n = double(uniform.film.pixels());
  MESSAGE("image means: BSDF sampling " << sum_a / n << ", with next-event estimation " << sum_b / n
                                        << " ± " << std::sqrt(var) / n);
  CHECK(std::abs(sum_a - sum_b) / n <= 4.0 * std::sqrt(var) / n);
  CHECK(outliers == 0);
  CHECK(mapped.stats.by_type[size_t(RayType::shadow)].rays > 0);
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
  s.width = s.height = 4, s.spp = 1, scene.environment = glm::vec3(1.f);
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
