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

// The thin lens: every ray through one image point, from anywhere on the lens, meets the pinhole
// ray's point on the plane in focus (a plane at the focus distance along the view axis, not a
// sphere around the lens), and the lens points fill a disk of the aperture's diameter uniformly.
TEST_CASE("thin lens: rays through a pixel meet on the focus plane, from a disk of the aperture") {
  for (bool orthographic : {false, true}) {
    INFO(std::string(orthographic ? "orthographic" : "perspective"));
    Camera cam = base_camera();
    cam.to_world = glm::inverse(glm::lookAt(glm::vec3(1, 2, 3), glm::vec3(-2, 1, -4),
                                            glm::vec3(0, 1, 0)));
    cam.orthographic = orthographic;
    cam.ymag = 0.8f;
    cam.aperture = 0.4f, cam.focus_distance = 2.5f;
    const glm::vec3 fwd = forward(cam), position = cam.position();
    const int width = 60, height = 40;
    // An image point off the centre (its ray leaves the axis at 15.6 degrees), where the depth
    // along the axis and the distance along the ray differ by 3.8 %.
    const float x = 47.3f, y = 6.6f;
    Camera pinhole = cam;
    pinhole.aperture = 0.f;
    glm::vec3 po, pd;
    camera_ray(pinhole, width, height, x, y, po, pd);
    const glm::vec3 in_focus = po + pd * (cam.focus_distance / glm::dot(pd, fwd));
    double r2 = 0.0, largest = 0.0;
    const int n = 64;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        glm::vec3 o, d;
        const float tmin =
            camera_ray(cam, width, height, x, y, (i + 0.5f) / n, (j + 0.5f) / n, o, d);
        CHECK(tmin == 0.f);  // znear 0
        CHECK(std::abs(glm::length(d) - 1.f) < 1e-6f);
        // The lens point is on the lens's plane (depth 0), at most the radius off the axis point.
        const glm::vec3 axis_point = orthographic ? po : position;
        const glm::vec3 off = o - axis_point;
        CHECK(std::abs(glm::dot(off, fwd)) < 1e-5f);
        const double r = glm::length(off);
        CHECK(r <= 0.2 + 1e-5);
        r2 += r * r, largest = std::max(largest, r);
        // Where the ray reaches the focus plane's depth: the pinhole ray's point there.
        const glm::vec3 at = o + d * (cam.focus_distance / glm::dot(d, fwd));
        CHECK_MESSAGE(near(at, in_focus, 2e-5f), "lens sample " << i << "," << j);
      }
    // A uniform disk of radius R: mean r² = R² / 2 (the grid's midpoints, 64², to 0.1 %), and
    // points out to its rim.
    CHECK(r2 / (n * n) == doctest::Approx(0.5 * 0.2 * 0.2).epsilon(2e-3));
    CHECK(largest > 0.19);
    // Lens numbers do not change a pinhole's ray.
    glm::vec3 o2, d2;
    camera_ray(pinhole, width, height, x, y, 0.9f, 0.1f, o2, d2);
    CHECK((o2 == po && d2 == pd));
  }
}

// The near plane stays at depth znear whatever the lens point.
TEST_CASE("thin lens: the near plane is at depth znear along the axis") {
  Camera cam = base_camera();
  cam.znear = 0.3f, cam.aperture = 0.5f, cam.focus_distance = 1.7f;
  for (float u : {0.1f, 0.5f, 0.93f}) {
    glm::vec3 o, d;
    const float tmin = camera_ray(cam, 30, 20, 3.f, 17.f, u, 1.f - u, o, d);
    CHECK(glm::dot(o + tmin * d - cam.position(), forward(cam)) == doctest::Approx(0.3f));
  }
}

