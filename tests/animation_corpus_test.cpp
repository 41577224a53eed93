// The Khronos glTF-Validator's animation, skin and morph cases (../shared/gltf-validator-tests/
// base/data/{animation,animation_data,skin,mesh}, each with the validator's .report.json): every
// valid file (numErrors 0) loads and poses at several times without a crash or a non-finite
// vertex, and every file the validator finds errors in under animation/, animation_data/ and
// skin/ is refused, naming the element, except the few whose errors posing does not depend on
// (listed, with why). Skipped with a message where the corpus is absent (CI).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "dacrt/io/gltf.h"
#include "dacrt/util/error.h"

using namespace dacrt;
namespace fs = std::filesystem;

namespace {

const fs::path kCorpus = fs::path(DACRT_SOURCE_DIR) / "../shared/gltf-validator-tests/base/data";

nlohmann::json report_of(const fs::path& gltf) {
  std::ifstream in(gltf.string() + ".report.json");
  return nlohmann::json::parse(in);
}

// Files with validator errors that render as the spec says all the same: the errors are about
// what posing does not read (input bounds, the skeleton property, where joints sit in the tree).
const std::set<std::string> kAcceptedDespiteErrors = {
    "animation/sampler_input_no_bounds.gltf",  // min/max of the times: informative
    "skin/no_common_root.gltf",                // joints posed by their own world transforms
    "skin/no_joints_in_scene.gltf",            // the same, from their own parent chains
    "skin/skeleton_invalid.gltf",              // `skeleton` is informative
};

// Valid files refused by design: their sampler inputs have no bufferView, so their times are
// zeros (the spec), which do not increase; the validator does not check data it does not have.
bool dataless_times(const fs::path& gltf) {
  std::ifstream in(gltf);
  const nlohmann::json doc = nlohmann::json::parse(in);
  if (!doc.contains("animations")) return false;
  for (const auto& a : doc["animations"])
    for (const auto& s : a.value("samplers", nlohmann::json::array())) {
      const auto& acc = doc["accessors"][s["input"].get<size_t>()];
      if (!acc.contains("bufferView") && acc["count"].get<int>() > 1) return true;
    }
  return false;
}

void check_posable(const std::string& path, const GltfAnimation& file, Scene& scene) {
  for (double t : {0.0, 0.3, 0.5, 1.0, 2.75, 100.0}) {
    file.pose(t, scene);
    for (size_t i = 0; i < scene.geometry.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 v = scene.geometry.vertex(i, k);
        INFO(path << " t = " << t << " triangle " << i);
        REQUIRE((std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)));
      }
    for (const glm::vec3& n : scene.normals)
      REQUIRE((std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z)));
  }
}

}  // namespace

TEST_CASE("glTF-Validator corpus: animations, skins and morph targets") {
  if (!fs::is_directory(kCorpus)) {
    MESSAGE("skipped: the glTF-Validator corpus is not at " << kCorpus.string());
    return;
  }
  size_t loaded = 0, refused = 0, dataless = 0;
  for (const char* dir : {"animation", "animation_data", "skin", "mesh"}) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(kCorpus / dir))
      if (e.path().extension() == ".gltf" && fs::exists(e.path().string() + ".report.json"))
        files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& path : files) {
      const std::string name = std::string(dir) + "/" + path.filename().string();
      INFO(name);
      const nlohmann::json report = report_of(path);
      const int errors = report["issues"]["numErrors"].get<int>();
      const bool must_load =
          errors == 0 ? !dataless_times(path) : kAcceptedDespiteErrors.count(name) > 0;
      if (errors == 0 && !must_load) ++dataless;
      try {
        const GltfAnimation file(path.string(), GltfOptions{});
        Scene scene = file.load();
        if (errors > 0 && std::string(dir) == "mesh") {
          continue;  // mesh/ errors are the general corpus test's (tests/gltf_validator_*)
        }
        CHECK_MESSAGE(must_load, name << " loaded despite " << errors << " validator errors");
        check_posable(path.string(), file, scene);
        ++loaded;
      } catch (const Error& e) {
        const std::string what = e.what();
        INFO(what);
        CHECK(what.find('\n') == std::string::npos);
        CHECK(what.rfind(path.string() + ": ", 0) == 0);
        if (std::string(dir) == "mesh" && errors > 0) continue;
        CHECK_MESSAGE(!must_load, name << " was refused");
        // The element named: an animation's or skin's (as the loader or the schema writes it),
        // or the buffer its data would come from (the file has none).
        const bool named = what.find("animations[") != std::string::npos ||
                           what.find("/animations") != std::string::npos ||
                           what.find("skins[") != std::string::npos ||
                           what.find("/skins") != std::string::npos ||
                           what.find("buffer 0 cannot be read") != std::string::npos ||
                           what.find("AnimationChannel") != std::string::npos;
        CHECK(named);
        ++refused;
      }
    }
  }
  MESSAGE(loaded << " posed, " << refused << " refused (" << dataless
                 << " valid with data-less times)");
  CHECK(loaded >= 8);
  CHECK(refused >= 20);
}
