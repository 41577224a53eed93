// The layers of the tree (CMakeLists.txt, DACRT_LAYERS, then bench, studies, python, apps and
// fuzz above the library): every #include "folder/…" in a folder's code names its own folder or one below it,
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

// The programs' folders: above the library, their headers included without the dacrt/ prefix.
bool program(const std::string& folder) {
  return folder == "bench" || folder == "studies" || folder == "apps" || folder == "python" || folder == "fuzz" ||
         folder == "tests";
}

// The #include "…" lines of `path` that name a folder of `order` ranked above `rank`, or that
// include the library's headers otherwise than as the installed package has them
// ("dacrt/<layer>/…": a host's own util/ or io/ is never taken for ours), or a program's with it.
std::vector<std::string> bad_includes(const fs::path& path, const std::vector<std::string>& order,
                                      size_t rank) {
  static const std::regex include(R"(^\s*#\s*include\s*"(dacrt/)?([^"/]+)/[^"]*")");
  std::vector<std::string> found;
  std::ifstream in(path);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::smatch m;
    if (!std::regex_search(line, m, include)) continue;
    const std::string folder = m[2].str(), where = path.string() + ":" + std::to_string(number);
    const auto it = std::find(order.begin(), order.end(), folder);
    if (it != order.end() && size_t(it - order.begin()) > rank)
      found.push_back(where + " includes " + m[0].str());
    if (it != order.end() && m[1].matched == program(folder))
      found.push_back(where + " includes " + m[0].str() +
                      (m[1].matched ? ": a program's header has no dacrt/ prefix"
                                    : ": the library's headers are included as \"dacrt/" +
                                          folder + "/…\""));
  }
  return found;
}

}  // namespace

TEST_CASE("layers: no folder includes a header of a folder above it, and the library's as dacrt/…") {
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
      for (std::string& u : bad_includes(entry.path(), order, rank)) upward.push_back(u);
    }
  }
  // The tests are above every layer: the prefix rule only.
  for (const auto& entry : fs::recursive_directory_iterator(root / "tests"))
    if ((entry.path().extension() == ".h" || entry.path().extension() == ".cpp") &&
        entry.path().parent_path().filename() != "consumer")  // a host's, on purpose
      for (std::string& u : bad_includes(entry.path(), order, order.size())) upward.push_back(u);
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
