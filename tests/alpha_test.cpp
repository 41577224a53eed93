// Alpha in renders: MASK lets rays pass where the coverage is below the cutoff and BLEND lets
// 1 − alpha through, for camera and shadow rays alike, identically in every backend; an
// alpha-tested emitter lights by its coverage.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "render_check.h"
#include "test_geometry.h"

using namespace dacrt;
using namespace dacrt::test;

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
  s.environment = glm::vec3(0.f);  // its lights alone (a sky of 1 stays beside the file's lights)
  s.width = s.height = 16, s.spp = 256;
  Result r = render(scene, s);
  CHECK(r.stats.by_type[size_t(RayType::shadow)].rays > 0);
  check_renders(r.film, 0.7 * 0.7 * 0.5 / glm::pi<double>());
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
