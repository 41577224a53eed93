// The layers of the tree (CMakeLists.txt, DACRT_LAYERS, then bench, apps and fuzz above the
// library): every #include "folder/…" in a folder's code names its own folder or one below it,
// so no two folders depend on each other both ways. A new back-arrow fails here, naming the file,
// the line and the header.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::vector<std::string> layers() {
  std::vector<std::string> out;
  std::istringstream in(DACRT_LAYER_ORDER);
  for (std::string layer; std::getline(in, layer, ',');) out.push_back(layer);
  return out;
}

// The #include "…" lines of `path` that name a folder of `order` ranked above `rank`.
std::vector<std::string> upward_includes(const fs::path& path, const std::vector<std::string>& order,
                                         size_t rank) {
  static const std::regex include(R"(^\s*#\s*include\s*"([^"/]+)/[^"]*")");
  std::vector<std::string> found;
  std::ifstream in(path);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::smatch m;
    if (!std::regex_search(line, m, include)) continue;
    const auto it = std::find(order.begin(), order.end(), m[1].str());
    if (it != order.end() && size_t(it - order.begin()) > rank)
      found.push_back(path.string() + ":" + std::to_string(number) + " includes " + m[0].str());
  }
  return found;
}

}  // namespace

TEST_CASE("layers: no folder includes a header of a folder above it") {
  const fs::path root = DACRT_SOURCE_DIR;
  const std::vector<std::string> order = layers();
  REQUIRE(order.size() >= 8);
  size_t files = 0;
  std::vector<std::string> upward;
  for (size_t rank = 0; rank < order.size(); ++rank) {
    REQUIRE_MESSAGE(fs::is_directory(root / order[rank]), order[rank]);
    for (const auto& entry : fs::recursive_directory_iterator(root / order[rank])) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp")) continue;
      ++files;
      for (std::string& u : upward_includes(entry.path(), order, rank)) upward.push_back(u);
    }
  }
  MESSAGE(files << " files in " << order.size() << " layers");
  CHECK(files > 100);
  for (const std::string& u : upward) CHECK_MESSAGE(false, u);
}

TEST_CASE("layers: every folder of C++ code is a layer, or the tests") {
  const fs::path root = DACRT_SOURCE_DIR;
  const std::vector<std::string> order = layers();
  for (const auto& entry : fs::directory_iterator(root)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_directory() || name.starts_with(".") || name.starts_with("build") ||
        name == "tests")
      continue;
    bool code = false;
    for (const auto& f : fs::recursive_directory_iterator(entry.path())) {
      const std::string ext = f.path().extension().string();
      code = code || ext == ".h" || ext == ".cpp";
    }
    if (code)
      CHECK_MESSAGE(std::find(order.begin(), order.end(), name) != order.end(),
                    name << "/ holds C++ code but is not in DACRT_LAYERS (CMakeLists.txt)");
  }
}
