// KHR_materials_volume and KHR_materials_dispersion in renders and in the path's media
// (integrators/media.h): a slab of known thickness and attenuation transmits c^(t/d) times its
// Fresnel terms, nested volumes refract by the ratio of their IORs and neither lose nor invent
// energy under a uniform sky, the media stack pushes, pops and overflows as documented, and a
// dispersive volume refracts each colour channel by its own IOR.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

#include "dacrt/integrators/media.h"
#include "render_check.h"
#include "test_geometry.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

// Adds triangle a b c of material `mat`, wound to face away from `inside`.
void add_outward(Geometry& g, glm::vec3 a, glm::vec3 b, glm::vec3 c, const glm::vec3& inside,
                 uint32_t mat) {
  if (glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.f - inside) < 0.f) std::swap(b, c);
  g.add(a, b, c, mat);
}

// An axis-aligned box [lo, hi], its faces looking out.
void add_box(Geometry& g, const glm::vec3& lo, const glm::vec3& hi, uint32_t mat) {
  const glm::vec3 s = hi - lo, centre = (lo + hi) * 0.5f;
  const glm::vec3 c[8] = {lo,
                          lo + glm::vec3(s.x, 0, 0),
                          lo + glm::vec3(0, s.y, 0),
                          lo + glm::vec3(s.x, s.y, 0),
                          lo + glm::vec3(0, 0, s.z),
                          lo + glm::vec3(s.x, 0, s.z),
                          lo + glm::vec3(0, s.y, s.z),
                          hi};
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 2, 6, 4},
                           {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}};
  for (const auto& f : faces) {
    add_outward(g, c[f[0]], c[f[1]], c[f[2]], centre, mat);
    add_outward(g, c[f[0]], c[f[2]], c[f[3]], centre, mat);
  }
}

// A closed sphere, its faces looking out.
void add_sphere(Geometry& g, const glm::vec3& centre, float radius, uint32_t mat) {
  const Geometry s = sphere(24, 48, centre, radius);
  for (size_t t = 0; t < s.size(); ++t)
    add_outward(g, s.vertex(t, 0), s.vertex(t, 1), s.vertex(t, 2), centre, mat);
}

// A smooth, white, fully transmissive volume material.
Material glass(float ior, const glm::vec3& attenuation_color = glm::vec3(1.f),
               float attenuation_distance = INFINITY) {
  Material m;
  m.base_color = glm::vec3(1.f);
  m.metallic = 0.f;
  m.roughness = 0.f;
  m.ior = ior;
  m.transmission = 1.f;
  m.thickness = 1.f;
  m.attenuation_color = attenuation_color;
  m.attenuation_distance = attenuation_distance;
  return m;
}

// An orthographic camera looking straight down (−z) at the middle of whatever is below z = 5.
Camera looking_down() {
  Camera cam = looking_at(glm::vec3(0.f, 0.f, 5.f), glm::vec3(0.f), 1.f);
  cam.orthographic = true;
  cam.ymag = 0.5f;
  return cam;
}

// Each channel's image mean within 4 of its standard error (+ tolerance) of expected.
void check_channels(const Film& film, const glm::dvec3& expected, double tolerance = 1e-5) {
  const Image image = film.resolve();
  const size_t n = film.pixels();
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0, var = 0.0;
    for (size_t p = 0; p < n; ++p) {
      sum += image.rgb[3 * p + size_t(c)];
      var += film.variance_of_mean(p, c);
    }
    const double mean = sum / double(n), error = std::sqrt(var) / double(n);
    INFO("channel " << c << ": " << mean << " ± " << error << ", expected " << expected[c]);
    CHECK(std::abs(mean - expected[c]) <= 4.0 * error + tolerance);
  }
}

// Seen head-on under a sky of 1, a smooth slab of interface reflectance R and internal
// transmittance τ shows its reflection plus its transmission, with every internal echo:
//   R + (1 − R)² τ (1 + R τ) / (1 − R² τ²) = R + (1 − R)² τ / (1 − R τ).
double slab(double r, double tau) {
  return r + (1.0 - r) * (1.0 - r) * tau / (1.0 - r * tau);
}

}  // namespace

