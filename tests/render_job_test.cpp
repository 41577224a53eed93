// RenderJob at the library level, on scenes whose answers are known: the first-hit layers (albedo,
// normal, depth, position, samples) exactly, the variance layer against the empirical variance of
// independent renders, `direct` as `path` with one scattering event bit for bit, sample ranges
// that merge, passes cut by a time limit or a stop token, and the integrators by name.
#include "dacrt/render/render_job.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>

#include "allocations.h"
#include "dacrt/integrators/sample_order.h"
#include "lit_scene.h"
#include "test_geometry.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

const AovSet all_aovs = AovSet::parse("albedo,normal,depth,position,variance,samples");

// A film's channels by name.
using Layers = std::map<std::string, std::vector<float>>;
Layers layers(const Film& film) {
  Layers out;
  for (Channel& c : film.channels()) out[c.name] = std::move(c.values);
  return out;
}

glm::vec3 layer3(const Layers& l, const std::string& prefix, const char* xyz, size_t p) {
  return {l.at(prefix + xyz[0])[p], l.at(prefix + xyz[1])[p], l.at(prefix + xyz[2])[p]};
}

// Samples [0, spp) of every pixel by `integrator`.
Film render(const Scene& scene, RenderSettings s, const char* integrator = "path") {
  s.integrator = integrator;
  auto backend = Backend::create("dacrt", scene.geometry);
  RenderJob job(scene, *backend, s);
  Film film = job.film();
  Progress quiet("test", 1, false);
  job.run(film, 0, uint32_t(s.spp), quiet);
  return film;
}

// An orthographic camera looking down −z at (x, y) = centre, seeing half a height of `ymag`.
Camera from_above(glm::vec2 centre, float ymag) {
  Camera cam = looking_at(glm::vec3(centre, 2.f), glm::vec3(centre, 0.f), 1.f);
  cam.orthographic = true;
  cam.ymag = ymag;
  return cam;
}

// Where pixel (x, y) of a width × height image meets the plane z = 0: the corners' bounds.
struct Footprint {
  glm::vec2 lo{INFINITY}, hi{-INFINITY};
  bool inside(glm::vec2 a, glm::vec2 b) const {
    return glm::all(glm::greaterThan(lo, a)) && glm::all(glm::lessThan(hi, b));
  }
  bool outside(glm::vec2 a, glm::vec2 b) const {
    return hi.x < a.x || hi.y < a.y || lo.x > b.x || lo.y > b.y;
  }
};
Footprint footprint(const Camera& cam, int width, int height, int x, int y) {
  Footprint f;
  for (int corner = 0; corner < 4; ++corner) {
    glm::vec3 o, d;
    camera_ray(cam, width, height, float(x + corner % 2), float(y + corner / 2), o, d);
    const glm::vec2 p = glm::vec2(o + d * (-o.z / d.z));
    f.lo = glm::min(f.lo, p), f.hi = glm::max(f.hi, p);
  }
  return f;
}

}  // namespace

TEST_CASE("render job: the albedo layer is the base colour, times the sRGB-decoded texture") {
  // A Lambert square over [-1, 2]² filling an orthographic view of [0, 1]², 8 × 8 pixels.
  Scene scene;
  add_square(scene.geometry, glm::vec2(-1.f), glm::vec2(2.f));
  const glm::vec3 colour(0.3f, 0.6f, 0.9f);
  scene.materials = {Material::lambert(colour)};
  scene.cameras = {from_above(glm::vec2(0.5f), 0.5f)};
  RenderSettings s;
  s.environment = glm::vec3(1.f);
  s.width = s.height = 8, s.spp = 4, s.aovs = all_aovs;
  const Layers plain = layers(render(scene, s));
  for (size_t p = 0; p < 64; ++p) CHECK(layer3(plain, "albedo.", "RGB", p) == colour);

  // The same square with a 2 × 2 base-colour texture (nearest, repeating) at uv = (x, 1 − y): the
  // view's quarters are the texels, upright.
  const std::vector<uint8_t> texels = {255, 0,   0,   255, 0,  128, 255, 255,
                                       188, 188, 188, 255, 20, 200, 90,  255};
  TextureImage image;
  image.width = image.height = 2;
  image.rgba8.assign(texels.begin(), texels.end());
  scene.images = {image};
  Texture texture;
  texture.nearest = true;
  scene.textures = {texture};
  const glm::vec3 factor(0.5f, 0.8f, 1.f);
  scene.materials[0].base_color = factor;
  scene.materials[0].base_color_texture.texture = 0;
  for (size_t t = 0; t < scene.geometry.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 v = scene.geometry.vertex(t, k);
      scene.texcoords[0].push_back(glm::vec2(v.x, 1.f - v.y));
    }
  const Layers textured = layers(render(scene, s));
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      // Pixels 3 and 4 touch a texel edge: a sample there may round onto either texel.
      if (x == 3 || x == 4 || y == 3 || y == 4) continue;
      const uint8_t* texel = &texels[4 * size_t(2 * (y / 4) + x / 4)];
      glm::vec3 expected;
      for (int c = 0; c < 3; ++c) expected[c] = factor[c] * srgb_to_linear(texel[c] / 255.f);
      // Every sample of the pixel sees one texel, so the mean is that texel's value; what is left
      // is float rounding of the decode and the product (a few ulps of values <= 1, ~2e-7), and
      // 1e-6 also admits a decode by pow() instead of a table.
      const glm::vec3 albedo = layer3(textured, "albedo.", "RGB", size_t(y) * 8 + x);
      INFO("pixel " << x << ", " << y << ": " << albedo.x << " " << albedo.y << " " << albedo.z);
      CHECK(glm::all(glm::lessThanEqual(glm::abs(albedo - expected), glm::vec3(1e-6f))));
    }
}

