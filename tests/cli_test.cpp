// The dacrt command line as a user meets it: exit codes (0 ok, 1 error, 2 usage), one clear line
// on stderr for bad input, and never an output file (or a temporary one) after a failure.
#include "cli.h"

#include <doctest/doctest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "gltf_writer.h"
#include "dacrt/io/color.h"
#include "dacrt/io/exr.h"
#include "ocio_config.h"
#include "test_geometry.h"

using namespace dacrt;
using namespace dacrt::test;
namespace fs = std::filesystem;

namespace {

const std::string cornell = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";

size_t split_count(const std::string& list) {
  return size_t(std::count(list.begin(), list.end(), ',')) + 1;
}

}  // namespace

TEST_CASE("cli: help and usage errors") {
  TempDir dir("cli-usage");
  Run help = run(dir, "--help");
  CHECK(help.code == 0);
  CHECK(help.out.find("dacrt render SCENE") != std::string::npos);
  CHECK(help.out.find("dacrt views") != std::string::npos);
  Run render_help = run(dir, "render --help");
  CHECK(render_help.code == 0);
  for (const char* flag :
       {"--spp", "--backend", "--preview", "--environment", "--max-depth", "--seed", "--threads",
        "--quiet", "--stats", "--camera", "--integrator", "--view", "--exposure"})
    CHECK_MESSAGE(render_help.out.find(flag) != std::string::npos, flag);
  for (const char* args :
       {"", "frobnicate", "render",
        "render " DACRT_SOURCE_DIR "/scenes/cornell-box.gltf --spp many", "render x.gltf --spp 0",
        "render x.gltf --width", "render x.gltf --bogus", "render x.gltf --environment 1,2",
        "render x.gltf --environment 1,nan,1", "render a.gltf b.gltf", "info",
        "render x.gltf --view sRGB", "render x.gltf --exposure 1",
        "render x.gltf --preview p.png --view ''", "render x.gltf --preview p.png --exposure nan",
        "render x.gltf --preview p.png --exposure 1e999",
        "render x.gltf --preview p.png --exposure 1x",
        "render x.gltf --preview p.png --exposure ''", "views sRGB"}) {
    Run r = run(dir, args);
    INFO(args << " → " << r.err);
    CHECK(r.code == 2);
    CHECK(lines(r.err) >= 1);
  }
}

TEST_CASE("cli: bad scenes fail with one line naming the file, and write nothing") {
  TempDir dir("cli-bad");
  std::vector<std::pair<std::string, std::string>> cases;  // file, word the message must hold
  write_text(dir / "not-json.gltf", "{ this is not json");
  cases.push_back({"not-json.gltf", "JSON"});
  {
    GltfWriter w;
    w.add_triangles({{0, 0, 0}, {1, std::nanf(""), 0}, {0, 1, 0}});
    w.write_gltf(dir / "nan.gltf");
    cases.push_back({"nan.gltf", "finite"});
  }
  {
    GltfWriter w;
    int node = w.add_triangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    w.doc["nodes"][node]["children"] = {node};
    w.write_gltf(dir / "cycle.gltf");
    cases.push_back({"cycle.gltf", "node"});
  }
  {
    GltfWriter w;
    w.add_triangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    w.write_gltf(dir / "missing-buffer.gltf", false);
    fs::remove(dir / "missing-buffer.bin");
    cases.push_back({"missing-buffer.gltf", "buffer"});
  }
  cases.push_back({"does-not-exist.gltf", "does-not-exist.gltf"});
  for (const auto& [file, word] : cases) {
    Run r = run(dir, "render " + (dir / file) + " -o " + (dir / "out.exr") + " --preview " +
                         (dir / "out.png") + " --stats " + (dir / "out.json") + " --spp 1");
    INFO(file << " → " << r.err);
    CHECK(r.code == 1);
    CHECK(lines(r.err) == 1);
    CHECK(r.err.find(file) != std::string::npos);
    CHECK(r.err.find(word) != std::string::npos);
    check_no_outputs(dir);
    Run info = run(dir, "info " + (dir / file));
    CHECK(info.code == 1);
    CHECK(lines(info.err) == 1);
  }
}

TEST_CASE("cli: an unwritable output fails before rendering, and names the path") {
  TempDir dir("cli-unwritable");
  Run r = run(dir, "render " + cornell + " -o " + (dir / "no/such/dir/x.exr") + " --spp 1");
  CHECK(r.code == 1);
  CHECK(lines(r.err) == 1);
  CHECK(r.err.find("no/such/dir") != std::string::npos);
  Run bad_backend = run(dir, "render " + cornell + " -o " + (dir / "x.exr") + " --backend warp");
  CHECK(bad_backend.code == 2);  // (a usage error)
  CHECK(bad_backend.err.find("warp") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "x.exr"));
}