TEST_CASE("volume: an index-matched slab transmits exactly c^(t/d) per channel (Beer–Lambert)") {
  // Thickness t = 1 (the mesh's, not thicknessFactor's, which says only "a volume"),
  // attenuationDistance d = 2: τ = c^(1/2).
  Scene scene;
  add_box(scene.geometry, glm::vec3(-10, -10, 0), glm::vec3(10, 10, 1), 0);
  const glm::vec3 c(0.2f, 0.5f, 0.9f);
  scene.materials = {glass(1.f, c, 2.f)};
  scene.materials[0].thickness = 0.01f;  // thicknessFactor is a hint: any > 0 is the same
  scene.cameras = {looking_down()};
  RenderSettings s;
  s.width = s.height = 8, s.spp = 4, s.environment = glm::vec3(1.f);
  Result r = render(scene, s);
  // (Exact but for float rounding of exp and of the offset ray origins.)
  check_channels(r.film, glm::dvec3(std::sqrt(0.2), std::sqrt(0.5), std::sqrt(0.9)), 1e-4);
  // Thin-walled (thickness 0), the same material absorbs nothing.
  scene.materials[0].thickness = 0.f;
  check_channels(render(scene, s).film, glm::dvec3(1.0), 2e-5);
}

TEST_CASE("volume: a glass slab shows its Fresnel reflection and c^(t/d) through it") {
  // IOR 1.5 (R = 0.04 head-on), t = 1, c = 0.5 at d = 0.5: τ = 0.25.
  Scene scene;
  add_box(scene.geometry, glm::vec3(-10, -10, 0), glm::vec3(10, 10, 1), 0);
  scene.materials = {glass(1.5f, glm::vec3(0.5f), 0.5f)};
  scene.cameras = {looking_down()};
  RenderSettings s;
  s.width = s.height = 8, s.spp = 512, s.environment = glm::vec3(1.f);
  Result r = render(scene, s);
  check_channels(r.film, glm::dvec3(slab(0.04, 0.25)));
  check_renders(r.film, slab(0.04, 0.25));
}

TEST_CASE("volume: nested slabs of one IOR: the inner faces are index-matched, only absorb") {
  // A clear slab z ∈ [0, 3] of IOR 1.5 holding an absorbing one z ∈ [1, 2] of IOR 1.5 (c = 0.5,
  // d = 0.5: τ = 0.25 over its thickness 1): inside the outer volume the inner faces separate
  // IOR 1.5 from 1.5 and reflect nothing, so the pair is one slab of R = 0.04 and τ = 0.25. (Were
  // the inner faces taken as glass against air they would add their own reflections.)
  Scene scene;
  add_box(scene.geometry, glm::vec3(-10, -10, 0), glm::vec3(10, 10, 3), 0);
  add_box(scene.geometry, glm::vec3(-5, -5, 1), glm::vec3(5, 5, 2), 1);
  scene.materials = {glass(1.5f), glass(1.5f, glm::vec3(0.5f), 0.5f)};
  scene.cameras = {looking_down()};
  RenderSettings s;
  s.width = s.height = 8, s.spp = 512, s.environment = glm::vec3(1.f);
  check_channels(render(scene, s).film, glm::dvec3(slab(0.04, 0.25)));
}

TEST_CASE("volume: a sphere of water inside a sphere of glass under a sky of 1 renders 1") {
  // Clear and smooth: whatever the refractions and internal reflections, no energy is lost or
  // made, so every pixel sees the sky's 1 (the radiance inside is η² times larger, and the
  // interfaces' 1/η² and η² must cancel on the way in and out of each medium).
  Scene scene;
  add_sphere(scene.geometry, glm::vec3(0.f), 1.f, 0);
  add_sphere(scene.geometry, glm::vec3(0.1f, 0.f, 0.f), 0.5f, 1);
  scene.materials = {glass(1.5f), glass(1.33f)};
  scene.cameras = {looking_at(glm::vec3(0.f, 0.f, 4.f), glm::vec3(0.f), 0.5f)};
  RenderSettings s;
  s.width = s.height = 12, s.spp = 256, s.environment = glm::vec3(1.f);
  s.max_depth = 1000;  // (paths caught by total internal reflection bounce long)
  Result r = render(scene, s);
  check_renders(r.film, 1.0);
  check_channels(r.film, glm::dvec3(1.0));
}

