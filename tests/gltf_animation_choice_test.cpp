// Which animations play (--animation NAME|INDEX|all, GltfOptions::animation): the first by
// default, one by index or name, or all at once; a note names the others when they animate the
// same targets; dacrt info lists them; a choice the file lacks is a usage error. And sequences of
// a file without a camera: one camera (the rest pose's framing) for every frame and --time, each
// frame's EXR with its own match.time.
#include <doctest/doctest.h>

#include <cmath>

#include "cli.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/gltf.h"
#include "gltf_writer.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

int floats(GltfWriter& w, const std::vector<float>& v, const char* type, size_t per) {
  return w.add_accessor(w.add_view(v.data(), v.size() * 4), kFloat, v.size() / per, type);
}

// A square of side 0.3 centred on (0.6, 0) in its mesh, on node 0 (at rest where the mesh says).
// Animation 0 "walk" scales the node by 0.5 and moves it up by 0.3 over [0, 1]; animation 1
// "run" turns it by 90° about Z and moves it down by 0.3. Both animate node 0's translation. At
// t = 1 the square's centre is at (0.3, 0.3) by "walk", (0, 0.3) by "run", (0, 0) by both (run's
// translation and rotation, walk's scale) and (0.6, 0) at rest. An orthographic camera sees
// [-1, 1]² unless `camera` is false.
std::string two_clips(const TempDir& dir, bool camera = true) {
  GltfWriter w;
  std::vector<glm::vec3> quad = {{-0.15f, -0.15f, 0}, {0.15f, -0.15f, 0}, {0.15f, 0.15f, 0},
                                 {-0.15f, -0.15f, 0}, {0.15f, 0.15f, 0},  {-0.15f, 0.15f, 0}};
  for (glm::vec3& p : quad) p.x += 0.6f;
  const int node = w.add_triangles(quad);
  const int times = floats(w, {0, 1}, "SCALAR", 1);
  const float h = std::sqrt(0.5f);
  auto clip = [&](const char* name, std::vector<std::pair<const char*, int>> channels) {
    json samplers = json::array(), list = json::array();
    for (const auto& [path, output] : channels) {
      list.push_back({{"sampler", samplers.size()}, {"target", {{"node", node}, {"path", path}}}});
      samplers.push_back({{"input", times}, {"output", output}});
    }
    w.doc["animations"].push_back({{"name", name}, {"samplers", samplers}, {"channels", list}});
  };
  clip("walk", {{"scale", floats(w, {1, 1, 1, 0.5f, 0.5f, 1}, "VEC3", 3)},
                {"translation", floats(w, {0, 0, 0, 0, 0.3f, 0}, "VEC3", 3)}});
  clip("run", {{"rotation", floats(w, {0, 0, 0, 1, 0, 0, h, h}, "VEC4", 4)},
               {"translation", floats(w, {0, 0, 0, 0, -0.3f, 0}, "VEC3", 3)}});
  if (camera) {
    w.doc["cameras"] = {
        {{"type", "orthographic"},
         {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}}};
    w.set_scene({node, w.add_node({{"camera", 0}, {"translation", {0, 0, 3}}})});
  }
  return w.write_gltf(dir / (camera ? "clips.gltf" : "clips-framed.gltf"));
}

