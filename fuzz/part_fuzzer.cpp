// libFuzzer target for the reader of part files (`make fuzz`): any input, read as `dacrt merge`
// and `render --resume` read a part (fuzz/part_input.h), must give a film or fail with one
// dacrt::Error; a crash, a sanitizer report, a leak, an allocation past -rss_limit_mb or a hang
// is a finding. Findings are kept as regression inputs in tests/fuzz-part/, which the suite runs
// through the same function under the sanitizers.
#include <unistd.h>

#include <filesystem>
#include <string>

#include "fuzz/part_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The part reader takes a path: one file per process, so that fuzzers run side by side (-jobs)
  // do not read each other's inputs.
  static const std::string path = (std::filesystem::temp_directory_path() /
                                   ("dacrt-part-fuzz-" + std::to_string(getpid()) + ".exr"))
                                      .string();
  (void)dacrt::fuzz_part_input(data, size, path);
  return 0;
}
