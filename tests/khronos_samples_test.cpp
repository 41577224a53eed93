// The Khronos glTF sample assets of ../shared/khronos-samples (issue 48: one model per feature,
// each with its authors' reference screenshot) through the CLI, as a user renders them: every
// model loads, renders at time 0 with the model in the picture, and prints no warning, for a
// warning there says the render leaves out something the file uses. How the full renders compare
// with the screenshots is judged in docs/gltf.md (tools/khronos-sheet.sh makes the sheet). Skipped,
// with a message, when ../shared is absent.
#include <doctest/doctest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "dacrt/io/exr.h"

using namespace dacrt;
using namespace dacrt::test;
namespace fs = std::filesystem;

namespace {

const fs::path kSamples = DACRT_SOURCE_DIR "/../shared/khronos-samples";

std::vector<fs::path> models() {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(kSamples))
    if (e.is_regular_file() && (e.path().extension() == ".gltf" || e.path().extension() == ".glb"))
      files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// The lines of `text` that say "warning", in any case.
std::vector<std::string> warnings(const std::string& text) {
  std::vector<std::string> found;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::string lower = line;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (lower.find("warning") != std::string::npos) found.push_back(line);
  }
  return found;
}

}  // namespace

TEST_CASE("khronos samples: every model loads and renders at time 0, in view, without a warning") {
  if (!fs::is_directory(kSamples)) {
    MESSAGE("skipped: " << kSamples.string() << " does not exist");
    return;
  }
  const std::vector<fs::path> files = models();
  REQUIRE(files.size() >= 25);  // the folder's README lists twenty-five
  TempDir dir("khronos-samples");
  for (const fs::path& file : files) {
    const std::string model = fs::relative(file, kSamples).string();
    CAPTURE(model);
    // The sheet's settings (tools/khronos-sheet.sh), tiny: the file's camera or the framing one,
    // a uniform sky, the animations at time 0 (the rest pose for files without any).
    const Run r = run(dir, "render '" + file.string() + "' -o " + (dir / "model.exr") +
                               " --width 32 --height 32 --spp 1 --time 0 --environment 1,1,1" +
                               " --aov depth --quiet --threads 2");
    CHECK_MESSAGE(r.code == 0, r.err);
    for (const std::string& line : warnings(r.err + r.out)) FAIL_CHECK(line);
    if (r.code != 0) continue;
    const ExrFile image = read_exr_file(dir / "model.exr");
    CHECK(image.width == 32);
    CHECK(image.height == 32);
    size_t finite = 0, on_model = 0;
    for (const Channel& c : image.channels)
      if (c.name == "R" || c.name == "G" || c.name == "B")
        for (float v : c.values) finite += std::isfinite(v);
    CHECK(finite == 3 * 32 * 32);
    const Channel* depth = image.find("Z");
    REQUIRE(depth);
    for (float z : depth->values) on_model += z < 1e10f;  // 1e10 where nothing was hit
    CHECK_MESSAGE(on_model > 0, "the model is not in the picture");
  }
}
