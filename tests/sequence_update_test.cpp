// render --frames keeps each backend from frame to frame and updates it with the next frame's
// geometry (Backend::update, option frames=refit|rebuild|new): every frame's image is the same
// bit for bit as with a new backend per frame (frames=new), for each backend and way of updating,
// on a skinned character and an animated node tree from ../shared/khronos-samples; a frame whose
// triangle count changes is built again, and --stats says so.
#include <doctest/doctest.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "gltf_writer.h"
#include "dacrt/io/exr.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

const fs::path kSamples = fs::path(DACRT_SOURCE_DIR) / "../shared/khronos-samples";

// Renders frames `range` of `scene` at 3 frames a second with `backend` and its `option` (empty:
// the default), to `dir`/`name`.NNNN.exr. Returns the --stats frames.
json render_frames(const TempDir& dir, const std::string& scene, const std::string& backend,
                   const std::string& option, const std::string& name, const std::string& range) {
  const std::string args = "render " + scene + " --quiet --width 40 --height 40 --spp 2 --frames " +
                           range + " --fps 3 --backend " + backend +
                           (option.empty() ? "" : " --backend-option " + option) + " -o " +
                           (dir / (name + ".exr")) + " --stats " + (dir / (name + ".json"));
  const Run r = run(dir, args);
  INFO(args);
  INFO(r.err);
  REQUIRE(r.code == 0);
  return json::parse(slurp(dir / (name + ".json")))["frames"];
}

std::string frame_file(const TempDir& dir, const std::string& name, int frame) {
  std::string number = std::to_string(frame);
  number = std::string(4 - number.size(), '0') + number;
  return dir / (name + "." + number + ".exr");
}

// Every frame of the two renders has the same pixels, bit for bit.
void check_same_frames(const TempDir& dir, const std::string& a, const std::string& b, int first,
                       int last) {
  for (int f = first; f <= last; ++f) {
    INFO("frame " << f);
    const Image x = read_exr(frame_file(dir, a, f)), y = read_exr(frame_file(dir, b, f));
    REQUIRE(x.rgb.size() == y.rgb.size());
    size_t differ = 0;
    for (size_t i = 0; i < x.rgb.size(); ++i)
      differ += std::memcmp(&x.rgb[i], &y.rgb[i], sizeof(float)) != 0;
    CHECK(differ == 0);
  }
}

std::vector<std::string> backends() {
  std::vector<std::string> out = {"dacrt", "dacrt-naive", "brute"};
#ifdef DACRT_HAVE_EMBREE
  out.push_back("embree");
#endif
  return out;
}

}  // namespace

TEST_CASE("sequence: updated backends render every frame as a new backend does, bit for bit") {
  size_t scenes = 0;
  for (const char* name : {"CesiumMan", "BoxAnimated"}) {
    const fs::path glb = kSamples / name / "glTF-Binary" / (std::string(name) + ".glb");
    if (!fs::exists(glb)) continue;
    ++scenes;
    INFO(std::string(name));
    TempDir dir;
    for (const std::string& backend : backends()) {
      INFO(backend);
      render_frames(dir, glb.string(), backend, "frames=new", "new." + backend, "0:3");
      // Every way of following frames the backend has (the default first).
      std::vector<std::string> ways = {""};
      if (backend != "brute") ways.push_back("frames=rebuild");
      if (backend != "brute") ways.push_back("frames=refit");
      for (const std::string& way : ways) {
        INFO("option " << (way.empty() ? "(default)" : way));
        const json frames = render_frames(dir, glb.string(), backend, way, "kept." + backend, "0:3");
        REQUIRE(frames.size() == 4);
        CHECK(frames[0]["update"] == "new");
        const std::string expected = way.empty()
                                         ? (backend == "embree" || backend == "brute" ? "rebuild"
                                                                                      : "refit")
                                         : way.substr(7);
        for (size_t k = 1; k < 4; ++k) {
          CHECK(frames[k]["update"] == expected);
          CHECK(frames[k]["build_seconds"] == 0.0);
          CHECK(frames[k]["update_seconds"].get<double>() > 0.0);
        }
        check_same_frames(dir, "kept." + backend, "new." + backend, 0, 3);
      }
    }
  }
  if (scenes == 0) MESSAGE("skipped: the Khronos samples are not at " << kSamples.string());
}

TEST_CASE("sequence: a frame whose triangle count changes is built again, and --stats says so") {
  TempDir dir;
  // Two quads side by side; the node of the left one scales its Y to 0 at t = 1 (its triangles
  // lose their area and are dropped), the right one stays.
  GltfWriter w;
  auto quad = [](float x) {
    return std::vector<glm::vec3>{{x - 0.3f, -0.3f, 0}, {x + 0.3f, -0.3f, 0}, {x + 0.3f, 0.3f, 0},
                                  {x - 0.3f, -0.3f, 0}, {x + 0.3f, 0.3f, 0},  {x - 0.3f, 0.3f, 0}};
  };
  const int left = w.add_triangles(quad(-0.5f));
  const int right = w.add_triangles(quad(0.5f));
  const std::vector<float> times = {0, 1}, scales = {1, 1, 1, 1, 0, 1};
  const int in = w.add_accessor(w.add_view(times.data(), 8), kFloat, 2, "SCALAR");
  const int out = w.add_accessor(w.add_view(scales.data(), 24), kFloat, 2, "VEC3");
  w.doc["animations"] = {
      {{"samplers", {{{"input", in}, {"output", out}}}},
       {"channels", {{{"sampler", 0}, {"target", {{"node", left}, {"path", "scale"}}}}}}}};
  w.set_scene({left, right});
  const std::string scene = w.write_gltf(dir / "collapse.gltf");
  for (const std::string& backend : backends()) {
    INFO(backend);
    render_frames(dir, scene, backend, "frames=new", "new." + backend, "2:3");  // t = 2/3, then 1
    const json frames = render_frames(dir, scene, backend, "", "kept." + backend, "2:3");
    CHECK(frames[0]["triangles"] == 4);
    CHECK(frames[1]["triangles"] == 2);
    CHECK(frames[1]["degenerate_triangles"] == 2);
    CHECK(frames[1]["update"] == "build");
    check_same_frames(dir, "kept." + backend, "new." + backend, 2, 3);
  }
}
