// Depth of field (a thin lens: --aperture or --fstop, --focus-distance or --focus-on) rendered:
// the circle of confusion of a point-like emitter against the thin-lens prediction, a render
// without an aperture bit for bit the pinhole's, and the options' usage errors, header and
// statistics from the CLI.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "dacrt/io/exr.h"
#include "dacrt/render/render_job.h"
#include "lit_scene.h"
#include "render_check.h"
#include "test_geometry.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

// A square emitter of side `side` centred on the view axis at depth `depth`, facing a camera at
// the origin that looks down -Z with this vertical field of view; nothing else (black around).
Scene point_like_emitter(float depth, float side, float yfov) {
  Scene scene;
  add_square(scene.geometry, glm::vec2(-0.5f * side), glm::vec2(0.5f * side), -depth, 0);
  Material light = Material::lambert(glm::vec3(0.f));
  light.emission = glm::vec3(1.f);
  scene.materials = {light};
  scene.cameras = {looking_at(glm::vec3(0.f), glm::vec3(0.f, 0.f, -1.f), yfov)};
  scene.cameras_from_file = 1;
  return scene;
}

// The image's second moment about `centre` (pixel units: mean squared distance from it, weighted
// by the pixels' values) and its standard error, from each pixel's variance of its mean (pixels
// are independent; the delta method for the ratio Σ p r² / Σ p).
struct Moment {
  double value, error;
};
Moment second_moment(const Film& film, int width, int height, glm::dvec2 centre) {
  const Image image = film.resolve();
  double sum = 0.0, weighted = 0.0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double p = image.pixel(x, y)[0];
      const glm::dvec2 c(x + 0.5, y + 0.5);
      sum += p, weighted += p * glm::dot(c - centre, c - centre);
    }
  const double m = weighted / sum;
  double variance = 0.0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const glm::dvec2 c(x + 0.5, y + 0.5);
      const double q = glm::dot(c - centre, c - centre) - m;
      variance += q * q * film.variance_of_mean(size_t(y) * width + x, 0);
    }
  return {m, std::sqrt(variance) / sum};
}

}  // namespace

// A point at depth d seen through a lens of diameter A focused at d_f is a disk of diameter
// A·|d − d_f| / d on the focus plane, whose height in view is 2·d_f·tan(yfov/2): on the image,
// radius R = A·|d − d_f| / d ÷ (2·d_f·tan(yfov/2)) × height / 2 pixels. The rendered spot is that
// uniform disk (second moment R²/2) convolved with the square's own image (side s pixels:
// s²/6) and a pixel's box (the camera samples are jittered over the pixel, and the moment is
// taken at pixel centres: 1/6), so its second moment is R²/2 + s²/6 + 1/6. Measured: within 4
// standard errors of the Monte Carlo estimate (its own error, from the film's per-pixel
// variances) plus 1 % for the discretisation at the disk's rim. A lens of twice the radius would
// be 4× the moment; a focus off by 10 % moves R by 10 % or more in each case below.
TEST_CASE("depth of field: a point's circle of confusion is the thin lens's, in pixels") {
  const float yfov = glm::radians(40.f);
  const int size = 96;
  struct Case {
    float depth, focus, aperture;
  };
  for (const Case c : {Case{2.f, 1.f, 0.3f}, Case{1.f, 2.f, 0.2f}, Case{1.5f, 1.5f, 0.3f},
                       Case{3.f, 1.2f, 0.45f}}) {
    // About 4 pixels wide at any depth (in focus: 1.75), small against the circles (6 to 15
    // pixels in radius), big enough that many lens samples see it.
    const float side = c.depth == c.focus ? 0.02f : 0.03f * c.depth;
    const float aperture = c.aperture;
    const Scene scene = point_like_emitter(c.depth, side, yfov);
    RenderSettings s;
    s.environment = glm::vec3(0.f);  // the square alone, on black
    s.width = s.height = size;
    s.spp = 256;
    s.lens.aperture = aperture;
    s.lens.focus_distance = c.focus;
    const Film film = render(scene, s).film;
    const double tan_half = std::tan(0.5 * yfov);
    const double radius =
        aperture * std::abs(c.depth - c.focus) / c.depth / (2.0 * c.focus * tan_half) * size / 2.0;
    const double square = side / (2.0 * c.depth * tan_half) * size;
    const double predicted = radius * radius / 2.0 + square * square / 6.0 + 1.0 / 6.0;
    const Moment m = second_moment(film, size, size, glm::dvec2(0.5 * size));
    const double measured_radius =
        std::sqrt(2.0 * std::max(0.0, m.value - square * square / 6.0 - 1.0 / 6.0));
    INFO("depth " << c.depth << ", focus " << c.focus << ": moment " << m.value << " ± " << m.error
                  << " px², predicted " << predicted << " (radius " << radius << " px, measured "
                  << measured_radius << ")");
    if (c.depth == c.focus)  // sharp: the square, 1.8 px wide, in the 2 × 2 pixels at the centre
      CHECK(m.value <= 0.5 + 1e-6);
    else
      CHECK(std::abs(m.value - predicted) < 4.0 * m.error + 0.01 * predicted);
  }
}