// The centre of the lit pixels of a 40 × 40 image of [-1, 1]² (a pixel is 0.05 wide).
glm::vec2 lit_centre(const std::string& exr) {
  const Image image = read_exr(exr);
  glm::dvec2 sum(0.0);
  int n = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x)
      if (image.rgb[3 * (size_t(y) * 40 + size_t(x))] > 0.5f)
        sum += glm::dvec2((x + 0.5) / 20.0 - 1.0, 1.0 - (y + 0.5) / 20.0), ++n;
  REQUIRE(n > 0);
  return glm::vec2(sum / double(n));
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("cli: --animation plays the first clip, one by index or name, or all of them") {
  TempDir dir;
  const std::string scene = two_clips(dir);
  const std::string common =
      "render " + scene +
      " --width 40 --height 40 --spp 1 --integrator albedo --time 1 --quiet -o " +
      (dir / "out.exr") + " ";
  struct Case {
    std::string option;
    glm::vec2 centre;
    std::string played;  // the EXR's match.animation
  };
  for (const Case& c :
       {Case{"", {0.3f, 0.3f}, "0"}, Case{"--animation 0", {0.3f, 0.3f}, "0"},
        Case{"--animation walk", {0.3f, 0.3f}, "0"}, Case{"--animation 1", {0.f, 0.3f}, "1"},
        Case{"--animation run", {0.f, 0.3f}, "1"}, Case{"--animation all", {0.f, 0.f}, "all"}}) {
    INFO("'" << c.option << "'");
    const Run r = run(dir, common + c.option);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const glm::vec2 at = lit_centre(dir / "out.exr");
    INFO("lit at " << at.x << ", " << at.y);
    CHECK(std::abs(at.x - c.centre.x) < 0.03f);
    CHECK(std::abs(at.y - c.centre.y) < 0.03f);
    // The default names the clip that plays, the one that does not, and the option; a clip
    // chosen by the option is not noted.
    const bool noted = has(r.err, "note: ");
    CHECK(noted == (c.option.empty() || c.option == "--animation all"));
    if (c.option.empty()) {
      CHECK(has(r.err,
                "animation 0 (\"walk\") plays, not 1 (\"run\") (of which 1 (\"run\") "
                "animates the same targets) (--animation NAME|INDEX|all chooses)"));
      CHECK(lines(r.err) == 1);
    }
    if (c.option == "--animation all")
      CHECK(has(r.err, "animations 0 (\"walk\"), 1 (\"run\") animate the same targets"));
    CHECK(read_exr_header(dir / "out.exr").attributes.at("match.animation") == c.played);
  }
  // At rest no animation plays, and none is noted.
  const Run rest = run(dir, "render " + scene + " --width 40 --height 40 --spp 1 --integrator " +
                                "albedo -o " + (dir / "rest.exr"));
  REQUIRE(rest.code == 0);
  CHECK(!has(rest.err, "note: "));
  CHECK(std::abs(lit_centre(dir / "rest.exr").x - 0.6f) < 0.03f);
  CHECK(read_exr_header(dir / "rest.exr").attributes.at("match.animation") == "rest pose");

  // The loader's API: the default, an index, a name, all.
  auto node_x = [&](const std::string& choice) {
    GltfOptions o;
    o.time = 1.0, o.animation = choice;
    const Scene s = load_gltf(scene, o);
    return s.bounds().center().x;
  };
  CHECK(node_x("") == doctest::Approx(0.3).epsilon(1e-4));
  CHECK(node_x("1") == doctest::Approx(0.0).scale(1).epsilon(1e-4));
  CHECK(node_x("all") == doctest::Approx(0.0).scale(1).epsilon(1e-4));
}

TEST_CASE("cli: dacrt info lists the animations, an unknown one is a usage error") {
  TempDir dir;
  const std::string scene = two_clips(dir);
  const Run info = run(dir, "info " + scene);
  REQUIRE(info.code == 0);
  CHECK(has(info.out, "animation  2 animations, keyframes to 1 s"));
  CHECK(
      has(info.out, "  animation 0 \"walk\": keyframes to 1 s, plays, animates targets of 1 too"));
  CHECK(has(info.out, "  animation 1 \"run\": keyframes to 1 s, animates targets of 0 too"));
  const Run second = run(dir, "info " + scene + " --animation run");
  REQUIRE(second.code == 0);
  CHECK(has(second.out, "  animation 1 \"run\": keyframes to 1 s, plays"));
  CHECK(!has(second.out, "\"walk\": keyframes to 1 s, plays"));
  const Run all = run(dir, "info " + scene + " --scene 0 --animation all");
  REQUIRE(all.code == 0);
  CHECK(has(all.out, "\"walk\": keyframes to 1 s, plays"));
  CHECK(has(all.out, "\"run\": keyframes to 1 s, plays"));

  for (const char* option : {"--animation 2", "--animation jog", "--animation ''",
                             "--animation 99999999999", "--animation"}) {
    const std::string bad = option;
    INFO(bad);
    for (const std::string& command :
         {"render " + scene + " --time 1 --quiet -o " + (dir / "x.exr"), "info " + scene}) {
      const Run r = run(dir, command + " " + bad);
      CHECK(r.code == 2);
      CHECK(lines(r.err) == 1);
      if (bad == "--animation jog" || bad == "--animation 2")
        CHECK(has(r.err, "(it has 2: 0 (\"walk\"), 1 (\"run\"))"));
    }
  }
  CHECK(!fs::exists(dir / "x.exr"));
}