TEST_CASE("volume: a point light inside an absorbing volume: shadow and camera rays attenuate") {
  // lit_plane's Lambert square (albedo 0.5, z = 0, seen from above over [−1, 1]²) inside an
  // index-matched box z ∈ [−1, 2] absorbing σ = ln 2 per unit (c = 0.5 at d = 1), a point light
  // of intensity 2 inside it: a pixel shows 0.5/π · 2 cos θ / d² · e^(−σ d) over the light's
  // distance d, times e^(−2σ) = 1/4 over the camera ray's 2 units inside (a black sky: nothing
  // else). The plane's vertices are the Lambert lanes', which must leave absorbing media alone.
  Scene scene = lit_plane();
  add_box(scene.geometry, glm::vec3(-3, -3, -1), glm::vec3(3, 3, 2), 1);
  scene.materials.push_back(glass(1.f, glm::vec3(0.5f), 1.f));
  PunctualLight l;
  l.intensity = glm::vec3(2.f);
  l.position = glm::vec3(0.3f, -0.2f, 1.f);
  scene.lights = {l};
  RenderSettings s;
  s.environment = glm::vec3(0.f);  // its lights alone (a sky of 1 stays beside the file's lights)
  s.width = s.height = 16, s.spp = 64;
  Result r = render(scene, s);
  const double sigma = std::log(2.0), brdf = 0.5 / glm::pi<double>();
  for (int y = 0; y < 16; y += 3)
    for (int x = 0; x < 16; x += 3) {
      double expected = 0.0;  // the pixel's mean over a 16 × 16 grid of points
      for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j) {
          const glm::dvec3 p(-1.0 + (x + (i + 0.5) / 16) / 8.0, 1.0 - (y + (j + 0.5) / 16) / 8.0,
                             0.0);
          const glm::dvec3 to = glm::dvec3(l.position) - p;
          const double d2 = glm::dot(to, to), d = std::sqrt(d2);
          expected += brdf * 2.0 * (to.z / d) / d2 * std::exp(-sigma * d) / 256.0;
        }
      expected *= 0.25;
      const glm::dvec2 m = r.film.mean_and_error(size_t(y) * 16 + x);
      INFO("pixel " << x << ", " << y << ": " << m.x << " ± " << m.y << ", expected " << expected);
      CHECK(std::abs(m.x - expected) <= 5.0 * m.y + 2e-3 * expected);
    }
}

TEST_CASE("volume: the media stack gives each interface the ratio of the IORs on its sides") {
  // Water (1.33) holding ice (1.31).
  Material water = glass(1.33f), ice = glass(1.31f), thin = glass(1.5f);
  thin.thickness = 0.f;
  const Media media({water, ice, thin});
  CHECK(media.any());
  CHECK(!media.absorbing());
  CHECK(!media.medium(2));  // thin-walled: not a medium
  MediumStack s;
  CHECK(media.eta(s, 0, true) == doctest::Approx(1.33f));  // air → water
  Media::cross(s, 0, true);
  CHECK(media.eta(s, 1, true) == doctest::Approx(1.31f / 1.33f));  // water → ice
  Media::cross(s, 1, true);
  CHECK(s.size == 2);
  CHECK(media.ior(s) == doctest::Approx(1.31f));
  CHECK(media.eta(s, 1, false) == doctest::Approx(1.33f / 1.31f));  // ice → water
  Media::cross(s, 1, false);
  CHECK(s.size == 1);
  CHECK(media.eta(s, 0, false) == doctest::Approx(1.f / 1.33f));  // water → air
  Media::cross(s, 0, false);
  CHECK(s.size == 0);
  // Leaving a volume the path was not recorded in removes nothing.
  Media::cross(s, 1, false);
  CHECK(s.size == 0);
  // Overflow: a fifth nested volume is not recorded; leaving it keeps the four.
  for (int k = 0; k < 5; ++k) Media::cross(s, uint32_t(k % 2), true);
  CHECK(s.size == MediumStack::depth);
  CHECK(s.material[3] == 1);
  MediumStack full = s;
  Media::cross(s, 7, false);
  CHECK(s.size == full.size);
  // Leaving a volume that is not on top (overlapping meshes) removes its topmost entry only.
  MediumStack o;
  Media::cross(o, 0, true), Media::cross(o, 1, true), Media::cross(o, 0, true);
  Media::cross(o, 1, false);
  REQUIRE(o.size == 2);
  CHECK(o.material[0] == 0);
  CHECK(o.material[1] == 0);
}