// Without an aperture (none asked for, or --aperture 0 with a focus) the rays, and so every
// pixel and layer, are the pinhole's bit for bit; an aperture changes them.
TEST_CASE("depth of field: aperture 0 renders the pinhole bit for bit") {
  const Scene scene = lit_scene();
  RenderSettings s = lit_settings();
  s.width = 24, s.height = 16, s.spp = 8;
  s.aovs = AovSet::parse("albedo,normal,depth,position,variance,samples");
  auto channels = [&](const RenderSettings& settings) {
    std::vector<std::vector<float>> out;
    for (Channel& ch : render(scene, settings).film.channels()) out.push_back(std::move(ch.values));
    return out;
  };
  auto bits = [](const std::vector<std::vector<float>>& a,
                 const std::vector<std::vector<float>>& b) {
    if (a.size() != b.size()) return false;
    for (size_t k = 0; k < a.size(); ++k)
      if (a[k].size() != b[k].size() ||
          std::memcmp(a[k].data(), b[k].data(), a[k].size() * sizeof(float)) != 0)
        return false;
    return true;
  };
  const auto pinhole = channels(s);
  for (int variant = 0; variant < 3; ++variant) {
    RenderSettings zero = s;
    zero.lens.aperture = 0.f;
    if (variant == 1) zero.lens.focus_distance = 0.7f;
    if (variant == 2) zero.lens.focus_on = glm::vec3(0.f, 0.f, 0.3f);
    INFO("variant " << variant);
    CHECK(bits(channels(zero), pinhole));
  }
  RenderSettings lens = s;
  lens.lens.aperture = 0.2f;
  CHECK_FALSE(bits(channels(lens), pinhole));
}

TEST_CASE(
    "depth of field: the default focus is the look-at point, the surface ahead, or the centre") {
  Scene scene = point_like_emitter(2.5f, 1.f, 0.7f);
  RenderSettings s;
  s.width = s.height = 8;
  s.lens.aperture = 0.1f;
  Shot shot = make_shot(scene, s);
  CHECK(shot.camera.focus_distance == doctest::Approx(2.5f));  // the square at the centre
  bool said = false;
  for (const std::string& note : shot.notes)
    said |= note.find("focus at depth 2.5, the first surface at the image's centre") !=
            std::string::npos;
  CHECK(said);
  s.camera_override.from = glm::vec3(0.f), s.camera_override.at = glm::vec3(0.f, 0.f, -4.f);
  CHECK(make_shot(scene, s).camera.focus_distance == doctest::Approx(4.f));
  // Beside the square, in its plane, looking at its centre (the scene's): the ray through the
  // image's centre grazes it, so the scene's centre is the focus.
  s.camera_override = {};
  s.camera_override.from = glm::vec3(1.f, 0.f, -2.5f);
  CHECK(make_shot(scene, s).camera.focus_distance == doctest::Approx(1.f));
  s.camera_override = {};
  s.lens.focus_distance = 7.f;
  CHECK(make_shot(scene, s).camera.focus_distance == 7.f);
}

