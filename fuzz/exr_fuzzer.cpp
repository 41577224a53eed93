// libFuzzer target for the EXR environment map reader (`make fuzz`): any input must give a map or
// fail with one dacrt::Error (fuzz/exr_input.h); a crash, a sanitizer report, a leak, an
// allocation past -rss_limit_mb or a hang is a finding. Findings are kept as regression inputs in
// tests/fuzz-exr/, which the suite runs through the same function under the sanitizers.
#include "fuzz/exr_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)dacrt::fuzz_exr_input(data, size, "fuzz.exr");
  return 0;
}