TEST_CASE("volume: Beer–Lambert's coefficient is −ln(attenuationColor) / attenuationDistance") {
  const Material m = glass(1.5f, glm::vec3(0.5f, 1.f, 0.f), 2.f);
  const std::optional<Medium> medium = medium_of(m);
  REQUIRE(medium);
  CHECK(medium->sigma_a.x == doctest::Approx(std::log(2.f) / 2.f));
  CHECK(medium->sigma_a.y == 0.f);
  CHECK(medium->sigma_a.z == INFINITY);
  const glm::vec3 t = beer_lambert(medium->sigma_a, 2.f);
  CHECK(t.x == doctest::Approx(0.5f));
  CHECK(t.y == 1.f);
  CHECK(t.z == 0.f);
  CHECK(beer_lambert(medium->sigma_a, INFINITY) == glm::vec3(0.f, 1.f, 0.f));  // no NaN
  CHECK(beer_lambert(medium->sigma_a, 0.f) == glm::vec3(1.f));
  // The default distance, +∞, absorbs nothing; no transmission or a metal: no volume at all.
  CHECK(!medium_of(glass(1.5f, glm::vec3(0.5f)))->absorbs);
  Material opaque = glass(1.5f);
  opaque.transmission = 0.f;
  CHECK(!medium_of(opaque));
  opaque.transmission = 1.f, opaque.metallic = 1.f;
  CHECK(!medium_of(opaque));
}

TEST_CASE("dispersion: R and B refract at the angles of their own IORs (the spec's formula)") {
  Material m = glass(1.5f);
  m.dispersion = 1.f;  // Abbe number 20
  const Media media({m});
  const float theta_o = glm::radians(60.f);
  const glm::vec3 wo(std::sin(theta_o), 0.f, std::cos(theta_o));
  float angle[3];
  for (int c = 0; c < 3; ++c) {
    MediumStack s;
    s.channel = int8_t(c);
    const float n = 1.5f + 0.5f / 20.f *
                               (523655.f / (channel_wavelength[c] * channel_wavelength[c]) - 1.5168f);
    CHECK(media.ior(0, c) == doctest::Approx(n).epsilon(1e-6));
    const float eta = media.eta(s, 0, true);
    CHECK(eta == doctest::Approx(n).epsilon(1e-6));
    const auto sample = RoughDielectric(eta, 0.f, glm::vec3(1.f)).sample(wo, 0.999f, 0.5f, 0.5f);
    REQUIRE(sample);
    REQUIRE(sample->wi.z < 0.f);
    angle[c] = std::asin(std::min(1.f, std::abs(sample->wi.x)));
    CHECK(std::sin(angle[c]) == doctest::Approx(std::sin(theta_o) / n).epsilon(2e-3));
  }
  // Blue bends towards the normal more than red, by more than the samples' spread.
  CHECK(angle[0] - angle[2] > 0.005f);
  // Without a channel, the material's own IOR.
  CHECK(media.eta(MediumStack{}, 0, true) == 1.5f);
}

TEST_CASE("dispersion: each channel of a dispersive slab reflects by its own IOR, unbiased") {
  // An exaggerated dispersion (10) spreads the IORs to 1.451 (R), 1.538 (G), 1.726 (B); each path
  // follows one channel (×3), and every channel's mean is its own slab's.
  Scene scene;
  add_box(scene.geometry, glm::vec3(-10, -10, 0), glm::vec3(10, 10, 1), 0);
  scene.materials = {glass(1.5f, glm::vec3(0.5f), 0.5f)};
  scene.materials[0].dispersion = 10.f;
  scene.cameras = {looking_down()};
  RenderSettings s;
  s.width = s.height = 8, s.spp = 1024, s.environment = glm::vec3(1.f);
  glm::dvec3 expected;
  for (int c = 0; c < 3; ++c) {
    const double n = dispersive_ior(1.5f, 10.f, channel_wavelength[c]);
    const double r = (n - 1.0) / (n + 1.0);
    expected[c] = slab(r * r, 0.25);
  }
  check_channels(render(scene, s).film, expected);
  // A clear one under the sky renders 1 in every channel.
  scene.materials[0].attenuation_distance = INFINITY;
  check_channels(render(scene, s).film, glm::dvec3(1.0));
}

