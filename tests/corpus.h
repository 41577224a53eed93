// The files of a kept fuzzing corpus (tests/fuzz/, tests/fuzz-exr/, tests/fuzz-part/,
// fuzz/seeds-gltf/), read whole, for the tests that
// run each through the fuzz target's function.
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace dacrt::test {

// Calls visit(path, bytes) for every regular file in `dir` except Markdown notes (README.md).
template <class Visit>
void for_each_corpus_file(const std::filesystem::path& dir, Visit&& visit) {
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (!entry.is_regular_file() || entry.path().extension() == ".md") continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                           std::istreambuf_iterator<char>());
    visit(entry.path(), bytes);
  }
}

}  // namespace dacrt::test
