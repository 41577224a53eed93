// Inputs the loader and the kernel must survive: every file in tests/fuzz/ (what `make fuzz`
// found, and a few hostile files written by hand) loads or fails with one dacrt::Error naming the
// file, never crashes, and what loads traces rays with dacrt exactly as brute force does
// (fuzz/trace_check.h); the suite runs this under ASan and UBSan too.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "../fuzz/trace_check.h"
#include "io/gltf.h"
#include "util/error.h"

TEST_CASE("the glTF loader survives every kept fuzzing input") {
  const std::filesystem::path dir = DACRT_SOURCE_DIR "/tests/fuzz";
  size_t inputs = 0, errors = 0, traced = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (!entry.is_regular_file() || entry.path().filename() == "README.md") continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                           std::istreambuf_iterator<char>());
    INFO(entry.path().filename().string());
    ++inputs;
    try {
      const dacrt::Scene scene = dacrt::load_gltf_memory(
          "/nonexistent/" + entry.path().filename().string(), bytes.data(), bytes.size());
      CHECK(dacrt::trace_check(scene.geometry) == 0);
      ++traced;
    } catch (const dacrt::Error& e) {
      ++errors;
      CHECK(std::string(e.what()).find(entry.path().filename().string()) != std::string::npos);
    }
  }
  MESSAGE(inputs << " inputs, " << errors << " rejected with an error, " << traced << " traced");
  CHECK(inputs > 0);
  CHECK(traced >= 2);  // the textured seed and the extent past float, at least
}