TEST_CASE("cli: a sequence of a file without a camera keeps one view, each frame its own time") {
  TempDir dir;
  const std::string scene = two_clips(dir, false);
  // Frames 0..2 at 2 fps: t = 0, 0.5, 1, the square moving and shrinking ("walk").
  const std::string common =
      "render " + scene + " --width 40 --height 40 --spp 1 --integrator albedo ";
  const Run frames = run(dir, common + "--frames 0:2 --fps 2 -o " + (dir / "f.exr"));
  INFO(frames.err);
  REQUIRE(frames.code == 0);
  std::vector<ExrHeader> headers;
  for (int f = 0; f <= 2; ++f)
    headers.push_back(read_exr_header(dir / ("f.000" + std::to_string(f) + ".exr")));
  // The same camera for every frame (framed on the rest pose, not on each frame's bounds) ...
  for (int f = 1; f <= 2; ++f) {
    CHECK(headers[size_t(f)].attributes.at("match.camera") ==
          headers[0].attributes.at("match.camera"));
  }
  // ... and each frame's own time.
  CHECK(headers[0].attributes.at("match.time") == "0");
  CHECK(headers[1].attributes.at("match.time") == "0.5");
  CHECK(headers[2].attributes.at("match.time") == "1");
  // --look-from without --look-at looks at the rest pose's centre in every frame too.
  REQUIRE(
      run(dir, common + "--quiet --look-from 0.5,0.5,3 --frames 0:2 --fps 2 -o " + (dir / "l.exr"))
          .code == 0);
  const std::string looking = read_exr_header(dir / "l.0000.exr").attributes.at("match.camera");
  CHECK(read_exr_header(dir / "l.0001.exr").attributes.at("match.camera") == looking);
  CHECK(read_exr_header(dir / "l.0002.exr").attributes.at("match.camera") == looking);
  CHECK(looking != headers[0].attributes.at("match.camera"));
  // --time renders the frame of that time, pixel for pixel (the same view).
  REQUIRE(run(dir, common + "--quiet --time 0.5 -o " + (dir / "t.exr")).code == 0);
  const Image frame = read_exr(dir / "f.0001.exr"), at_time = read_exr(dir / "t.exr");
  CHECK(frame.rgb == at_time.rgb);
  // The view is the rest pose's: the file loaded at rest frames the same camera.
  const Run rest = run(dir, common + "--quiet -o " + (dir / "rest.exr"));
  REQUIRE(rest.code == 0);
  CHECK(read_exr_header(dir / "rest.exr").attributes.at("match.camera") ==
        headers[0].attributes.at("match.camera"));
}

TEST_CASE("a still sequence of a file without a camera renders identical frames") {
  TempDir dir;
  // A square that does not move, and an animation of an empty node far away (which moves
  // nothing visible: the bounds are the square's at every time).
  GltfWriter w;
  const std::vector<glm::vec3> quad = {{-0.2f, -0.2f, 0}, {0.2f, -0.2f, 0}, {0.2f, 0.2f, 0},
                                       {-0.2f, -0.2f, 0}, {0.2f, 0.2f, 0},  {-0.2f, 0.2f, 0}};
  const int square = w.add_triangles(quad);
  const int empty = w.add_node(json::object());
  w.set_scene({square, empty});
  const int in = floats(w, {0, 1}, "SCALAR", 1), out = floats(w, {0, 0, 0, 5, 5, 5}, "VEC3", 3);
  w.doc["animations"] = {
      {{"samplers", {{{"input", in}, {"output", out}}}},
       {"channels", {{{"sampler", 0}, {"target", {{"node", empty}, {"path", "translation"}}}}}}}};
  const std::string scene = w.write_gltf(dir / "still.gltf");
  const Run r =
      run(dir, "render " + scene + " --width 24 --height 24 --spp 4 --frames 0:2 --fps 2 " +
                   "--quiet -o " + (dir / "s.exr"));
  REQUIRE(r.code == 0);
  const Image first = read_exr(dir / "s.0000.exr");
  for (const char* name : {"s.0001.exr", "s.0002.exr"}) {
    INFO(name);
    CHECK(read_exr(dir / name).rgb == first.rgb);
  }
}