TEST_CASE("cli: render writes the EXR, the preview and the statistics") {
  TempDir dir("cli-render");
  Run r = run(dir, "render " + cornell + " -o " + (dir / "cb.exr") + " --preview " +
                       (dir / "cb.png") + " --stats " + (dir / "cb.json") +
                       " --width 24 --height 20 --spp 4 --quiet --threads 2");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.err.empty());  // --quiet
  Image img = read_exr(dir / "cb.exr");
  CHECK(img.width == 24);
  CHECK(img.height == 20);
  double sum = 0;
  for (float v : img.rgb) sum += v;
  CHECK(sum > 0.0);
  CHECK(fs::file_size(dir / "cb.png") > 0);
  auto stats = nlohmann::json::parse(slurp(dir / "cb.json"));
  CHECK(stats["spp"] == 4);
  CHECK(stats["backend"] == "dacrt");
  CHECK(stats["rays"]["primary"]["rays"] == 24 * 20 * 4);
  CHECK(stats["rays"]["shadow"]["rays"].get<uint64_t>() > 0);
  CHECK(stats["rays"]["bounce"]["rays"].get<uint64_t>() > 0);
  // Without --quiet there is a summary with rays/s per ray type.
  Run loud =
      run(dir, "render " + cornell + " -o " + (dir / "cb2.exr") + " --width 8 --height 8 --spp 1");
  CHECK(loud.code == 0);
  CHECK(loud.err.find("Mrays/s") != std::string::npos);
  // info describes the scene.
  Run info = run(dir, "info " + cornell);
  CHECK(info.code == 0);
  CHECK(info.out.find("triangles  32") != std::string::npos);
  CHECK(info.out.find("lights     2 emissive triangles") != std::string::npos);
}

