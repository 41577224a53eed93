// Every scene we ship (scenes/) and every real one of ../shared renders with its defaults to a
// picture that is not black (issue 50): the default sky stays beside glowing emitters and the
// file's punctual lights, and only scenes with lamps brighter than the sky (the Cornell boxes,
// EmissiveStrengthTest: KHR_materials_emissive_strength) are lit by their own emitters alone,
// dimmer by design. ../shared's scenes are skipped, with a message, when it is absent. A render
// made black on purpose gets the one line that says so, with the option that changes it.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "cli.h"
#include "dacrt/io/exr.h"

using namespace dacrt;
using namespace dacrt::test;
namespace fs = std::filesystem;

namespace {

// Every glTF file under `root`, but the compressed and embedded copies of a model the folder
// also holds plainly (the Khronos samples' glTF-Draco, glTF-Meshopt…: the same picture).
std::vector<fs::path> scenes_under(const fs::path& root) {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    const std::string ext = e.path().extension().string(), dir = e.path().parent_path().string();
    if (!e.is_regular_file() || (ext != ".gltf" && ext != ".glb")) continue;
    if (dir.find("glTF-") != std::string::npos && dir.find("glTF-Binary") == std::string::npos)
      continue;
    files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The mean of R, G and B over the image.
double mean_rgb(const ExrFile& image) {
  double sum = 0.0;
  size_t n = 0;
  for (const Channel& c : image.channels)
    if (c.name == "R" || c.name == "G" || c.name == "B")
      for (float v : c.values) sum += double(v), ++n;
  return n ? sum / double(n) : 0.0;
}

// Renders `file` with its defaults, tiny; checks the lighting `dacrt info` names agrees with the
// render's note and that the picture is lit: a mean over 0.25 under the sky, over 0.02 (the
// Cornell box's dark outside and unlit ceiling) under the scene's own lamps.
void check_lit(const TempDir& dir, const fs::path& file, const std::set<std::string>& own) {
  const std::string name = file.filename().string();
  CAPTURE(name);
  const Run info = run(dir, "info '" + file.string() + "'");
  REQUIRE_MESSAGE(info.code == 0, info.err);
  const bool self_lit = info.out.find("lighting   its own: ") != std::string::npos;
  CHECK(self_lit == (own.count(name) > 0));
  CHECK(self_lit != (info.out.find("lighting   a uniform sky of 1") != std::string::npos));
  const Run r = run(dir, "render '" + file.string() + "' -o " + (dir / "lit.exr") +
                             " --width 24 --height 24 --spp 2 --threads 2");
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(r.err.find("nearly black") == std::string::npos);
  CHECK((r.err.find("lighting it with a uniform sky of 1") != std::string::npos) == !self_lit);
  const double mean = mean_rgb(read_exr_file(dir / "lit.exr"));
  CHECK(mean > (self_lit ? 0.02 : 0.25));
}

}  // namespace

TEST_CASE("default lighting: every scene of scenes/ renders lit, the Cornell boxes by their own lamp") {
  TempDir dir("default-lighting");
  const std::vector<fs::path> files = scenes_under(DACRT_SOURCE_DIR "/scenes");
  REQUIRE(files.size() >= 2);
  for (const fs::path& file : files)
    check_lit(dir, file, {"cornell-box.gltf", "cornell-box-lambert.gltf"});
}

TEST_CASE("default lighting: every scene of ../shared renders lit with its defaults") {
  const fs::path shared = DACRT_SOURCE_DIR "/../shared";
  if (!fs::is_directory(shared / "scenes") || !fs::is_directory(shared / "khronos-samples")) {
    MESSAGE("skipped: " << shared.string() << " has no scenes/ and khronos-samples/");
    return;
  }
  TempDir dir("default-lighting-shared");
  std::vector<fs::path> files = scenes_under(shared / "scenes");
  const std::vector<fs::path> samples = scenes_under(shared / "khronos-samples");
  files.insert(files.end(), samples.begin(), samples.end());
  REQUIRE(files.size() >= 48);  // 23 scenes, 25 samples
  // Lit by lamps brighter than the sky, by design; DamagedHelmet, ToyCar, WaterBottle and three
  // samples glow beside the sky (they were 98–99 % black without it).
  for (const fs::path& file : files)
    check_lit(dir, file, {"CornellBox-Original.glb", "EmissiveStrengthTest.glb"});
}

TEST_CASE("default lighting: a nearly black render says so, with the option that changes it") {
  TempDir dir("dark-render");
  const std::string box = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";
  const std::string args = " -o " + (dir / "dark.exr") + " --width 16 --height 16 --spp 1";
  // Lit by its lamp only, seen at -20 stops: the sky is the option.
  Run r = run(dir, "render " + box + args + " --exposure -20 --preview " + (dir / "dark.png"));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(r.err.find(dir / "dark.exr" + ": the image is nearly black") != std::string::npos);
  CHECK(r.err.find("no sky lights it; --environment 1,1,1 adds one") != std::string::npos);
  r = run(dir, "render " + box + args);  // the lamp lights it
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(r.err.find("nearly black") == std::string::npos);
  // Under a sky: the exposure is the option.
  r = run(dir, "render " + box + args + " --environment 1,1,1 --exposure -20 --preview " +
                   (dir / "dark.png"));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(r.err.find("nearly black") != std::string::npos);
  CHECK(r.err.find("--exposure STOPS brightens its preview") != std::string::npos);
  CHECK(r.err.find("--environment 1,1,1 adds") == std::string::npos);
  // --quiet: nothing.
  r = run(dir, "render " + box + args + " --exposure -20 --preview " + (dir / "dark.png") +
                   " --quiet");
  CHECK(r.err.empty());
}
