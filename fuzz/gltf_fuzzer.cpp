// libFuzzer target for the glTF loader (`make fuzz`): any input must either load or fail with
// one dacrt::Error; a crash, a sanitizer report, a leak or a hang is a finding. Findings are kept
// as regression inputs in tests/fuzz/, which the test suite loads under the sanitizers.
#include <cstddef>
#include <cstdint>

#include "io/gltf.h"
#include "util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    // A directory that does not exist: external buffers and images cannot be reached.
    dacrt::Scene scene = dacrt::load_gltf_memory("/nonexistent/fuzz.gltf", data, size);
    (void)scene;
  } catch (const dacrt::Error&) {
  }
  return 0;
}