TEST_CASE("render job: normals are unit and face the camera, from the wall's front and back") {
  // A tilted wall through the origin, 20 across, normal n (the winding's).
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, 0.2f, 1.f));
  const glm::vec3 t1 = glm::normalize(glm::cross(glm::vec3(0, 1, 0), n)), t2 = glm::cross(n, t1);
  Scene scene;
  const glm::vec3 a = -10.f * t1 - 10.f * t2, b = 10.f * t1 - 10.f * t2, c = 10.f * t1 + 10.f * t2,
                  d = -10.f * t1 + 10.f * t2;
  scene.geometry.add(a, b, c, 0);
  scene.geometry.add(a, c, d, 0);
  scene.materials = {Material::lambert(glm::vec3(0.5f))};
  RenderSettings s;
  s.width = s.height = 12, s.spp = 2, s.aovs = all_aovs;
  for (const float side : {1.f, -1.f}) {
    INFO((side > 0 ? "front" : "back"));
    const glm::vec3 eye = 3.f * side * n + glm::vec3(0.2f, 0.1f, 0.f);
    scene.cameras = {looking_at(eye, glm::vec3(0.f), 0.9f)};
    const Layers l = layers(render(scene, s));
    for (size_t p = 0; p < 144; ++p) {
      const glm::vec3 normal = layer3(l, "N.", "XYZ", p), at = layer3(l, "P.", "XYZ", p);
      INFO("pixel " << p << ": " << normal.x << " " << normal.y << " " << normal.z);
      CHECK(std::abs(glm::length(normal) - 1.f) < 1e-5f);
      CHECK(glm::dot(normal, eye - at) > 0.f);
      CHECK(glm::length(normal - side * n) < 1e-5f);
    }
  }
}

TEST_CASE(
    "render job: depth is along the view axis, P lies on the plane, the background is empty") {
  // A plane 3 below a wide perspective camera looking straight down at it: every pixel's depth is
  // 3, though the corner rays are 1.8 times as long.
  const float distance = 3.f;
  Scene scene;
  add_square(scene.geometry, glm::vec2(-50.f), glm::vec2(50.f));
  scene.materials = {Material::lambert(glm::vec3(0.5f))};
  const Camera cam = looking_at(glm::vec3(0.f, 0.f, distance), glm::vec3(0.f), 1.4f);
  scene.cameras = {cam};
  RenderSettings s;
  s.width = 24, s.height = 16, s.spp = 4, s.aovs = all_aovs;
  s.environment = glm::vec3(0.f);  // a black sky: the background's colour is 0 too
  glm::vec3 o, d;
  camera_ray(cam, s.width, s.height, 0.f, 0.f, o, d);
  REQUIRE(distance / -d.z > 1.8f * distance);
  const Layers plane = layers(render(scene, s));
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const size_t p = size_t(y) * s.width + x;
      const Footprint f = footprint(cam, s.width, s.height, x, y);
      const glm::vec3 at = layer3(plane, "P.", "XYZ", p);
      INFO("pixel " << x << ", " << y << ": Z " << plane.at("Z")[p] << ", P " << at.x << " " << at.y
                    << " " << at.z);
      // t × (d · forward) rounds t, d and their product: a few float ulps.
      CHECK(plane.at("Z")[p] == doctest::Approx(distance).epsilon(1e-6));
      CHECK(at.z == 0.f);
      CHECK(glm::all(glm::greaterThanEqual(glm::vec2(at), f.lo - 1e-5f)));
      CHECK(glm::all(glm::lessThanEqual(glm::vec2(at), f.hi + 1e-5f)));
      CHECK(plane.at(Film::samples_channel)[p] == 4.f);
    }

  // A square of side 2 in the middle of the view: the pixels that see only the (black)
  // background hold nothing but Z = +inf; the pixels that see only the square, its depth.
  scene.geometry = Geometry();
  add_square(scene.geometry, glm::vec2(-1.f), glm::vec2(1.f));
  const Layers square = layers(render(scene, s));
  size_t background = 0, inside = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const size_t p = size_t(y) * s.width + x;
      INFO("pixel " << x << ", " << y);
      const Footprint f = footprint(cam, s.width, s.height, x, y);
      CHECK(square.at(Film::samples_channel)[p] == 4.f);
      if (f.outside(glm::vec2(-1.f), glm::vec2(1.f))) {
        ++background;
        CHECK(square.at("Z")[p] == 1e10f);  // docs/usage.md#aovs: Cycles' background depth
        CHECK(layer3(square, "P.", "XYZ", p) == glm::vec3(0.f));
        CHECK(layer3(square, "albedo.", "RGB", p) == glm::vec3(0.f));
        CHECK(layer3(square, "N.", "XYZ", p) == glm::vec3(0.f));
        CHECK(layer3(square, "", "RGB", p) == glm::vec3(0.f));
      } else if (f.inside(glm::vec2(-1.f), glm::vec2(1.f))) {
        ++inside;
        CHECK(square.at("Z")[p] == doctest::Approx(distance).epsilon(1e-6));
        CHECK(layer3(square, "N.", "XYZ", p) == glm::vec3(0.f, 0.f, 1.f));
      }
    }
  CHECK(background > 100);
  CHECK(inside >= 16);
}