TEST_CASE("lens camera: aperture, f-number and focus from the request, and their errors") {
  std::vector<std::string> notes;
  const Camera base = base_camera();  // at (1, 2, 3) looking down -Z, yfov 0.5
  LensRequest lens;
  lens.aperture = 0.1f, lens.focus_on = glm::vec3(4, 0, -1);
  Camera c = lens_camera(base, lens, 1.5f, 9.f, notes);
  CHECK(c.aperture == 0.1f);
  CHECK(c.focus_distance == doctest::Approx(4.f));  // its depth along the axis, not its distance
  // An f-number: the full-frame focal length for yfov 0.5 (the 24 mm side vertical in a wide
  // image, the 36 mm side in a tall one) over N.
  LensRequest f;
  f.fstop = 2.f;
  const float focal = 0.012f / std::tan(0.25f);
  CHECK(lens_camera(base, f, 1.5f, 3.f, notes).aperture == doctest::Approx(focal / 2.f));
  CHECK(lens_camera(base, f, 0.5f, 3.f, notes).aperture == doctest::Approx(1.5f * focal / 2.f));
  CHECK(lens_camera(base, f, 1.5f, 3.f, notes).focus_distance == 3.f);  // the default given
  CHECK(notes.empty());
  // A point behind the camera, or beside it, is no focus.
  lens.focus_on = glm::vec3(0, 0, 3.5f);
  CHECK_THROWS_WITH_AS(lens_camera(base, lens, 1.f, 1.f, notes),
                       doctest::Contains("--focus-on 0,0,3.5 is not in front"), SettingError);
  lens.focus_on = glm::vec3(5, 5, 3);
  CHECK_THROWS_AS(lens_camera(base, lens, 1.f, 1.f, notes), SettingError);
  // An f-number needs a field of view.
  Camera ortho = base;
  ortho.orthographic = true;
  CHECK_THROWS_WITH_AS(lens_camera(ortho, f, 1.f, 1.f, notes),
                       doctest::Contains("--fstop needs a field of view"), SettingError);
  // A focus without an aperture: the pinhole, and a note.
  LensRequest focus_only;
  focus_only.focus_distance = 2.f;
  c = lens_camera(base, focus_only, 1.f, 1.f, notes);
  CHECK(c.aperture == 0.f);
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].find("--focus-distance has no effect") != std::string::npos);
}

TEST_CASE("camera: a pinhole's rays made four at a time are ray()'s, bit for bit") {
  // Cameras turned, moved and looking at the sky, with several fields of view and image sizes;
  // points anywhere in the image (its corners too).
  uint32_t state = 51;
  auto uniform = [&] { return float((state = state * 1664525u + 1013904223u) >> 8) * 0x1p-24f; };
  int differ = 0;
  for (int c = 0; c < 24; ++c) {
    Camera camera;
    const glm::vec3 eye(uniform() * 20.f - 10.f, uniform() * 5.f, uniform() * 30.f - 15.f);
    const glm::vec3 target(uniform() * 4.f - 2.f, uniform() * 4.f - 2.f, uniform() * 4.f - 2.f);
    camera.to_world = glm::inverse(glm::lookAt(eye, target, glm::vec3(0.f, 1.f, 0.f)));
    camera.yfov = 0.2f + 2.f * uniform();
    camera.znear = c % 3 == 0 ? 0.f : 0.05f * float(c);
    const int w = 17 + c * 37, h = 9 + c * 23;
    const CameraProjection projection(camera, w, h);
    REQUIRE(projection.pinhole());
    float x[64], y[64], d[3][64], tmin[64];
    for (int k = 0; k < 64; ++k) {
      x[k] = k < 4 ? float((k & 1) * w) : uniform() * float(w);
      y[k] = k < 4 ? float((k >> 1) * h) : uniform() * float(h);
    }
    projection.pinhole_rays(x, y, 64, d[0], d[1], d[2], tmin);
    for (int k = 0; k < 64; ++k) {
      glm::vec3 o, dir;
      const float t = projection.ray(x[k], y[k], o, dir);
      differ += o != glm::vec3(camera.to_world[3]) || dir != glm::vec3(d[0][k], d[1][k], d[2][k]) ||
                t != tmin[k];
    }
  }
  CHECK(differ == 0);
}