TEST_CASE("depth of field: the CLI's usage errors, the header and merge, the statistics") {
  TempDir dir("dof-cli");
  const std::string cornell = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";
  const std::string common = "render " + cornell + " --quiet --width 16 --height 12 --spp 4 ";
  for (const char* flags :
       {"--aperture -1", "--aperture nan", "--aperture inf", "--aperture 1e39", "--aperture x",
        "--fstop 0", "--fstop -2", "--focus-distance 0", "--focus-distance -1",
        "--focus-distance inf", "--focus-on 1,2", "--focus-on 1,2,nan", "--aperture 0.1 --fstop 2",
        "--fstop 2 --aperture 0", "--focus-distance 1 --focus-on 0,0,0",
        "--focus-on 0,0,0 --focus-distance 1",
        // The Cornell box's camera is at z = -0.8 looking down +Z.
        "--aperture 0.1 --focus-on 0.278,0.273,-2", "--fstop 2 --focus-on 0.278,0.273,-0.8"}) {
    const Run r = run(dir, common + "-o " + (dir / "x.exr") + " " + flags);
    INFO(std::string(flags) << " → " << r.err);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
    CHECK(r.err.find("dacrt render --help") != std::string::npos);
  }
  check_no_outputs(dir);
  // The lens is in the header's camera (as flags), exactly in match.camera, and in --stats.
  REQUIRE(run(dir, common + "--aperture 0.05 --focus-distance 1.25 --samples 0:2 -o " +
                       (dir / "a.exr") + " --stats " + (dir / "a.json"))
              .code == 0);
  const ExrFile a = read_exr_file(dir / "a.exr");
  CHECK(a.attributes.at("camera").find("--aperture 0.05 --focus-distance 1.25") !=
        std::string::npos);
  CHECK(a.attributes.at("match.camera").find(" lens ") != std::string::npos);
  const auto stats = nlohmann::json::parse(slurp(dir / "a.json"));
  CHECK(stats.at("lens").at("aperture").get<double>() == doctest::Approx(0.05));
  CHECK(stats.at("lens").at("focus_distance").get<double>() == doctest::Approx(1.25));
  // Parts of renders with other lenses (or none) are not one render: merge refuses them.
  REQUIRE(run(dir, common + "--samples 2:4 -o " + (dir / "pinhole.exr")).code == 0);
  REQUIRE(run(dir, common + "--fstop 2 --focus-distance 1.25 --samples 2:4 -o " + (dir / "f2.exr"))
              .code == 0);
  REQUIRE(
      run(dir, common + "--aperture 0.05 --focus-distance 1.25 --samples 2:4 -o " + (dir / "b.exr"))
          .code == 0);
  for (const char* other : {"pinhole.exr", "f2.exr"}) {
    const Run merge = run(
        dir, "merge --quiet " + (dir / "a.exr") + " " + (dir / other) + " -o " + (dir / "m.exr"));
    INFO(std::string(other) << ": " << merge.err);
    CHECK(merge.code != 0);
    CHECK(merge.err.find("match.camera") != std::string::npos);
  }
  CHECK(run(dir,
            "merge --quiet " + (dir / "a.exr") + " " + (dir / "b.exr") + " -o " + (dir / "m.exr"))
            .code == 0);
  // A focus without an aperture renders the pinhole and says so.
  const Run note =
      run(dir, "render " + cornell + " --width 8 --height 8 --spp 1 --focus-distance 2 -o " +
                   (dir / "n.exr"));
  CHECK(note.code == 0);
  CHECK(note.err.find("--focus-distance has no effect without --aperture") != std::string::npos);
}
