// Inputs the loader must survive: every file in tests/fuzz/ (what `make fuzz` found, and a few
// hostile files written by hand) loads or fails with one dacrt::Error naming the file, never
// crashes; the suite runs this under ASan and UBSan too.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "io/gltf.h"
#include "util/error.h"

TEST_CASE("the glTF loader survives every kept fuzzing input") {
  const std::filesystem::path dir = DACRT_SOURCE_DIR "/tests/fuzz";
  size_t inputs = 0, errors = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (!entry.is_regular_file() || entry.path().filename() == "README.md") continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                           std::istreambuf_iterator<char>());
    INFO(entry.path().filename().string());
    ++inputs;
    try {
      dacrt::load_gltf_memory("/nonexistent/" + entry.path().filename().string(), bytes.data(),
                              bytes.size());
    } catch (const dacrt::Error& e) {
      ++errors;
      CHECK(std::string(e.what()).find(entry.path().filename().string()) != std::string::npos);
    }
  }
  MESSAGE(inputs << " inputs, " << errors << " rejected with an error");
  CHECK(inputs > 0);
}
