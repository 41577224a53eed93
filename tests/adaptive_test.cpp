// Adaptive sampling (render/adaptive.h) through RenderJob: a pixel that never stops is the
// uniform render's pixel bit for bit, the render is the same for any thread count, a flat sky
// stops at the minimum while noisy pixels (and their neighbours) go on, and the film counts
// the samples each pixel got.
#include "dacrt/render/adaptive.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <map>
#include <string>

#include "dacrt/io/gltf.h"
#include "dacrt/render/render_job.h"
#include "test_geometry.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

struct Rendered {
  Film film;
  uint64_t paths;
};

Rendered render(const Scene& scene, const RenderSettings& s, PassOptions passes = {}) {
  auto backend = Backend::create("dacrt", scene.geometry);
  RenderJob job(scene, *backend, s);
  Film film = job.film();
  Progress quiet("test", 1, false);
  job.run(film, 0, uint32_t(s.spp), quiet, passes);
  return {std::move(film), job.stats().paths};
}

std::map<std::string, std::vector<float>> layers(const Film& film) {
  std::map<std::string, std::vector<float>> out;
  for (Channel& c : film.channels()) out[c.name] = std::move(c.values);
  return out;
}

// The Cornell box, small, with a target some pixels reach before the samples asked and some do
// not; a wavefront as small for the image as the default is at 384² (passes of a quarter more
// samples, not twice as many).
RenderSettings cornell_settings() {
  RenderSettings s;
  s.width = 32, s.height = 32, s.spp = 64, s.seed = 3, s.wavefront = 2048;
  s.adaptive = 0.08;
  s.aovs = AovSet::parse("variance,samples");
  return s;
}

const Scene& cornell() {
  static const Scene scene = load_gltf(DACRT_SOURCE_DIR "/scenes/cornell-box.gltf");
  return scene;
}

// A Lambert floor [-1, 1]² at z = 0 with a wall along y = 0 standing on it (z in [0, 1]), under a
// uniform sky of 1, seen from straight above by an orthographic camera over [-2, 2]² in 32 × 32
// pixels: the floor is pixels [8, 24)², the wall is edge-on (seen from above it is a line). A
// camera ray that misses sees exactly 1, so the sky around the floor has no variance at all; the
// floor, which the wall hides part of the sky from, is noisy.
Scene floor_and_wall() {
  Scene scene;
  const glm::vec3 a(-1, -1, 0), b(1, -1, 0), c(1, 1, 0), d(-1, 1, 0);
  scene.geometry.add(a, b, c, 0);
  scene.geometry.add(a, c, d, 0);
  const glm::vec3 e(-1, 0, 0), f(1, 0, 0), g(1, 0, 1), h(-1, 0, 1);
  scene.geometry.add(e, f, g, 0);
  scene.geometry.add(e, g, h, 0);
  scene.materials = {Material::lambert(glm::vec3(0.5f))};
  Camera cam = looking_at(glm::vec3(0, 0, 3), glm::vec3(0, 0, 0), 1.f);
  cam.orthographic = true;
  cam.ymag = 2.f;
  scene.cameras = {cam};
  return scene;
}

}  // namespace

TEST_CASE("adaptive: a pixel that never stops is the uniform render's, bit for bit") {
  const RenderSettings s = cornell_settings();
  RenderSettings off = s;
  off.adaptive = 0.0;
  const Rendered adaptive = render(cornell(), s), uniform = render(cornell(), off);
  const auto a = layers(adaptive.film), u = layers(uniform.film);
  size_t full = 0, stopped = 0;
  for (size_t p = 0; p < adaptive.film.pixels(); ++p) {
    CHECK(uniform.film.count(p) == 64u);
    if (adaptive.film.count(p) < 64u) {
      ++stopped;
      continue;
    }
    ++full;
    for (const char* name : {"R", "G", "B", "variance.R", "variance.G", "variance.B"}) {
      INFO("pixel " << p << " channel " << name);
      CHECK(a.at(name)[p] == u.at(name)[p]);
    }
  }
  // Both kinds are there: the check compared something, and adaptive sampling did something.
  INFO(full << " pixels sampled to the end, " << stopped << " stopped");
  CHECK(full > 50);
  CHECK(stopped > 50);
  // Only the samples taken were rendered: the paths are the film's counts.
  CHECK(adaptive.paths == adaptive.film.total_count());
  CHECK(adaptive.paths < uniform.paths);
}

