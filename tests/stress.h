// The numerical stress suite's scenes and checks (issue 13, item 6). Each scene is built at a
// Placement (every point p becomes scale · p + translate · (1, 1, 1), in double, then rounded to
// float) and rendered through RenderJob by every backend; each check answers whether it holds
// there, with a message saying why not. stress_test.cpp runs them at the levels the README claims
// (in ctest) and, in `make stress`, sweeps translation and scale by powers of ten.
#pragma once

#include <cmath>
#include <functional>
#include <glm/glm.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "dacrt/render/render_job.h"
#include "render_check.h"
#include "dacrt/scene/scene.h"
#include "test_geometry.h"
#include "dacrt/tracer/backend.h"

namespace dacrt::test::stress {

struct Placement {
  double translate = 0.0, scale = 1.0;
  glm::vec3 operator()(const glm::dvec3& p) const {
    return glm::vec3(p * scale + glm::dvec3(translate));
  }
  glm::vec3 operator()(const glm::vec3& p) const { return (*this)(glm::dvec3(p)); }
};

inline std::string describe(const Placement& at) {
  std::ostringstream s;
  s << "translate " << at.translate << ", scale " << at.scale;
  return s.str();
}

// Every backend this build has: the three of ours, and embree when it was found.
inline std::vector<std::string> backends() {
  std::vector<std::string> out = {"dacrt", "dacrt-naive", "brute"};
  for (const std::string& name : Backend::names())
    if (name == "embree") out.push_back(name);
  return out;
}

using Rendered = Result;  // tests/render_check.h

// A test scene and the uniform environment its renders add (a render's choice, not the scene's).
struct Lit {
  Scene scene;
  glm::vec3 environment{0.f};
};

inline Rendered render(const Scene& scene, const RenderSettings& s, const std::string& backend) {
  return test::render(scene, s, backend.c_str());
}
inline Rendered render(const Lit& lit, RenderSettings s, const std::string& backend) {
  s.environment = lit.environment;
  return render(lit.scene, s, backend);
}

// A check's answer: empty when it holds, else why not (the first few failures).
struct Verdict {
  std::string failure;
  size_t failures = 0;
  bool holds() const { return failures == 0; }
  void fail(const std::string& why) {
    if (failures++ < 3) failure += (failure.empty() ? "" : "; ") + why;
  }
};

// No NaN or inf: every channel of every pixel finite, and no sample dropped by the film for not
// being finite (a dropped sample is a silent bias).
inline void check_finite(const Rendered& r, Verdict& v) {
  if (r.stats.dropped_samples != 0 || r.film.dropped() != 0)
    v.fail(std::to_string(r.film.dropped()) + " samples not finite (dropped)");
  const Image img = r.film.resolve();
  for (size_t p = 0; p < img.rgb.size(); ++p)
    if (!std::isfinite(img.rgb[p])) {
      v.fail("pixel value " + std::to_string(p / 3) + " not finite");
      break;
    }
}

// ---- Scenes
// --------------------------------------------------------------------------------------

// A closed box [-1, 1]³ whose faces are n × n grids (every grid vertex shared exactly by its
// neighbours, so the mesh is closed at any placement: equal coordinates place equally).
inline void add_box(Geometry& g, const Placement& at, int n, uint32_t material) {
  for (int axis = 0; axis < 3; ++axis)
    for (double side : {-1.0, 1.0})
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto corner = [&](int a, int b) {
            glm::dvec3 p;
            p[axis] = side;
            p[(axis + 1) % 3] = -1.0 + 2.0 * a / n;
            p[(axis + 2) % 3] = -1.0 + 2.0 * b / n;
            return at(p);
          };
          g.add(corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), material);
          g.add(corner(i, j), corner(i + 1, j + 1), corner(i, j + 1), material);
        }
}

