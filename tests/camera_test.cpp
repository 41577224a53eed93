// Cameras from the command line (--look-from, --look-at, --up, --fov): what each part overrides,
// the errors, and `dacrt info`'s printed form rendering the camera it describes.
#include <doctest/doctest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>

#include "cli.h"
#include "dacrt/io/exr.h"
#include "dacrt/scene/scene.h"
#include "dacrt/util/error.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

bool near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) {
  return glm::length(a - b) <= eps;
}

glm::vec3 forward(const Camera& c) {
  return -glm::vec3(c.to_world[2]);
}
glm::vec3 up(const Camera& c) {
  return glm::vec3(c.to_world[1]);
}

// A camera at (1, 2, 3) looking down -Z, yfov 0.5, with an aspect ratio.
Camera base_camera() {
  Camera c;
  c.name = "file";
  c.to_world = glm::translate(glm::mat4(1.f), glm::vec3(1, 2, 3));
  c.yfov = 0.5f;
  c.aspect = 1.5f;
  return c;
}

}  // namespace

TEST_CASE("camera override: each part replaces only its own") {
  const Camera base = base_camera();
  const glm::vec3 target(0, 0, -10);
  // Nothing given: the camera as it was.
  Camera same = override_camera(base, {}, target);
  CHECK(near(same.position(), {1, 2, 3}));
  CHECK(near(forward(same), {0, 0, -1}));
  CHECK(same.name == "file");
  // All given.
  CameraOverride all;
  all.from = glm::vec3(0, 0, 0), all.at = glm::vec3(10, 0, 0), all.up = glm::vec3(0, 0, 1);
  all.fov_degrees = 90.f;
  Camera c = override_camera(base, all, target);
  CHECK(near(c.position(), {0, 0, 0}));
  CHECK(near(forward(c), {1, 0, 0}));
  CHECK(near(up(c), {0, 0, 1}));
  CHECK(c.yfov == doctest::Approx(glm::half_pi<float>()));
  CHECK(c.aspect == 1.5f);  // the image's shape stays the file camera's
  CHECK(c.name == "command line");
  // An up that is not orthogonal to the view is made so (LookAt), keeping its side.
  all.up = glm::vec3(1, 0, 1);
  CHECK(near(up(override_camera(base, all, target)), {0, 0, 1}));
  // Only the position: it looks at the target (the scene's centre), keeping its up.
  CameraOverride from;
  from.from = glm::vec3(0, 0, 10);
  c = override_camera(base, from, target);
  CHECK(near(c.position(), {0, 0, 10}));
  CHECK(near(forward(c), {0, 0, -1}));
  from.from = glm::vec3(-10, 0, -10);
  CHECK(near(forward(override_camera(base, from, target)), {1, 0, 0}));
  // Only the point looked at: from where it is.
  CameraOverride at;
  at.at = glm::vec3(1, 2, 13);
  c = override_camera(base, at, target);
  CHECK(near(c.position(), {1, 2, 3}));
  CHECK(near(forward(c), {0, 0, 1}));
  // Only the field of view: the pose is kept; an orthographic camera becomes perspective.
  CameraOverride fov;
  fov.fov_degrees = 30.f;
  Camera ortho = base;
  ortho.orthographic = true;
  c = override_camera(ortho, fov, target);
  CHECK_FALSE(c.orthographic);
  CHECK(c.yfov == doctest::Approx(glm::radians(30.f)));
  CHECK(near(c.position(), {1, 2, 3}));
  CHECK(near(forward(c), {0, 0, -1}));
}

TEST_CASE("camera override: a position equal to the point looked at, or up along the view") {
  const Camera base = base_camera();
  CameraOverride o;
  o.from = glm::vec3(1, 1, 1), o.at = glm::vec3(1, 1, 1);
  CHECK_THROWS_WITH_AS(override_camera(base, o, {}), doctest::Contains("--look-at must differ"),
                       Error);
  o.at = glm::vec3(1, 5, 1);  // straight up, with up +Y
  CHECK_THROWS_WITH_AS(override_camera(base, o, {}), doctest::Contains("--up"), Error);
  o.up = glm::vec3(0, 0, 0);
  CHECK_THROWS_AS(override_camera(base, o, {}), Error);
  o.up = glm::vec3(0, 0, 1);
  CHECK_NOTHROW(override_camera(base, o, {}));
}

TEST_CASE("camera flags: usage errors, and info's printed camera renders the same view") {
  TempDir dir("camera-cli");
  const std::string cornell = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";
  for (const char* flags : {"--look-from 1,2", "--look-from 1,2,x", "--look-at 1,2,3,4", "--fov 0",
                            "--fov 180", "--up nan,1,0", "--look-from 0,0,0 --look-at 0,0,0",
                            "--look-from 0,0,0 --look-at 0,5,0 --up 0,1,0"}) {
    Run r = run(dir, "render " + cornell + " --quiet -o " + (dir / "x.exr") + " " + flags);
    INFO(flags << " → " << r.err);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
  }
  // info prints each camera as flags; rendering with them gives camera 0's image.
  Run info = run(dir, "info " + cornell);
  REQUIRE(info.code == 0);
  const size_t at = info.out.find("    --look-from ");
  REQUIRE(at != std::string::npos);
  const std::string flags = info.out.substr(at + 4, info.out.find('\n', at) - at - 4);
  const std::string common = "render " + cornell + " --quiet --width 24 --height 24 --spp 4 ";
  REQUIRE(run(dir, common + "-o " + (dir / "file.exr")).code == 0);
  REQUIRE(run(dir, common + flags + " -o " + (dir / "flags.exr")).code == 0);
  // Looking the other way (from the back wall towards the opening) gives another image.
  REQUIRE(run(dir, common + "--look-from 0.278,0.273,0.5 --look-at 0.278,0.273,-0.8 -o " +
                       (dir / "back.exr"))
              .code == 0);
  const Image file = read_exr(dir / "file.exr"), with_flags = read_exr(dir / "flags.exr"),
              back = read_exr(dir / "back.exr");
  auto mean_difference = [](const Image& a, const Image& b) {
    double d = 0.0, m = 0.0;
    for (size_t i = 0; i < a.rgb.size(); ++i) d += std::abs(a.rgb[i] - b.rgb[i]), m += a.rgb[i];
    return d / m;
  };
  // Printed to 7 digits, the flags move rays by ~1e-7 (measured: 1.2e-7 of the image's sum).
  CHECK(mean_difference(file, with_flags) < 1e-3);
  CHECK(mean_difference(file, back) > 0.2);
}

TEST_CASE("camera override: a new view from the framed camera is upright (its up is +Y)") {
  // The framed camera looks down at the scene: its image's up leans back. A new position or
  // direction keeps the up it was aimed with, +Y, so the new image is not tilted.
  const Camera framed = frame_bounds(Box{glm::vec3(-1.f), glm::vec3(1.f)}, 1.f);
  CHECK(glm::vec3(framed.to_world[1]).y < 0.99f);
  CHECK(near(framed.up(), {0, 1, 0}));
  CameraOverride o;
  o.from = glm::vec3(3, 0.5f, 0), o.at = glm::vec3(0, 0, 2);
  const Camera c = override_camera(framed, o, {});
  CHECK(std::abs(c.to_world[0].y) < 1e-6f);  // the image's horizontal is the world's
  CHECK(up(c).y > 0.9f);
  CHECK(near(c.up(), {0, 1, 0}));
}