TEST_CASE("cli: --scene picks one of the file's scenes, for render and info") {
  TempDir dir("cli-scenes");
  GltfWriter w;
  const std::vector<glm::vec3> one = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<glm::vec3> two = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                      {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  int a = w.add_node({{"mesh", w.add_mesh({GltfWriter::primitive(w.add_vec3(one))})}});
  int b = w.add_node({{"mesh", w.add_mesh({GltfWriter::primitive(w.add_vec3(two))})}});
  w.doc["scenes"] = {{{"nodes", {a}}}, {{"nodes", {b}}}};
  w.doc["scene"] = 0;
  const std::string file = dir / "scenes.gltf";
  w.write_gltf(file);
  CHECK(run(dir, "info " + file).out.find("triangles  1\n") != std::string::npos);
  CHECK(run(dir, "info " + file + " --scene 1").out.find("triangles  2\n") != std::string::npos);
  Run ok = run(dir, "render " + file + " --scene 1 -o " + (dir / "one.exr") +
                        " --width 4 --height 4 --spp 1 --quiet");
  CHECK(ok.code == 0);
  Run missing = run(dir, "render " + file + " --scene 2 -o " + (dir / "two.exr") + " --quiet");
  CHECK(missing.code != 0);
  CHECK(missing.err.find("scene 2") != std::string::npos);
  CHECK(!fs::exists(dir / "two.exr"));
}

TEST_CASE("cli: a white sphere under --environment 1,1,1 renders 1 everywhere") {
  TempDir dir("cli-furnace");
  Geometry g = sphere(24, 48, glm::vec3(0.f), 1.f);
  std::vector<glm::vec3> positions;
  for (size_t i = 0; i < g.size(); ++i)
    for (int c = 0; c < 3; ++c) positions.push_back(g.vertex(i, c));
  GltfWriter w;
  // The furnace: base colour 1, metallic 0, KHR_materials_specular factor 0.
  w.add_material({{"pbrMetallicRoughness", {{"metallicFactor", 0}}},
                  {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}});
  w.add_triangles(positions, {{"material", 0}});
  w.write_glb(dir / "sphere.glb");
  Run r = run(dir, "render " + (dir / "sphere.glb") + " -o " + (dir / "sphere.exr") +
                       " --environment 1,1,1 --sample-environment off --width 16 --height 16"
                       " --spp 4 --quiet");
  INFO(r.err);
  REQUIRE(r.code == 0);
  Image img = read_exr(dir / "sphere.exr");
  size_t off = 0;
  for (float v : img.rgb) off += std::abs(v - 1.f) > 1e-5f;
  CHECK(off == 0);  // BSDF sampling alone: every sample is 1
  // Sampled as a light, 1 on average only.
  Run nee = run(dir, "render " + (dir / "sphere.glb") + " -o " + (dir / "nee.exr") +
                         " --environment 1,1,1 --sample-environment on --width 16 --height 16"
                         " --spp 4 --quiet");
  REQUIRE(nee.code == 0);
  off = 0;
  for (float v : read_exr(dir / "nee.exr").rgb) off += std::abs(v - 1.f) > 1e-5f;
  CHECK(off > 0);
  Run bad = run(dir, "render " + (dir / "sphere.glb") + " -o " + (dir / "bad.exr") +
                         " --sample-environment sometimes --quiet");
  CHECK(bad.code == 2);
  CHECK(bad.err.find("--sample-environment wants auto, on or off, not 'sometimes'") !=
        std::string::npos);
  // The same furnace with --environment FILE.exr holding 1 everywhere: sampled, so 1 on average.
  Image sky(16, 8);
  std::fill(sky.rgb.begin(), sky.rgb.end(), 1.f);
  write_exr(dir / "sky.exr", sky, {});
  Run map = run(dir, "render " + (dir / "sphere.glb") + " -o " + (dir / "mapped.exr") +
                         " --environment " + (dir / "sky.exr") +
                         " --width 16 --height 16 --spp 16 --quiet");
  INFO(map.err);
  REQUIRE(map.code == 0);
  Image mapped = read_exr(dir / "mapped.exr");
  double mean = 0.0;
  for (float v : mapped.rgb) mean += v;
  mean /= double(mapped.rgb.size());
  CHECK(mean == doctest::Approx(1.0).epsilon(0.02));
  // A missing map is one error naming it, and no image.
  Run missing = run(dir, "render " + (dir / "sphere.glb") + " -o " + (dir / "none.exr") +
                             " --environment " + (dir / "nowhere.exr") + " --quiet");
  CHECK(missing.code != 0);
  CHECK(missing.err.find("nowhere.exr") != std::string::npos);
  CHECK(!fs::exists(dir / "none.exr"));
  // Without --environment the same scene is black where nothing emits: the default is 1 only
  // because the scene has no emitters, and the render says so.
  Run loud = run(dir, "render " + (dir / "sphere.glb") + " -o " + (dir / "sphere2.exr") +
                          " --width 4 --height 4 --spp 1");
  CHECK(loud.err.find("no emitters") != std::string::npos);
  Run black = run(dir, "render " + (dir / "sphere.glb") + " -o " + (dir / "sphere3.exr") +
                           " --environment 0,0,0 --width 4 --height 4 --spp 1 --quiet");
  REQUIRE(black.code == 0);
  for (float v : read_exr(dir / "sphere3.exr").rgb) CHECK(v == 0.f);
}

TEST_CASE("cli: --backend a,b,c renders with each, names each image, and compares them") {
  TempDir dir;
  const std::string out = (dir / "box.exr");
  std::string backends = "dacrt,dacrt-naive,brute";
#ifdef DACRT_HAVE_EMBREE
  backends += ",embree";
#endif
  Run r = run(
      dir, "render " + cornell + " --width 24 --height 16 --spp 2 --quiet --backend " + backends +
               " --backend-option dacrt.top_triangles=0 --backend-option dacrt.leaf_lanes=1 -o " +
               out + " --preview " + (dir / "box.png") + " --stats " + (dir / "box.json"));
  REQUIRE(r.code == 0);
  CHECK(r.err.empty());
  // One image and preview per backend; the exact ones are the same image, bit for bit.
  const Image reference = read_exr(dir / "box.dacrt.exr");
  for (const char* name : {"dacrt-naive", "brute"}) {
    INFO(name);
    CHECK(read_exr(dir / ("box." + std::string(name) + ".exr")).rgb == reference.rgb);
    CHECK(fs::exists(dir / ("box." + std::string(name) + ".png")));
  }
  CHECK(!fs::exists(out));
  // The table: a column per backend, the ray types, the kernel's counters, the speed-up row.
  const std::string speedup = "speed-up vs dacrt, higher is faster";
  for (const char* text :
       {"dacrt-naive", "brute", "primary rays", "shadow Mrays/s", "bounce 1 rays",
        "bounce batch min/median/max", "box tests", "triangle tests", "filter skips",
        "render s, build included", speedup.c_str()})
    CHECK_MESSAGE(r.out.find(text) != std::string::npos, "missing: " << text);
  // The statistics: one entry per backend, with the same rays for the exact ones, and the
  // option given to dacrt alone reached it (nothing kept) without upsetting the others.
  const nlohmann::json j = nlohmann::json::parse(slurp(dir / "box.json"));
  REQUIRE(j["backends"].size() == split_count(backends));
  // The speed-up row: dacrt's seconds over each backend's (higher is faster), to two decimals.
  {
    std::istringstream row(r.out.substr(r.out.find(speedup) + speedup.size()));
    for (const auto& b : j["backends"]) {
      double printed = -1.0;
      row >> printed;
      INFO(b["backend"].get<std::string>());
      CHECK(std::abs(printed - j["backends"][0]["seconds_with_build"].get<double>() /
                                   b["seconds_with_build"].get<double>()) <= 0.0051);
    }
  }
  CHECK(j["backends"][0]["backend"] == "dacrt");
  CHECK(j["backends"][0]["rays"]["bounce"]["rays"] == j["backends"][2]["rays"]["bounce"]["rays"]);
  CHECK(j["backends"][0]["backend_stats"]["nodes"].get<uint64_t>() > 0);
  CHECK(j["backends"][0]["backend_stats"]["kept_nodes"] == 0);
  // A backend it does not know is an error before anything renders.
  Run bad = run(dir, "render " + cornell + " --width 8 --height 8 --spp 1 --quiet --backend " +
                         "dacrt,nosuch -o " + (dir / "bad.exr"));
  CHECK(bad.code != 0);
  CHECK(!fs::exists(dir / "bad.dacrt.exr"));
}

TEST_CASE("cli: --view and --exposure change the preview only, as to_display makes it") {
  TempDir dir("cli-view");
  ScopedOcioEnv env(nullptr);
  const std::string aces = "ACES 1.0 SDR-video (sRGB)";
  auto render = [&](const std::string& name, const std::string& flags) {
    Run r = run(dir,
                "render " + cornell + " --width 24 --height 20 --spp 4 --quiet -o " +
                    (dir / (name + ".exr")) + " --preview " + (dir / (name + ".png")) + flags,
                "env -u OCIO");
    INFO(r.err);
    CHECK(r.code == 0);
  };
  render("default", "");
  render("srgb", " --view sRGB --exposure 0");
  render("aces", " --view '" + aces + "' --exposure 1");
  // The EXR stays the same linear radiance; the default view is sRGB, bit for bit.
  const Image image = read_exr(dir / "default.exr");
  CHECK(read_exr(dir / "aces.exr").rgb == image.rgb);
  CHECK(slurp(dir / "srgb.png") == slurp(dir / "default.png"));
  CHECK(slurp(dir / "aces.png") != slurp(dir / "default.png"));
  // Each preview is the library's, of the view and exposure asked for.
  write_preview_png(dir / "default-again.png", image);
  CHECK(slurp(dir / "default-again.png") == slurp(dir / "default.png"));
  write_preview_png(dir / "aces-again.png", image, {aces, 1.0});
  CHECK(slurp(dir / "aces-again.png") == slurp(dir / "aces.png"));
}

TEST_CASE("cli: dacrt views lists the built-in views, or those of $OCIO, which render selects") {
  TempDir dir("cli-views");
  Run builtin = run(dir, "views", "env -u OCIO");
  CHECK(builtin.code == 0);
  CHECK(builtin.out.find("sRGB (default)\n") == 0);
  CHECK(builtin.out.find("\nACES 1.0 SDR-video (sRGB)\n") != std::string::npos);
  CHECK(lines(builtin.out) == dacrt::display_views().names.size());
  Run help = run(dir, "views --help");
  CHECK(help.code == 0);
  CHECK(help.out.find("Usage: dacrt views") == 0);

  write_text(dir / "config.ocio", ocio_test_config);
  const std::string ocio = "OCIO=" + (dir / "config.ocio");
  Run listed = run(dir, "views", ocio);
  CHECK(listed.code == 0);
  CHECK(listed.out == "Test/Gamma2 (default)\nTest/Raw\nOther/Half\n");
  Run r = run(dir,
              "render " + cornell + " --width 16 --height 12 --spp 2 --quiet -o " +
                  (dir / "half.exr") + " --preview " + (dir / "half.png") + " --view Other/Half",
              ocio);
  INFO(r.err);
  REQUIRE(r.code == 0);
  ScopedOcioEnv env((dir / "config.ocio").c_str());
  write_preview_png(dir / "half-again.png", read_exr(dir / "half.exr"), {"Other/Half"});
  CHECK(slurp(dir / "half-again.png") == slurp(dir / "half.png"));
  write_preview_png(dir / "gamma2.png", read_exr(dir / "half.exr"));
  CHECK(slurp(dir / "gamma2.png") != slurp(dir / "half.png"));
}