// Lights that shine on a closed mesh around [-1, 1]³ from outside: a uniform environment of 1,
// a directional light and a point light.
inline Lit light_from_outside(Scene scene, const Placement& at) {
  PunctualLight sun;
  sun.type = PunctualLight::Type::directional;
  sun.direction = glm::normalize(glm::vec3(-0.4f, -0.5f, -0.77f));
  sun.intensity = glm::vec3(3.f);
  PunctualLight bulb;
  bulb.position = at(glm::dvec3(3.0, 2.5, 4.0));
  bulb.intensity = glm::vec3(float(20.0 * at.scale * at.scale));  // 20 / d² at unit scale
  if (!(bulb.intensity.x > 0.f) || !std::isfinite(bulb.intensity.x))
    bulb.intensity = glm::vec3(1.f);
  scene.lights = {sun, bulb};
  return {std::move(scene), glm::vec3(1.f)};
}

// The camera inside a closed box lit from outside; the box is two closed meshes on the same six
// planes, overlapping and tessellated differently (4 × 4 and 3 × 3 per face).
inline Lit closed_box(const Placement& at) {
  Scene scene;
  add_box(scene.geometry, at, 4, 0);
  add_box(scene.geometry, at, 3, 0);
  scene.materials = {Material::lambert(glm::vec3(0.8f))};
  // Aimed at a corner, wide: the view takes in three faces, their edges and a vertex.
  scene.cameras = {
      looking_at(at(glm::dvec3(0.3, -0.2, 0.25)), at(glm::dvec3(1.0, 0.7, -1.0)), 1.5f)};
  return light_from_outside(std::move(scene), at);
}

// The camera inside a closed, jittered UV sphere (poles and seams: vertices shared by up to 24
// triangles) lit from outside.
inline Lit closed_sphere(const Placement& at) {
  Scene scene;
  const Geometry unit = sphere(12, 24, glm::vec3(0.f), 1.f, 0.1f, 5);
  for (size_t t = 0; t < unit.size(); ++t)
    scene.geometry.add(at(unit.vertex(t, 0)), at(unit.vertex(t, 1)), at(unit.vertex(t, 2)), 0);
  scene.materials = {Material::lambert(glm::vec3(0.8f))};
  scene.cameras = {looking_at(at(glm::dvec3(0.1, 0.2, -0.1)), at(glm::dvec3(0.0, 1.0, 0.0)), 1.6f)};
  return light_from_outside(std::move(scene), at);
}

// The grazing plane: a 200 × 200 square of 20 × 20 cells tilted to the normal n = (0, 0.6, 0.8)
// (spanned by (1, 0, 0) and (0, 0.8, -0.6), with corners on a lattice of exact floats at any
// translation up to 2^24 / 16), Lambert of albedo 0.5, lit by a directional light 88° from its
// normal and seen by a camera 1 above it looking 40 ahead along it (1.4° from grazing): every
// camera ray meets it, far away and at a grazing angle.
constexpr double grazing_cos = 0.03489949670250097;  // cos 88°
inline const glm::dvec3 grazing_n(0.0, 0.6, 0.8), grazing_t1(1.0, 0.0, 0.0),
    grazing_t2(0.0, 0.8, -0.6);
inline glm::dvec3 grazing_light() {  // where the light's photons travel
  const double sin = std::sqrt(1.0 - grazing_cos * grazing_cos);
  return -(grazing_cos * grazing_n + sin * (0.6 * grazing_t1 + 0.8 * grazing_t2));
}