TEST_CASE("render job: the variance layer is the variance of the pixel mean, as K renders show") {
  // A Lambert floor under a grey environment map that varies with direction, seen from above:
  // every sample is the map's light by next-event estimation and BSDF sampling, weighed by MIS:
  // noisy, but bounded (no heavy tail).
  Scene scene;
  add_square(scene.geometry, glm::vec2(-2.f), glm::vec2(2.f));
  scene.materials = {Material::lambert(glm::vec3(0.8f))};
  scene.cameras = {from_above(glm::vec2(0.f), 1.f)};
  Image sky(16, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x)
      std::fill_n(sky.pixel(x, y), 3, 0.2f + 0.15f * float(y) + 0.05f * float(x % 4));
  RenderSettings s;
  s.environment_map = std::make_shared<const EnvironmentMap>(sky, "sky");
  s.width = s.height = 16, s.spp = 8, s.aovs = AovSet::parse("variance");
  // s²/n is the variance of the mean of independent samples: with the sobol sampler's stratified
  // ones the true variance is lower and the layer overestimates it (about 4× here).
  s.sampler = SamplerKind::independent;
  // K renders of n samples with independent seeds. Per pixel: X_k the film's mean (channel R),
  // V_k its variance layer, S² = Σ (X_k − X̄)² / (K − 1) the empirical variance of the means,
  // V̄ = Σ V_k / K. Both estimate σ²/n without bias. For normal samples, (K − 1) S² / (σ²/n) is
  // χ²(K − 1), K (n − 1) V̄ / (σ²/n) is χ²(K (n − 1)) (a sum of K independent χ²(n − 1)), and
  // the two are independent (a normal sample's mean is independent of its variance), so
  // r = S² / V̄ follows F(d1, d2), d1 = K − 1, d2 = K (n − 1): mean d2 / (d2 − 2), variance
  // 2 d2² (d1 + d2 − 2) / (d1 (d2 − 2)² (d2 − 4)). Pixels are independent (their random numbers
  // are keyed by pixel), so the mean of r over P pixels has that mean and variance / P: with
  // K = 40, n = 8, P = 256, 1.0072 ± 0.0153. We allow 5 of those standard deviations (the samples
  // are bounded but not normal; over 30 seed sets it stayed within 2.3).
  // The variance of the samples instead of that of their mean would give r ≈ 1/n = 0.125, and
  // Σx² − (Σx)²/n divided by n − 1 once too many or too few, ≈ 7 or 1/7.
  constexpr int K = 40;
  const double n = s.spp, d1 = K - 1, d2 = K * (n - 1), pixels = 256;
  const double mean_r = d2 / (d2 - 2);
  const double sd_r =
      std::sqrt(2 * d2 * d2 * (d1 + d2 - 2) / (d1 * (d2 - 2) * (d2 - 2) * (d2 - 4)));
  std::vector<double> sum_x(256, 0.0), sum_xx(256, 0.0), sum_v(256, 0.0);
  for (int k = 0; k < K; ++k) {
    s.seed = uint64_t(1000 + k);
    const Layers l = layers(render(scene, s));
    for (size_t p = 0; p < 256; ++p) {
      const double x = l.at("R")[p];
      sum_x[p] += x, sum_xx[p] += x * x, sum_v[p] += l.at("variance.R")[p];
    }
  }
  double r = 0.0;
  for (size_t p = 0; p < 256; ++p) {
    const double s2 = (sum_xx[p] - sum_x[p] * sum_x[p] / K) / (K - 1);
    REQUIRE(sum_v[p] > 0.0);
    r += s2 / (sum_v[p] / K) / pixels;
  }
  const double sd = sd_r / std::sqrt(pixels);
  INFO("mean of S² / V̄ over the pixels: " << r << ", expected " << mean_r << " ± " << sd);
  CHECK(std::abs(r - mean_r) <= 5.0 * sd);
}

