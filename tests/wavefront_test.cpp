// The wavefront loop (integrators/wavefront.h): renders are deterministic whatever the threads,
// backend and wavefront size; stream regeneration keeps the bounce batches full; the default
// wavefront follows the memory budget.
#include "dacrt/integrators/wavefront.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>

#include "render_check.h"
#include "test_geometry.h"

using namespace dacrt;
using namespace dacrt::test;

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
