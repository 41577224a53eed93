// The CLI's animation options: --time poses the file, --frames FIRST:LAST --fps F renders
// numbered images (each frame where its time puts the animated quad), prints each frame's
// geometry and build times (and writes them to --stats); bad ranges are usage errors.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "gltf_writer.h"
#include "dacrt/io/exr.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

// A white square of side 0.4 moved along X from -0.5 at t = 0 to 0.5 at t = 1 (LINEAR), under
// an orthographic camera that sees [-1, 1]² in 20 × 20 pixels.
std::string moving_quad(const TempDir& dir) {
  GltfWriter w;
  const std::vector<glm::vec3> quad = {{-0.2f, -0.2f, 0}, {0.2f, -0.2f, 0}, {0.2f, 0.2f, 0},
                                       {-0.2f, -0.2f, 0}, {0.2f, 0.2f, 0},  {-0.2f, 0.2f, 0}};
  const int node = w.add_triangles(quad);
  const std::vector<float> times = {0, 1}, xs = {-0.5f, 0, 0, 0.5f, 0, 0};
  const int in = w.add_accessor(w.add_view(times.data(), 8), kFloat, 2, "SCALAR");
  const int out = w.add_accessor(w.add_view(xs.data(), 24), kFloat, 2, "VEC3");
  w.doc["animations"] = {
      {{"samplers", {{{"input", in}, {"output", out}}}},
       {"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", "translation"}}}}}}}};
  w.doc["cameras"] = {{{"type", "orthographic"},
                       {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}}};
  const int camera = w.add_node({{"camera", 0}, {"translation", {0, 0, 3}}});
  w.set_scene({node, camera});
  return w.write_gltf(dir / "moving.gltf");
}

// The mean x of the lit pixels of a 20 × 20 image of [-1, 1]².
double lit_x(const std::string& exr) {
  const Image image = read_exr(exr);
  double sum = 0.0;
  int n = 0;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x)
      if (image.rgb[3 * (size_t(y) * 20 + size_t(x))] > 0.5f) sum += (x + 0.5) / 10.0 - 1.0, ++n;
  REQUIRE(n > 0);
  return sum / n;
}

}  // namespace

TEST_CASE("cli: --time poses the scene, --frames renders numbered frames with their timings") {
  TempDir dir;
  const std::string scene = moving_quad(dir);
  const std::string common =
      "render " + scene + " --width 20 --height 20 --spp 1 --integrator albedo ";
  REQUIRE(run(dir, common + "--quiet --time 0.75 -o " + (dir / "t.exr")).code == 0);
  CHECK(lit_x(dir / "t.exr") == doctest::Approx(0.25).epsilon(0.1));
  const Run info = run(dir, "info " + scene);
  CHECK(info.out.find("animation  1 animations, keyframes to 1 s") != std::string::npos);
  REQUIRE(run(dir, common + "--quiet -o " + (dir / "rest.exr")).code == 0);
  CHECK(lit_x(dir / "rest.exr") == doctest::Approx(0.0).scale(1).epsilon(0.05));  // no channel

  std::string backends = "dacrt";
#ifdef DACRT_HAVE_EMBREE
  backends += ",embree";
#endif
  const Run frames = run(dir, common + "--frames 1:3 --fps 4 --backend " + backends + " -o " +
                                  (dir / "f.exr") + " --stats " + (dir / "f.json"));
  REQUIRE(frames.code == 0);
  INFO(frames.err);
  for (int f = 1; f <= 3; ++f) {
    const std::string number = "000" + std::to_string(f);
    // Frame f at t = f / 4: x = -0.5 + f / 4.
    for (const std::string& b : {std::string("dacrt")
#ifdef DACRT_HAVE_EMBREE
                                     ,
                                 std::string("embree")
#endif
         }) {
      const std::string exr = dir / ("f." + b + "." + number + ".exr");
      REQUIRE(fs::exists(exr));
      CHECK(lit_x(exr) == doctest::Approx(-0.5 + f / 4.0).scale(1).epsilon(0.05));
    }
    const char* times[] = {"", "0.25", "0.5", "0.75"};
    CHECK(frames.err.find("frame " + std::to_string(f) + " (" + std::to_string(f) + " of 3, t = " +
                          times[f] + " s): geometry") != std::string::npos);
  }
  CHECK(!fs::exists(dir / "f.0000.dacrt.exr"));
  CHECK(!fs::exists(dir / "f.0004.dacrt.exr"));
  CHECK(frames.err.find("geometry ") != std::string::npos);
  CHECK(frames.err.find("dacrt build ") != std::string::npos);
#ifdef DACRT_HAVE_EMBREE
  CHECK(frames.err.find("embree build ") != std::string::npos);
#endif
  const json stats = json::parse(slurp(dir / "f.json"));
  REQUIRE(stats["frames"].size() == 3);
  for (size_t k = 0; k < 3; ++k) {
    CHECK(stats["frames"][k]["frame"] == int(k) + 1);
    CHECK(stats["frames"][k]["time"] == doctest::Approx((k + 1) / 4.0));
    CHECK(stats["frames"][k]["geometry_seconds"].get<double>() >= 0.0);
    CHECK(stats["frames"][k]["backends"][0]["build_seconds"].get<double>() >= 0.0);
  }
}

TEST_CASE("cli: bad --frames, --fps and --time are usage errors") {
  TempDir dir;
  const std::string scene = moving_quad(dir);
  for (const char* bad : {"--frames 3:1", "--frames 1", "--frames a:2", "--frames -1:2",
                          "--frames 1:2 --fps 0", "--frames 1:2 --fps -3", "--fps 24",
                          "--time -1", "--time nan", "--time 1 --frames 1:2",
                          "--frames 0:200000"}) {
    INFO(bad);
    const Run r = run(dir, "render " + scene + " --quiet -o " + (dir / "x.exr") + " " + bad);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
  }
  CHECK(!fs::exists(dir / "x.exr"));
}
