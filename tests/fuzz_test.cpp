// Inputs the loader, the image decoders and the kernel must survive: every file in tests/fuzz/
// (what `make fuzz` found, and hostile files and seeds written by hand) loads or decodes or fails
// with one dacrt::Error naming the file, never crashes, and what loads traces rays with dacrt
// exactly as brute force does (fuzz/fuzz_input.h, as the fuzz target); the suite runs this under
// ASan and UBSan too.
#include <doctest/doctest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "../fuzz/fuzz_input.h"
#include "tests/corpus.h"

TEST_CASE("the glTF loader and the image decoders survive every kept fuzzing input") {
  const std::filesystem::path dir = DACRT_SOURCE_DIR "/tests/fuzz";
  size_t inputs = 0, errors = 0, traced = 0, decoded = 0;
  dacrt::test::for_each_corpus_file(dir, [&](const std::filesystem::path& path,
                                             const std::vector<unsigned char>& bytes) {
    const std::string name = path.filename().string();
    INFO(name);
    ++inputs;
    const dacrt::FuzzOutcome outcome = dacrt::fuzz_input(bytes.data(), bytes.size(), name);
    switch (outcome.kind) {
      case dacrt::FuzzOutcome::loaded:
        CHECK(outcome.wrong_hits == 0);
        ++traced;
        break;
      case dacrt::FuzzOutcome::decoded:
        ++decoded;
        break;
      case dacrt::FuzzOutcome::refused:
        ++errors;
        CHECK(outcome.error.find(name) != std::string::npos);
        CHECK(outcome.error.find('\n') == std::string::npos);
        break;
    }
    // A hostile image (hostile-*.hdr, .pgm…) must be refused; a seed image must decode.
    const std::string ext = path.extension().string();
    if (name.rfind("hostile-", 0) == 0 && ext != ".gltf" && ext != ".glb")
      CHECK(outcome.kind == dacrt::FuzzOutcome::refused);
    if (name.rfind("seed-", 0) == 0 && (ext == ".png" || ext == ".jpg" || ext == ".webp"))
      CHECK(outcome.kind == dacrt::FuzzOutcome::decoded);
    if (name.rfind("seed-", 0) == 0 && (ext == ".gltf" || ext == ".glb"))
      CHECK(outcome.kind == dacrt::FuzzOutcome::loaded);
  });
  MESSAGE(inputs << " inputs, " << errors << " rejected with an error, " << traced << " traced, "
                 << decoded << " images decoded");
  CHECK(traced >= 3);   // the textured seeds and the extent past float, at least
  CHECK(decoded >= 9);  // the seed PNGs, JPEGs and WebPs
}
