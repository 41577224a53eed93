// libFuzzer target for the glTF loader, the image decoders and the kernel (`make fuzz`): any
// input must load (or decode) or fail with one dacrt::Error, and what loads is traced by dacrt
// and compared with brute force (fuzz_input.h); a crash, a sanitizer report, a leak, a hang or a
// wrong hit is a finding. Findings are kept as regression inputs in tests/fuzz/, which the test
// suite runs through the same function under the sanitizers.
#include <cstdio>
#include <cstdlib>

#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const dacrt::FuzzOutcome outcome = dacrt::fuzz_input(data, size, "fuzz.gltf");
  if (outcome.wrong_hits > 0) {
    std::fprintf(stderr, "dacrt and brute disagree on %zu rays\n", outcome.wrong_hits);
    std::abort();
  }
  return 0;
}
