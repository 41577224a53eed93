// The suite's own contract with ctest: doctest_discover_tests (CMakeLists.txt) makes one ctest
// entry per TEST_CASE, named by the case, and runs it as `dacrt-tests --test-case=NAME`. A ';' in
// a name is CMake's list separator: the case became two entries, each matching no case, so it
// never ran under ctest (22 cases did not, until this test).
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

TEST_CASE("test names: no TEST_CASE name holds a semicolon, which ctest splits into two that run nothing") {
  const std::regex name(R"re(TEST_CASE\(\s*"((?:[^"\\]|\\.)*)")re");
  size_t cases = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(DACRT_SOURCE_DIR) / "tests")) {
    if (entry.path().extension() != ".cpp") continue;
    std::ifstream in(entry.path());
    std::stringstream text;
    text << in.rdbuf();
    const std::string source = text.str();
    for (std::sregex_iterator it(source.begin(), source.end(), name), end; it != end; ++it) {
      const std::string n = (*it)[1].str();
      ++cases;
      CHECK_MESSAGE(n.find(';') == std::string::npos,
                    entry.path().filename().string() << ": \"" << n << "\"");
    }
  }
  CHECK(cases > 400);
}
