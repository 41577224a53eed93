// Inputs the loader, the image decoders and the kernel must survive: every file in tests/fuzz/
// (what `make fuzz` found, and hostile files and seeds written by hand) and in fuzz/seeds-gltf/
// (the fuzzer's compressed-geometry seeds, which must load) loads or decodes or fails
// with one dacrt::Error naming the file, never crashes, and what loads traces rays with dacrt
// exactly as brute force does (fuzz/fuzz_input.h, as the fuzz target); the suite runs this under
// ASan and UBSan too. Every file in tests/fuzz-part/ is read as a part file (fuzz/part_input.h,
// as the part fuzz target reads it) and gives a film or one dacrt::Error naming the file.
#include <doctest/doctest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "../fuzz/fuzz_input.h"
#include "../fuzz/part_input.h"
#include "tests/corpus.h"
#include "tests/temp_dir.h"

TEST_CASE("the glTF loader and the image decoders survive every kept fuzzing input") {
  size_t inputs = 0, errors = 0, traced = 0, decoded = 0;
  auto check = [&](const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
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
  };
  dacrt::test::for_each_corpus_file(DACRT_SOURCE_DIR "/tests/fuzz", check);
  dacrt::test::for_each_corpus_file(DACRT_SOURCE_DIR "/fuzz/seeds-gltf", check);
  MESSAGE(inputs << " inputs, " << errors << " rejected with an error, " << traced << " traced, "
                 << decoded << " images decoded");
  CHECK(traced >= 9);   // the textured and compressed seeds and the extent past float, at least
  CHECK(decoded >= 9);  // the seed PNGs, JPEGs and WebPs
}

TEST_CASE("the part file reader survives every kept fuzzing input, and reads the seed parts") {
  const dacrt::test::TempDir dir("fuzz-part");
  size_t inputs = 0, loaded = 0;
  dacrt::test::for_each_corpus_file(
      DACRT_SOURCE_DIR "/tests/fuzz-part",
      [&](const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
        const std::string name = path.filename().string();
        INFO(name);
        ++inputs;
        // Read under its own name, so that a message naming the file names this input.
        const std::string file = dir / name;
        const dacrt::PartFuzzOutcome outcome =
            dacrt::fuzz_part_input(bytes.data(), bytes.size(), file);
        INFO(outcome.error);
        if (outcome.kind == dacrt::PartFuzzOutcome::loaded) ++loaded;
        if (outcome.kind == dacrt::PartFuzzOutcome::refused) {
          CHECK(outcome.error.find(file) != std::string::npos);
          CHECK(outcome.error.find('\n') == std::string::npos);
        }
        // Seeds are parts `dacrt render --samples` wrote (tests/fuzz-part/README.md).
        if (name.rfind("seed-", 0) == 0) CHECK(outcome.kind == dacrt::PartFuzzOutcome::loaded);
        if (name.rfind("hostile-", 0) == 0) CHECK(outcome.kind != dacrt::PartFuzzOutcome::loaded);
        CHECK(!std::filesystem::exists(file));
      });
  MESSAGE(inputs << " inputs, " << loaded << " read");
  CHECK(loaded >= 4);
}