TEST_CASE("render job: `direct` is `path` with max depth 1, bit for bit in every channel") {
  const Scene scene = lit_scene();
  RenderSettings s = lit_settings();
  s.width = 24, s.height = 16, s.spp = 8, s.seed = 5, s.aovs = all_aovs;
  const std::vector<Channel> direct = render(scene, s, "direct").channels();
  RenderSettings one = s;
  one.max_depth = 1;
  const std::vector<Channel> path = render(scene, one, "path").channels();
  REQUIRE(direct.size() == path.size());
  for (size_t c = 0; c < direct.size(); ++c) {
    INFO(direct[c].name);
    CHECK(direct[c].name == path[c].name);
    CHECK(direct[c].values == path[c].values);
  }
  // Not a black or trivial image: light of every kind arrives, and deeper paths add to it.
  const std::vector<Channel> deep = render(scene, s, "path").channels();
  double sum = 0.0, deeper = 0.0;
  for (size_t p = 0; p < direct[0].values.size(); ++p)
    sum += direct[0].values[p], deeper += deep[0].values[p];
  CHECK(sum > 0.0);
  CHECK(deeper > sum);
}

namespace {
// A film's state, exactly: the fixed-point sums and the counts.
std::pair<std::vector<Fixed>, std::vector<uint32_t>> film_state(Film& f) {
  std::vector<Fixed> sums = f.sums();
  std::vector<uint32_t> counts;
  for (size_t p = 0; p < f.pixels(); ++p)
    for (int i = 0; i < f.counts_per_pixel(); ++i) counts.push_back(f.count_value(p, i));
  return {sums, counts};
}
}  // namespace

TEST_CASE("render job: samples 0 to a and a to b, merged, are samples 0 to b") {
  const Scene scene = lit_scene();
  RenderSettings s = lit_settings();
  s.width = 24, s.height = 16, s.spp = 7, s.seed = 2, s.aovs = all_aovs;
  auto backend = Backend::create("dacrt", scene.geometry);
  RenderJob job(scene, *backend, s);
  Progress quiet("test", 1, false);
  Film whole = job.film();
  job.run(whole, 0, 7, quiet);
  // Several splits, merged in any order: the sums are exact, so each is the whole bit for bit.
  const std::vector<std::vector<uint32_t>> splits = {{0, 3, 7}, {0, 1, 2, 6, 7}, {0, 5, 6, 7}};
  for (const auto& split : splits) {
    for (bool backwards : {false, true}) {
      CAPTURE(split.size());
      CAPTURE(backwards);
      Film merged = job.film();
      for (size_t k = 0; k + 1 < split.size(); ++k) {
        const size_t i = backwards ? split.size() - 2 - k : k;
        Film part = job.film();
        job.run(part, split[i], split[i + 1], quiet);
        merged.merge(part);
      }
      CHECK(film_state(merged) == film_state(whole));
      const std::vector<Channel> a = merged.channels(), b = whole.channels();
      REQUIRE(a.size() == b.size());
      for (size_t c = 0; c < a.size(); ++c) {
        INFO(a[c].name);
        CHECK(std::memcmp(a[c].values.data(), b[c].values.data(),
                          a[c].values.size() * sizeof(float)) == 0);
      }
      CHECK(merged.dropped() == whole.dropped());
    }
  }
  Film merged = job.film();
  for (size_t p = 0; p < whole.pixels(); ++p) CHECK(whole.count(p) == 7u);
  // Films of another size, or other outputs, do not merge.
  Film other_size(s.height, s.width, s.aovs);
  CHECK_THROWS_AS(merged.merge(other_size), Error);
  Film colour_only(s.width, s.height);
  CHECK_THROWS_AS(merged.merge(colour_only), Error);
}

namespace {

// The dacrt backend, which sets a stop token after `calls` closest-hit calls.
class StopAfter final : public Backend {
 public:
  StopAfter(const Geometry& g, int calls, std::atomic<bool>& stop)
      : inner_(Backend::create("dacrt", g)), calls_(calls), stop_(stop) {}
  Stats stats() const override { return inner_->stats(); }

 private:
  void do_intersect(const RayBatch& rays, HitBatch& hits, const HitFilter* filter) override {
    inner_->intersect(rays, hits, filter);
    if (--calls_ == 0) stop_ = true;
  }
  void do_occluded(const RayBatch& rays, std::span<uint8_t> occluded,
                   const HitFilter* filter) override {
    inner_->occluded(rays, occluded, filter);
  }
  std::unique_ptr<Backend> inner_;
  int calls_;
  std::atomic<bool>& stop_;
};

// What a run must end with: how, its bounds and whole passes, and the film's fewest and most
// samples in a pixel.
struct Expected {
  bool stopped = false, timed_out = false;
  uint32_t complete, most, passes, min_count, max_count;
};
void check_outcome(const RenderOutcome& out, const Film& film, const Expected& e) {
  CHECK(out.stopped == e.stopped);
  CHECK(out.timed_out == e.timed_out);
  CHECK(out.complete == e.complete);
  CHECK(out.most == e.most);
  CHECK(out.passes == e.passes);
  CHECK(film.min_count() == e.min_count);
  CHECK(film.max_count() == e.max_count);
}

}  // namespace

