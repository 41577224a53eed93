// lit_scene: a small scene made in code that every kind of light reaches (an emissive square, a
// point light, an environment map, a glossy box), for the render tests and the MPI check.
#pragma once

#include <glm/glm.hpp>
#include <memory>

#include "dacrt/render/render_job.h"
#include "test_geometry.h"

namespace dacrt::test {

// The square [lo, hi]² in the plane z, facing +z.
inline void add_square(Geometry& g, glm::vec2 lo, glm::vec2 hi, float z = 0.f,
                       uint32_t material = 0) {
  const glm::vec3 a(lo.x, lo.y, z), b(hi.x, lo.y, z), c(hi.x, hi.y, z), d(lo.x, hi.y, z);
  g.add(a, b, c, material);
  g.add(a, c, d, material);
}

// A floor lit by everything a path can meet: an emissive square facing down, a point light, an
// environment map that is not uniform (so next-event estimation samples it: lit_settings), a
// mirror-ish box.
inline Scene lit_scene() {
  Scene scene;
  add_square(scene.geometry, glm::vec2(-3.f), glm::vec2(3.f), 0.f, 0);
  const glm::vec3 a(-0.4f, -0.4f, 1.5f), b(0.4f, -0.4f, 1.5f), c(0.4f, 0.4f, 1.5f),
      d(-0.4f, 0.4f, 1.5f);
  scene.geometry.add(a, c, b, 1);  // facing −z
  scene.geometry.add(a, d, c, 1);
  const Geometry box = inward_box();
  for (size_t t = 0; t < box.size(); ++t) {
    auto v = [&](int k) { return 0.3f * box.vertex(t, k) + glm::vec3(0.8f, 0.2f, 0.3f); };
    scene.geometry.add(v(0), v(2), v(1), 2);  // facing outwards
  }
  Material light = Material::lambert(glm::vec3(0.f));
  light.emission = glm::vec3(3.f, 2.f, 1.f);
  Material metal;
  metal.base_color = glm::vec3(0.9f, 0.7f, 0.5f), metal.roughness = 0.3f;
  scene.materials = {Material::lambert(glm::vec3(0.7f, 0.6f, 0.5f)), light, metal};
  PunctualLight point;
  point.position = glm::vec3(-1.f, 0.5f, 1.f);
  point.intensity = glm::vec3(2.f);
  scene.lights = {point};
  scene.cameras = {looking_at(glm::vec3(0.5f, -2.5f, 2.f), glm::vec3(0.f, 0.f, 0.3f), 1.2f)};
  return scene;
}

// Settings for lit_scene: its environment map.
inline RenderSettings lit_settings() {
  Image sky(16, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) sky.pixel(x, y)[c] = 0.1f + 0.1f * float(x % 5 + y + c);
  RenderSettings s;
  s.environment_map = std::make_shared<const EnvironmentMap>(sky, "sky");
  return s;
}

}  // namespace dacrt::test