TEST_CASE("volume: a path that ends inside a volume leaves nothing to the next one in its slot") {
  // An absorbing, index-matched box below z = −1 fills the left half of the view, a Lambert floor
  // (albedo 0.5, z = 0, which cannot see the box) the right half, under a sky of 1. At one
  // scattering event every camera ray into the box refracts in and its path ends inside (the
  // box's pixels are 0); the floor shows 0.5. The wavefront gives the box's path slots to new
  // camera samples, which start outside every volume: were the stack carried over, the floor's
  // light would be absorbed by a box it never entered.
  Scene scene;
  add_box(scene.geometry, glm::vec3(-10, -10, -3), glm::vec3(0, 10, -1), 1);
  scene.geometry.add(glm::vec3(0, -10, 0), glm::vec3(10, -10, 0), glm::vec3(10, 10, 0), 0);
  scene.geometry.add(glm::vec3(0, -10, 0), glm::vec3(10, 10, 0), glm::vec3(0, 10, 0), 0);
  scene.materials = {Material::lambert(glm::vec3(0.5f)), glass(1.f, glm::vec3(0.5f), 1.f)};
  scene.cameras = {looking_down()};
  RenderSettings s;
  s.width = s.height = 8, s.spp = 64, s.environment = glm::vec3(1.f), s.max_depth = 1;
  // The frame's 4096 paths through 100 slots: not a multiple of the 64 pixels, so that a slot
  // serves pixels of both halves.
  s.wavefront = 100;
  for (bool lanes : {true, false}) {
    s.lambert_lanes = lanes;
    const Result r = render(scene, s);
    size_t floor = 0;
    for (size_t p = 0; p < r.film.pixels(); ++p) {
      const glm::dvec2 m = r.film.mean_and_error(p);
      INFO("lanes " << lanes << ", pixel " << p << ": " << m.x << " ± " << m.y);
      if (m.x > 0.25) {
        ++floor;
        CHECK(std::abs(m.x - 0.5) <= 5.0 * m.y + 1e-4);
      } else {
        CHECK(m.x == 0.0);
      }
    }
    CHECK(floor == 32);
  }
}

TEST_CASE("volume: Lambert surfaces inside an absorbing volume see emitters through it") {
  // lit_plane's Lambert square inside an index-matched box z ∈ [−1, 2] absorbing σ = ln 2 per
  // unit, lit only by a small emitter facing down at z = 1.5 inside it (a black sky): next-event
  // estimation's shadow rays cross 1.5 units or more of the medium. The Lambert lanes' shadow
  // rays know nothing of media, so such vertices are shaded the general way: the image is the
  // same, within noise, with the lanes on or off (off, the general path, whose attenuation of
  // shadow rays the point-light test above checks against the closed form).
  Scene scene = lit_plane();
  add_box(scene.geometry, glm::vec3(-3, -3, -1), glm::vec3(3, 3, 2), 1);
  scene.materials.push_back(glass(1.f, glm::vec3(0.5f), 1.f));
  const float z = 1.5f, r = 0.3f;
  scene.geometry.add(glm::vec3(-r, -r, z), glm::vec3(r, r, z), glm::vec3(r, -r, z), 2);
  scene.geometry.add(glm::vec3(-r, -r, z), glm::vec3(-r, r, z), glm::vec3(r, r, z), 2);
  Material light;
  light.emission = glm::vec3(20.f);
  scene.materials.push_back(light);
  RenderSettings s;
  s.width = s.height = 16, s.spp = 64;
  glm::dvec2 means[2];
  for (int lanes : {0, 1}) {
    s.lambert_lanes = lanes == 1;
    const Result r = render(scene, s);
    double sum = 0.0, var = 0.0;
    for (size_t p = 0; p < r.film.pixels(); ++p) {
      const glm::dvec2 m = r.film.mean_and_error(p);
      sum += m.x, var += m.y * m.y;
    }
    means[lanes] = glm::dvec2(sum, std::sqrt(var)) / double(r.film.pixels());
  }
  INFO("general " << means[0].x << " ± " << means[0].y << ", lanes " << means[1].x << " ± "
                  << means[1].y);
  CHECK(means[0].x > 0.01);
  CHECK(std::abs(means[0].x - means[1].x) <= 4.0 * std::hypot(means[0].y, means[1].y));
}