TEST_CASE("render job: passes end at a time limit, a stop token, or a stop from a checkpoint") {
  const Scene scene = lit_scene();
  RenderSettings s = lit_settings();
  s.width = s.height = 16, s.spp = 10;
  auto backend = Backend::create("dacrt", scene.geometry);
  Progress quiet("test", 1, false);
  SUBCASE("a time limit ends the render after the pass that crosses it") {
    RenderJob job(scene, *backend, s);
    Film film = job.film();
    PassOptions o;
    o.spp_per_pass = 2, o.time_limit = 1e-9;
    const RenderOutcome out = job.run(film, 3, 13, quiet, o);
    CHECK(out.first == 3u);
    check_outcome(
        out, film,
        {.timed_out = true, .complete = 5, .most = 5, .passes = 1, .min_count = 2, .max_count = 2});
  }
  SUBCASE("a stop token set before the run: nothing is rendered") {
    RenderJob job(scene, *backend, s);
    Film film = job.film();
    std::atomic<bool> stop{true};
    PassOptions o;
    o.stop = &stop;
    const RenderOutcome out = job.run(film, 0, 10, quiet, o);
    check_outcome(
        out, film,
        {.stopped = true, .complete = 0, .most = 0, .passes = 0, .min_count = 0, .max_count = 0});
    CHECK(job.stats().paths == 0u);
  }
  SUBCASE("a stop token set by the checkpoint callback: the render ends after that pass") {
    RenderJob job(scene, *backend, s);
    Film film = job.film();
    std::atomic<bool> stop{false};
    PassOptions o;
    o.spp_per_pass = 2, o.checkpoint = 1e-9, o.stop = &stop;
    int calls = 0;
    const RenderOutcome out =
        job.run(film, 0, 10, quiet, o, [&](const Film& f, const RenderOutcome& now) {
          ++calls;
          CHECK(f.min_count() == now.complete - now.first);
          stop = true;
        });
    CHECK(calls == 1);
    // Whole passes: most == complete, every pixel has their samples.
    check_outcome(
        out, film,
        {.stopped = true, .complete = 2, .most = 2, .passes = 1, .min_count = 2, .max_count = 2});
  }
  SUBCASE("a stop token set in the middle of a pass: the samples begun finish and reach the film") {
    std::atomic<bool> stop{false};
    StopAfter stopping(scene.geometry, 5, stop);
    RenderSettings small = s;
    small.wavefront = 64;  // a pass of 4 × 256 samples takes many wavefronts
    RenderJob job(scene, stopping, small);
    Film film = job.film();
    PassOptions o;
    o.spp_per_pass = 4, o.stop = &stop;
    const RenderOutcome out = job.run(film, 2, 10, quiet, o);
    CHECK(out.stopped);
    CHECK(out.complete < 6u);
    CHECK(film.min_count() >= out.complete - out.first);
    CHECK(film.max_count() <= out.most - out.first);
    // An untextured scene's samples go sample by sample (integrators/sample_order.h): the
    // first pixels have one sample more than the rest, and every sample begun is there.
    uint64_t total = 0;
    for (size_t p = 0; p < film.pixels(); ++p) {
      total += film.count(p);
      if (p > 0) CHECK(film.count(p) <= film.count(p - 1));
    }
    CHECK(total == job.stats().paths);
    CHECK(total > uint64_t(out.complete - out.first) * film.pixels());
  }
}

