// An emitter beside an environment map: light adds up. Rendered with the emitter alone (a black
// sky), with the map alone (the emitter's triangles black) and with both, the image means must
// add within their noise. Next-event estimation picks the map with some probability and the
// scene's emitters with the rest (integrators/light_sampling.h): an emitter's pdf that forgets
// the map's share weighs its samples wrongly, and the sum no longer holds.
#include <doctest/doctest.h>

#include <cmath>
#include <memory>

#include "lit_scene.h"
#include "render_check.h"

using namespace dacrt;

namespace {

// A Lambert floor under a small emissive square facing down (material 1), seen from above at an
// angle, so that most pixels see both the square's light and the sky's.
Scene floor_under_lamp(glm::vec3 emission) {
  Scene scene;
  test::add_square(scene.geometry, glm::vec2(-3.f), glm::vec2(3.f), 0.f, 0);
  const glm::vec3 a(-0.5f, -0.5f, 1.2f), b(0.5f, -0.5f, 1.2f), c(0.5f, 0.5f, 1.2f),
      d(-0.5f, 0.5f, 1.2f);
  scene.geometry.add(a, c, b, 1);  // facing −z
  scene.geometry.add(a, d, c, 1);
  Material lamp = Material::lambert(glm::vec3(0.f));
  lamp.emission = emission;
  scene.materials = {Material::lambert(glm::vec3(0.6f, 0.5f, 0.4f)), lamp};
  scene.cameras = {test::looking_at(glm::vec3(0.3f, -2.5f, 2.5f), glm::vec3(0.f), 0.9f)};
  return scene;
}

struct Mean {
  double value, variance;  // of the image mean (of the pixels' channel averages)
};

Mean image_mean(const Scene& scene, bool map) {
  RenderSettings s;
  s.width = s.height = 24;
  s.spp = 96;
  s.environment = glm::vec3(0.f);
  if (map) {
    Image sky(1, 1);
    sky.rgb = {0.7f, 0.8f, 0.9f};
    s.environment_map = std::make_shared<const EnvironmentMap>(sky, "constant sky");
  }
  const test::Result r = test::render(scene, s);
  double sum = 0.0, var = 0.0;
  for (size_t p = 0; p < r.film.pixels(); ++p) {
    const glm::dvec2 m = r.film.mean_and_error(p);
    sum += m.x, var += m.y * m.y;
  }
  const double n = double(r.film.pixels());
  return {sum / n, var / (n * n)};
}

}  // namespace

TEST_CASE("an emitter beside a constant map: the two alone add up to both together") {
  const glm::vec3 emission(4.f, 3.f, 2.f);
  const Mean lamp = image_mean(floor_under_lamp(emission), false);
  const Mean sky = image_mean(floor_under_lamp(glm::vec3(0.f)), true);
  const Mean both = image_mean(floor_under_lamp(emission), true);
  const double error = std::sqrt(lamp.variance + sky.variance + both.variance);
  INFO("lamp " << lamp.value << ", sky " << sky.value << ", both " << both.value << " ± "
               << error);
  // The lamp's share is no small part of the sum, else the check would see nothing.
  REQUIRE(lamp.value > 20.0 * error);
  REQUIRE(sky.value > 20.0 * error);
  CHECK(std::abs(both.value - (lamp.value + sky.value)) <= 4.0 * error);
}