inline Lit grazing_plane(const Placement& at) {
  Scene scene;
  auto corner = [&](int i, int j) { return at(10.0 * i * grazing_t1 + 10.0 * j * grazing_t2); };
  for (int i = -10; i < 10; ++i)
    for (int j = -10; j < 10; ++j) {
      scene.geometry.add(corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), 0);
      scene.geometry.add(corner(i, j), corner(i + 1, j + 1), corner(i, j + 1), 0);
    }
  scene.materials = {Material::lambert(glm::vec3(0.5f))};
  PunctualLight sun;
  sun.type = PunctualLight::Type::directional;
  sun.direction = glm::vec3(grazing_light());
  sun.intensity = glm::vec3(2.f);
  scene.lights = {sun};
  const glm::dvec3 eye = grazing_n - 40.0 * grazing_t2;
  Camera cam = looking_at(at(eye), at(glm::dvec3(0.0)), 0.0175f);  // 1° of view
  // looking_at aims with +y up; the plane's normal is the view's up here, which keeps every
  // pixel's ray on the plane (+y is close enough to it: n · y = 0.6).
  scene.cameras = {cam};
  return {std::move(scene)};
}

// What every sample of the grazing plane is: the Lambert BRDF times the light's irradiance.
inline double grazing_value() {
  return 0.5 / 3.141592653589793 * 2.0 * grazing_cos;
}

// Slivers, degenerate triangles (repeated and collinear corners) and two overlapping coplanar
// quads tessellated differently, lit by an emissive quad, a point light and an environment.
inline Lit hard_triangles(const Placement& at) {
  Scene scene;
  Geometry& g = scene.geometry;
  const Geometry thin = slivers(150, 9);
  for (size_t t = 0; t < thin.size(); ++t)
    g.add(at(thin.vertex(t, 0)), at(thin.vertex(t, 1)), at(thin.vertex(t, 2)), 0);
  const glm::dvec3 a(0.1, 0.2, 0.3), b(0.9, 0.4, 0.6), c(0.3, 0.8, 0.1);
  g.add(at(a), at(a), at(b), 0);                   // two corners equal
  g.add(at(a), at(b), at(0.5 * (a + b)), 0);       // collinear
  g.add(at(a), at(a), at(a), 0);                   // a point
  g.add(at(a), at(b), at(a + 1e-7 * (c - a)), 0);  // a needle, almost collinear
  // Overlapping coplanar quads at y = -0.2: [-0.5, 1.5]² as two triangles, and as eight.
  auto floor = [&](double x, double z) { return at(glm::dvec3(x, -0.2, z)); };
  g.add(floor(-0.5, -0.5), floor(1.5, 1.5), floor(1.5, -0.5), 1);
  g.add(floor(-0.5, -0.5), floor(-0.5, 1.5), floor(1.5, 1.5), 1);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      const double x = -0.5 + i, z = -0.5 + j;
      g.add(floor(x, z), floor(x + 1, z + 1), floor(x + 1, z), 0);
      g.add(floor(x, z), floor(x, z + 1), floor(x + 1, z + 1), 0);
    }
  // The emitter: a quad at y = 2 facing down.
  auto top = [&](double x, double z) { return at(glm::dvec3(x, 2.0, z)); };
  g.add(top(0.2, 0.2), top(0.8, 0.2), top(0.8, 0.8), 2);
  g.add(top(0.2, 0.2), top(0.8, 0.8), top(0.2, 0.8), 2);
  Material light = Material::lambert(glm::vec3(0.f));
  light.emission = glm::vec3(5.f);
  Material metal;
  metal.base_color = glm::vec3(0.9f), metal.roughness = 0.2f;
  scene.materials = {Material::lambert(glm::vec3(0.7f)), metal, light};
  PunctualLight bulb;
  bulb.position = at(glm::dvec3(-1.0, 1.5, 2.0));
  bulb.intensity = glm::vec3(float(4.0 * at.scale * at.scale));
  if (!(bulb.intensity.x > 0.f) || !std::isfinite(bulb.intensity.x))
    bulb.intensity = glm::vec3(1.f);
  scene.lights = {bulb};
  scene.cameras = {looking_at(at(glm::dvec3(0.5, 0.9, 2.6)), at(glm::dvec3(0.5, 0.2, 0.4)), 0.9f)};
  return {std::move(scene), glm::vec3(0.3f)};
}