TEST_CASE("render job: a render stopped in the middle of passes, resumed, is the whole render") {
  const Scene scene = lit_scene();
  RenderSettings s = lit_settings();
  s.width = 24, s.height = 16, s.spp = 10, s.seed = 4, s.aovs = all_aovs;
  s.wavefront = 64;  // a pass of 4 × 384 samples takes many wavefronts
  Progress quiet("test", 1, false);
  PassOptions o;
  o.spp_per_pass = 4;
  auto backend = Backend::create("dacrt", scene.geometry);
  RenderJob whole_job(scene, *backend, s);
  Film whole = whole_job.film();
  whole_job.run(whole, 2, 10, quiet, o);
  // Stopped twice at odd places (a stop inside the resume's levelling too), then resumed to the
  // end, each time by a new job as a new process would.
  for (int calls : {5, 23}) {
    CAPTURE(calls);
    Film film = whole_job.film();
    std::atomic<bool> stop{false};
    {
      StopAfter stopping(scene.geometry, calls, stop);
      RenderJob job(scene, stopping, s);
      PassOptions stoppable = o;
      stoppable.stop = &stop;
      const RenderOutcome out = job.run(film, 2, 10, quiet, stoppable);
      REQUIRE(out.stopped);
      REQUIRE(film.min_count() < film.max_count());  // some pixels are ahead of others
    }
    {
      stop = false;
      StopAfter stopping(scene.geometry, 3, stop);
      RenderJob job(scene, stopping, s);
      PassOptions stoppable = o;
      stoppable.stop = &stop;
      const RenderOutcome out = job.resume(film, 2, 10, quiet, stoppable);
      CHECK(out.stopped);
      CHECK(out.complete < 10u);
    }
    RenderJob job(scene, *backend, s);
    const RenderOutcome out = job.resume(film, 2, 10, quiet, o);
    CHECK(!out.stopped);
    CHECK(out.first == 2u);
    CHECK(out.complete == 10u);
    CHECK(out.most == 10u);
    CHECK(film_state(film) == film_state(whole));
  }
  // Adaptive sampling's pixels stop by what the others have: not resumable.
  RenderSettings adaptive = s;
  adaptive.adaptive = 0.1;
  RenderJob job(scene, *backend, adaptive);
  Film film = job.film();
  CHECK_THROWS_AS(job.resume(film, 0, 10, quiet, o), Error);
}

TEST_CASE("sample order: every sample of the call once, pixels by tiles, and the counts a stop leaves") {
  // Images whose pixels fill whole groups of 64 or not, one tile or many.
  for (const auto& [w, h] : {std::pair{8u, 8u}, {16u, 16u}, {13u, 7u}, {40u, 3u}, {1u, 1u}}) {
    const std::vector<uint32_t> tiled = SampleOrder::tiled(w, h);
    REQUIRE(tiled.size() == size_t(w) * h);
    std::vector<uint32_t> seen(tiled.size(), 0);
    for (uint32_t p : tiled) ++seen[p];
    CHECK(std::count(seen.begin(), seen.end(), 1u) == long(seen.size()));  // a permutation
    // The first tile's first row, then its second: (0, 0), (1, 0)… (0, 1).
    if (w >= 8 && h >= 2) CHECK(tiled[8] == w);
    for (uint32_t samples : {1u, 3u, 5u}) {
      INFO(w << " x " << h << ", " << samples << " samples");
      const SampleOrder order{tiled.size(), 7, samples};
      std::vector<uint32_t> count(tiled.size(), 0), next(tiled.size(), 7);
      bool in_order = true;
      SampleOrder::Cursor cursor(order, 0);
      for (uint64_t k = 0; k < tiled.size() * samples; ++k, ++cursor) {
        const auto [index, sample] = order.at(k);
        CHECK(*cursor == order.at(k));
        CHECK(*SampleOrder::Cursor(order, k) == order.at(k));
        REQUIRE(index < tiled.size());
        in_order &= sample == next[index]++;  // each pixel's samples in turn, from first on
        ++count[index];
        // After k + 1 samples, the fewest and most any pixel has, as counts() says.
        const auto [fewest, most] = order.counts(k + 1);
        CHECK(fewest == *std::min_element(count.begin(), count.end()));
        CHECK(most == *std::max_element(count.begin(), count.end()));
        // A pixel's samples come together: at most one group of pixels is part-way through.
        CHECK(index / order.group == k / (order.group * samples));
      }
      CHECK(in_order);
      CHECK(std::count(count.begin(), count.end(), samples) == long(count.size()));
      CHECK(order.counts(0) == std::pair{0u, 0u});
    }
  }
}