TEST_CASE("adaptive: the same render for any thread count, and with passes of any size") {
  const RenderSettings s = cornell_settings();
  auto channels = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    return layers(render(cornell(), s).film);
  };
  const auto two = channels(2);
  CHECK(channels(1) == two);
  CHECK(channels(3) == two);
  // The passes after the minimum, where pixels may stop, are adaptive sampling's own: --pass-spp
  // changes only those before the minimum, and so nothing in the image.
  PassOptions small;
  small.spp_per_pass = 5;
  auto counts = [](const Film& f) {
    std::vector<uint32_t> n(f.pixels());
    for (size_t p = 0; p < n.size(); ++p) n[p] = f.count(p);
    return n;
  };
  const Film other = render(cornell(), s, small).film;
  CHECK(counts(other) == counts(render(cornell(), s).film));
  CHECK(layers(other) == two);
}

TEST_CASE("adaptive: a flat sky stops at the minimum, noisy pixels and their neighbours go on") {
  const Scene scene = floor_and_wall();
  RenderSettings s;
  s.environment = glm::vec3(1.f);
  s.width = s.height = 32, s.spp = 64, s.seed = 1;
  s.adaptive = 0.01;
  REQUIRE(adaptive_min_spp(s) == 16u);
  const Film film = render(scene, s).film;
  auto count = [&](int x, int y) { return film.count(size_t(y) * 32 + size_t(x)); };
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      INFO("pixel (" << x << ", " << y << ")");
      // The sky two pixels or more from the floor: no variance in its window.
      if (x < 6 || x > 25 || y < 6 || y > 25) CHECK(count(x, y) == 16u);
      // The floor beside the wall: far from 1% at 64 spp.
      if (x >= 10 && x < 22 && y >= 14 && y < 18) CHECK(count(x, y) == 64u);
    }
  // The sky right beside a noisy floor pixel goes on with it (the 3×3 window).
  CHECK(count(7, 15) > 16u);
  CHECK(count(24, 16) > 16u);
  CHECK(film.min_count() == 16u);
  CHECK(film.max_count() == 64u);
}

TEST_CASE("adaptive: the minimum is max(16, spp / 16) or adaptive_min, at most spp") {
  RenderSettings s;
  s.adaptive = 0.01;
  s.spp = 64;
  CHECK(adaptive_min_spp(s) == 16u);
  s.spp = 1024;
  CHECK(adaptive_min_spp(s) == 64u);
  s.spp = 8;
  CHECK(adaptive_min_spp(s) == 8u);
  s.spp = 64, s.adaptive_min = 4;
  CHECK(adaptive_min_spp(s) == 4u);
  // Passes: up to the minimum in the job's passes, then a quarter more at a time, or up to
  // twice as many when that is less than two wavefronts of samples (16 pixels here).
  s.adaptive_min = 0;
  const AdaptiveSampling a(s, 4, 4);
  CHECK(a.pass_end(0, 64, 10, 8) == 10u);
  CHECK(a.pass_end(10, 64, 10, 8) == 16u);
  CHECK(a.pass_end(16, 64, 10, 8) == 20u);
  CHECK(a.pass_end(20, 64, 3, 8) == 25u);
  CHECK(a.pass_end(60, 64, 10, 8) == 64u);
  CHECK(a.pass_end(0, 8, 10, 8) == 8u);
  CHECK(a.pass_end(16, 64, 10, 96) == 28u);
  CHECK(a.pass_end(16, 64, 10, 1000) == 32u);
}
