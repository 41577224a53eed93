// libFuzzer target for the glTF loader and the kernel (`make fuzz`): any input must either load or
// fail with one dacrt::Error, and what loads is traced by dacrt and compared with brute force
// (trace_check.h); a crash, a sanitizer report, a leak, a hang or a wrong hit is a finding.
// Findings are kept as regression inputs in tests/fuzz/, which the test suite loads under the
// sanitizers.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "fuzz/trace_check.h"
#include "io/gltf.h"
#include "util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    // A directory that does not exist: external buffers and images cannot be reached.
    dacrt::Scene scene = dacrt::load_gltf_memory("/nonexistent/fuzz.gltf", data, size);
    if (const size_t wrong = dacrt::trace_check(scene.geometry)) {
      std::fprintf(stderr, "dacrt and brute disagree on %zu rays\n", wrong);
      std::abort();
    }
  } catch (const dacrt::Error&) {
  }
  return 0;
}