TEST_CASE("render job: integrators by name, and ao, albedo, normal and depth give what they say") {
  const std::vector<std::string> names = Integrator::names();
  for (const char* name : {"path", "direct", "ao", "albedo", "normal", "depth"}) {
    INFO(name);
    CHECK(std::find(names.begin(), names.end(), name) != names.end());
  }
  RenderSettings s;
  s.width = s.height = 12, s.spp = 8, s.aovs = all_aovs;
  auto all_equal = [](const Film& film, float value) {
    const std::vector<float> r = layers(film).at("R");
    return std::all_of(r.begin(), r.end(), [&](float x) { return x == value; });
  };
  SUBCASE("ao: 1 on an open plane, 0 in a closed box, 1 again there within a short distance") {
    Scene open;
    add_square(open.geometry, glm::vec2(-100.f), glm::vec2(100.f));
    open.materials = {Material::lambert(glm::vec3(0.5f))};
    open.cameras = {looking_at(glm::vec3(0.3f, 0.2f, 3.f), glm::vec3(0.f), 0.8f)};
    CHECK(all_equal(render(open, s, "ao"), 1.f));
    // Inside a box of side 2 looking straight at a wall: the points seen are 0.74 or more from the
    // other walls.
    Scene box;
    box.geometry = inward_box();
    box.materials = {Material::lambert(glm::vec3(0.5f))};
    box.cameras = {looking_at(glm::vec3(0.f), glm::vec3(0.f, 0.f, -1.f), 0.5f)};
    CHECK(all_equal(render(box, s, "ao"), 0.f));
    RenderSettings near = s;
    near.ao_distance = 0.5f;
    CHECK(all_equal(render(box, near, "ao"), 1.f));
  }
  SUBCASE("albedo, normal and depth: their image is the first-hit layer") {
    // The integrator's colour is the layer's value, sample for sample (0 for a miss), so the
    // means are the same bit for bit; depth's only where no sample missed (Z averages hits).
    const Scene scene = lit_scene();
    const Layers albedo = layers(render(scene, s, "albedo"));
    const Layers normal = layers(render(scene, s, "normal"));
    const Layers depth = layers(render(scene, s, "depth"));
    size_t background = 0, hit = 0;
    for (size_t p = 0; p < 144; ++p) {
      INFO("pixel " << p);
      CHECK(layer3(albedo, "", "RGB", p) == layer3(albedo, "albedo.", "RGB", p));
      CHECK(layer3(normal, "", "RGB", p) == layer3(normal, "N.", "XYZ", p));
      const float z = depth.at("Z")[p];
      if (z == Film::background_depth) {
        ++background;
        CHECK(layer3(depth, "", "RGB", p) == glm::vec3(0.f));
      } else if (glm::length(layer3(depth, "N.", "XYZ", p)) > 1.f - 1e-6f) {
        // Unit: every sample met a surface (a miss adds a normal of 0), all of one orientation.
        ++hit;
        CHECK(layer3(depth, "", "RGB", p) == glm::vec3(z));
      }
    }
    CHECK(background > 0);
    CHECK(hit > 20);
  }
}

TEST_CASE("render job: camera, size, lights and sky are the shot's, the scene stays as loaded") {
  Scene scene;
  add_square(scene.geometry, glm::vec2(-1.f), glm::vec2(1.f));
  scene.materials = {Material::lambert(glm::vec3(0.5f))};
  Camera file_camera = looking_at(glm::vec3(0.f, 0.f, 3.f), glm::vec3(0.f), 0.8f);
  file_camera.aspect = 2.f;
  scene.cameras = {file_camera};
  scene.cameras_from_file = 1;
  const glm::mat4 before = scene.cameras[0].to_world;

  RenderSettings s;
  s.longer_side = 32, s.spp = 1;
  s.camera_override.from = glm::vec3(0.f, 2.f, 2.f);
  const Shot sky = make_shot(scene, s);
  CHECK(sky.camera.position() == glm::vec3(0.f, 2.f, 2.f));
  CHECK(sky.width == 32);
  CHECK(sky.height == 16);  // the camera's aspect ratio 2
  // No emitter and no light: a uniform environment of 1, and a note that says so.
  CHECK(sky.environment == glm::vec3(1.f));
  REQUIRE(sky.notes.size() == 1);
  CHECK(sky.notes[0].find("no emitters") != std::string::npos);

  PunctualLight bulb;
  bulb.position = glm::vec3(0.f, 0.f, 1.f);
  s.lights = {bulb};
  const Shot lit = make_shot(scene, s);
  REQUIRE(lit.lights.size() == 1);
  CHECK(lit.lights[0].position == bulb.position);
  CHECK(lit.environment == glm::vec3(0.f));  // the settings' light is an emitter
  CHECK(lit.notes.empty());

  // A whole render leaves the scene as it was loaded: its camera and its (empty) light list.
  auto backend = Backend::create("dacrt", scene.geometry);
  RenderJob job(scene, *backend, s);
  Film film = job.film();
  CHECK(film.pixels() == 32u * 16u);
  Progress quiet("test", 1, false);
  job.run(film, 0, 1, quiet);
  CHECK(scene.cameras[0].to_world == before);
  CHECK(scene.lights.empty());
  CHECK(job.shot().camera.position() == glm::vec3(0.f, 2.f, 2.f));

  // What cannot be made: a camera the scene lacks is the scene's error, a degenerate override the
  // caller's (SettingError: the CLI exits 2 for it).
  RenderSettings missing;
  missing.camera = 1;
  CHECK_THROWS_WITH_AS(make_shot(scene, missing), doctest::Contains("camera 1 does not exist"),
                       Error);
  RenderSettings same;
  same.camera_override.from = same.camera_override.at = glm::vec3(1.f);
  CHECK_THROWS_AS(make_shot(scene, same), SettingError);
}