// ---- Checks
// --------------------------------------------------------------------------------------

inline RenderSettings small_settings(int spp, int max_depth = 64) {
  RenderSettings s;
  s.width = 16, s.height = 12, s.spp = spp, s.max_depth = max_depth, s.seed = 7;
  return s;
}

// No NaN or inf on any of the scenes, for `backend`.
inline Verdict finite_everywhere(const Placement& at, const std::string& backend) {
  Verdict v;
  for (const Lit& lit : {closed_box(at), closed_sphere(at), grazing_plane(at), hard_triangles(at)})
    check_finite(render(lit, small_settings(4), backend), v);
  return v;
}

// No light inside a closed mesh lit from outside: exactly 0 at every pixel.
inline Verdict no_leaks(const Placement& at, const std::string& backend) {
  Verdict v;
  int which = 0;
  for (const Lit& lit : {closed_box(at), closed_sphere(at)}) {
    const Rendered r = render(lit, small_settings(8), backend);
    check_finite(r, v);
    for (size_t p = 0; p < r.film.pixels(); ++p) {
      const double m = r.film.mean_and_error(p).x;
      if (m != 0.0)
        v.fail(std::string(which ? "sphere" : "box") + " pixel " + std::to_string(p) + " is " +
               std::to_string(m));
    }
    ++which;
  }
  return v;
}

// No acne: every sample of the grazing plane is grazing_value(), up to float rounding of the
// cosine (relative ~1e-5 at cos 88°). A shadow ray that finds the plane itself blackens its
// sample and moves the pixel's mean by value / spp: the tolerance is half that, so one shadowed
// sample in any pixel fails the check.
inline Verdict no_acne(const Placement& at, const std::string& backend, int spp = 16) {
  Verdict v;
  const Rendered r = render(grazing_plane(at), small_settings(spp, 1), backend);
  check_finite(r, v);
  const double expected = grazing_value(), tolerance = 0.5 * expected / spp;
  for (size_t p = 0; p < r.film.pixels(); ++p) {
    const double m = r.film.mean_and_error(p).x;
    if (!(std::abs(m - expected) <= tolerance))
      v.fail("pixel " + std::to_string(p) + " is " + std::to_string(m) + ", not " +
             std::to_string(expected));
  }
  return v;
}

// ---- Closest hits against brute force
// --------------------------------------------------------------

// Rays whose origins lie exactly on vertices and edges (tmin 0, random directions and directions
// along the edges), rays aimed exactly at vertices and edge midpoints from outside, grazing rays
// over a large plane, for one triangle set.
inline RayBatch stress_rays(const Geometry& g, uint64_t seed) {
  Pcg32 rng(seed);
  RayBatch rays;
  rays.type = RayType::bounce;
  const Box box = g.bounds();
  const glm::vec3 centre = 0.5f * (box.lo + box.hi);
  const float size = glm::length(box.extent());
  uint32_t n = 0;
  for (size_t t = 0; t < g.size(); t += 1 + rng.below(3)) {
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 a = g.vertex(t, k), b = g.vertex(t, (k + 1) % 3);
      const glm::vec3 mid = 0.5f * (a + b);
      rays.push(a, random_direction(rng), 0.f, INFINITY, n++);    // from a vertex
      rays.push(mid, random_direction(rng), 0.f, INFINITY, n++);  // from an edge
      if (b != a) rays.push(a, b - a, 0.f, INFINITY, n++);        // along an edge
      const glm::vec3 from = centre + size * random_direction(rng);
      rays.push(from, a - from, 0.f, INFINITY, n++);        // at a vertex
      rays.push(from, mid - from, 0.f, INFINITY, n++);      // at an edge
      rays.push(centre, mid - centre, 0.f, INFINITY, n++);  // from inside, at an edge
    }
  }
  return rays;
}

