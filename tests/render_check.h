// What the render tests share: render a scene with a backend and an integrator, check each pixel
// of the image against a known answer within its own standard error, and a Lambert plane under an
// orthographic camera for lights to shine on.
#pragma once

#include <doctest/doctest.h>

#include <cmath>
#include <utility>

#include "dacrt/integrators/integrator.h"
#include "dacrt/render/render_job.h"
#include "test_geometry.h"

namespace dacrt::test {

struct Result {
  Film film;
  RenderStats stats;
};

inline Result render(const Scene& scene, RenderSettings s, const char* backend = "dacrt",
                     const char* integrator = "path") {
  s.integrator = integrator;
  auto b = Backend::create(backend, scene.geometry);
  RenderJob job(scene, *b, s);
  Film film = job.film();
  Progress quiet("test", 1, false);
  job.run(film, 0, uint32_t(s.spp), quiet);
  return {std::move(film), job.stats()};
}

// Every pixel within z standard errors of `expected` (z = 5: a false alarm over a few thousand
// pixels has probability ~1e-3), and the image mean within 4 of its own standard error. The
// pixel's standard error is its own samples' (s / √n), so that z is near normal only when every
// pixel has enough samples of each kind its estimator mixes (see the closed box in
// integrator_test.cpp).
inline void check_renders(const Film& film, double expected, double z = 5.0) {
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

// A Lambert square of albedo 0.5 in z = 0 ([-2, 2]², facing +z) seen from straight above by an
// orthographic camera whose 16 × 16 pixels cover [-1, 1]²: a pixel's value is the direct light
// on the part of the plane it sees, times 0.5 / π (bounces leave for a black sky).
inline Scene lit_plane() {
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

}  // namespace dacrt::test