TEST_CASE("render job: the default sky stays beside glowing emitters and the file's lights, not beside lamps") {
  Scene scene;
  add_square(scene.geometry, glm::vec2(-1.f), glm::vec2(1.f));
  Material glow = Material::lambert(glm::vec3(0.5f));
  glow.emission = glm::vec3(1.f, 0.5f, 0.2f);  // an emissiveFactor: at most 1
  scene.materials = {glow};
  scene.cameras = {looking_at(glm::vec3(0.f, 0.f, 3.f), glm::vec3(0.f), 0.8f)};
  scene.cameras_from_file = 1;
  RenderSettings s;
  s.longer_side = 8;

  // A glowing surface (a visor, a screen) is no lighting: the sky stays, and the note says why.
  const Shot glowing = make_shot(scene, s);
  CHECK(glowing.environment == glm::vec3(1.f));
  REQUIRE(glowing.notes.size() == 1);
  CHECK(glowing.notes[0].find("2 emissive triangles no brighter than it") != std::string::npos);
  CHECK(glowing.notes[0].find("--environment 0") != std::string::npos);
  CHECK(default_lighting(scene, 0).sky);

  // The file's punctual lights shine beside the sky, as glTF viewers light them.
  scene.lights.push_back(PunctualLight{});
  CHECK(make_shot(scene, s).environment == glm::vec3(1.f));
  CHECK(default_lighting(scene, 0).what.find("beside 1 punctual light and 2 emissive") !=
        std::string::npos);

  // A lamp brighter than the sky (KHR_materials_emissive_strength) is the scene's own lighting.
  scene.materials[0].emission = glm::vec3(0.2f, 0.4f, 1.f) * 1.5f;
  const Shot lamp = make_shot(scene, s);
  CHECK(lamp.environment == glm::vec3(0.f));
  CHECK(lamp.notes.empty());
  CHECK(default_lighting(scene, 0).what ==
        "its own: 2 emissive triangles (radiance up to 1.5) and 1 punctual light; "
        "--environment 1,1,1 adds a sky");

  // Lights the command line adds are the user's lighting, with or without emitters.
  scene.materials[0].emission = glm::vec3(0.f);
  scene.lights.clear();
  s.lights = {PunctualLight{}};
  CHECK(make_shot(scene, s).environment == glm::vec3(0.f));
  CHECK_FALSE(default_lighting(scene, 1).sky);
  s.lights.clear();
  CHECK(default_lighting(scene, 0).what.find("no emitters and no lights") != std::string::npos);

  // --environment states the lighting: no rule applies.
  scene.materials[0].emission = glm::vec3(4.f);
  s.environment = glm::vec3(0.25f);
  CHECK(make_shot(scene, s).environment == glm::vec3(0.25f));
}

TEST_CASE("render job: a nearly black image gets one line naming the option that changes it") {
  Shot shot;
  Image image(10, 10);  // black
  const std::string own = dark_image_note(image, shot, 0.0, "out.exr");
  CHECK(own.rfind("out.exr: the image is nearly black (100.0 % of its pixels", 0) == 0);
  CHECK(own.find("no sky lights it; --environment 1,1,1 adds one") != std::string::npos);
  shot.environment = glm::vec3(1.f);
  const std::string sky = dark_image_note(image, shot, 0.0, "out.exr");
  CHECK(sky.find("--exposure STOPS") != std::string::npos);
  CHECK(sky.find("--environment") == std::string::npos);

  // Four pixels in a hundred at white: not dark. Three: dark (97 %). The exposure counts.
  for (int x = 0; x < 4; ++x) image.pixel(x, 0)[0] = image.pixel(x, 0)[1] = image.pixel(x, 0)[2] = 1.f;
  CHECK(dark_image_note(image, shot, 0.0, "o").empty());
  CHECK_FALSE(dark_image_note(image, shot, -10.0, "o").empty());  // 2^-10 < 0.002
  image.pixel(3, 0)[1] = std::nanf("");
  CHECK_FALSE(dark_image_note(image, shot, 0.0, "o").empty());  // NaN is no light
}

TEST_CASE("render job: release frees the integrator's path state and keeps its statistics") {
  // What a render holds while its outputs are written: the film, not the paths (the 1080p
  // every-AOV peak lost the path state's ~100 MB this way).
  const Scene scene = lit_scene();
  RenderSettings s;
  s.spp = 4;
  auto backend = Backend::create("dacrt", scene.geometry);
  RenderJob job(scene, *backend, s);
  Film film = job.film();
  Progress quiet("test", 1, false);
  job.run(film, 0, 4, quiet);
  const RenderStats before = job.stats();
  CHECK(before.paths > 0);
  const uint64_t live = AllocationWatch::live();
  job.release();
  const uint64_t freed = live - std::min(live, AllocationWatch::live());
  MESSAGE("release freed " << freed << " bytes for a wavefront of " << before.wavefront
                           << " paths");
  CHECK(freed >= before.wavefront * 32);  // at least the throughput, radiance and pixel of each
  CHECK(job.stats().paths == before.paths);
  CHECK(job.stats().wavefront == before.wavefront);
  job.release();  // twice is harmless
  CHECK(job.stats().paths == before.paths);
}