// Grazing rays over the grazing plane: from 1e-2 to 1e-6 above it, climbing or falling by angles
// of 1e-1 to 1e-7 radians.
inline RayBatch grazing_rays(const Placement& at, uint64_t seed) {
  Pcg32 rng(seed);
  RayBatch rays;
  rays.type = RayType::bounce;
  uint32_t n = 0;
  for (int k = 0; k < 2000; ++k) {
    const double height = std::pow(10.0, -2.0 - 4.0 * rng.uniform()) * (rng.below(2) ? 1 : -1);
    const double angle = std::pow(10.0, -1.0 - 6.0 * rng.uniform()) * (rng.below(2) ? 1 : -1);
    const double phi = 6.283185307179586 * rng.uniform();
    const glm::dvec3 along = std::cos(phi) * grazing_t1 + std::sin(phi) * grazing_t2;
    const glm::dvec3 o = 90.0 * (2.0 * rng.uniform() - 1.0) * grazing_t1 +
                         90.0 * (2.0 * rng.uniform() - 1.0) * grazing_t2 + height * grazing_n;
    const glm::dvec3 d = std::cos(angle) * along + std::sin(angle) * grazing_n;
    rays.push(at(o), glm::vec3(d), 0.f, INFINITY, n++);
  }
  return rays;
}

// The same closest hit (triangle, t, u, v bit for bit) and occlusion answer as brute force.
inline void same_as_brute(const Geometry& g, const RayBatch& rays, const std::string& backend,
                          Verdict& v, const char* what) {
  auto brute = Backend::create("brute", g), other = Backend::create(backend, g);
  HitBatch expect, got;
  brute->intersect(rays, expect);
  other->intersect(rays, got);
  for (size_t i = 0; i < rays.size(); ++i)
    if (expect.prim[i] != got.prim[i] ||
        (expect.hit(i) &&
         (expect.t[i] != got.t[i] || expect.u[i] != got.u[i] || expect.v[i] != got.v[i])))
      v.fail(std::string(what) + " ray " + std::to_string(i) + ": triangle " +
             std::to_string(got.prim[i]) + " at " + std::to_string(got.t[i]) + ", brute " +
             std::to_string(expect.prim[i]) + " at " + std::to_string(expect.t[i]));
  std::vector<uint8_t> a(rays.size()), b(rays.size());
  brute->occluded(rays, a);
  other->occluded(rays, b);
  for (size_t i = 0; i < rays.size(); ++i)
    if (a[i] != b[i])
      v.fail(std::string(what) + " ray " + std::to_string(i) + ": occlusion differs");
}

inline Verdict closest_hits(const Placement& at, const std::string& backend) {
  Verdict v;
  const Scene box = closed_box(at).scene, ball = closed_sphere(at).scene,
              plane = grazing_plane(at).scene, hard = hard_triangles(at).scene;
  same_as_brute(box.geometry, stress_rays(box.geometry, 1), backend, v, "box");
  same_as_brute(ball.geometry, stress_rays(ball.geometry, 2), backend, v, "sphere");
  same_as_brute(hard.geometry, stress_rays(hard.geometry, 3), backend, v, "slivers");
  same_as_brute(plane.geometry, stress_rays(plane.geometry, 4), backend, v, "plane");
  same_as_brute(plane.geometry, grazing_rays(at, 5), backend, v, "grazing");
  return v;
}

// ---- The checks by name ------------------------------------------------------------------------

struct Check {
  const char* name;
  std::function<Verdict(const Placement&, const std::string&)> run;
  bool exact_backends_only = false;  // closest hits: dacrt and dacrt-naive against brute
};

inline std::vector<Check> checks() {
  return {{"no NaN or inf", finite_everywhere},
          {"no light leaks", no_leaks},
          {"no acne", [](const Placement& at, const std::string& b) { return no_acne(at, b); }},
          {"closest hit = brute", closest_hits, true}};
}

}  // namespace dacrt::test::stress
