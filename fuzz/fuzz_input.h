// One fuzzing input, as the fuzz target and the suite's fuzz test both treat it. A glTF (JSON, or
// GLB by its magic) is loaded, decoding the images its materials use, and what loads is traced by
// dacrt and compared with brute force (trace_check.h). Anything else is handed to the image
// decoder as a glTF image's bytes, so the fuzzer reaches PNG, JPEG and WebP decoding directly, and
// every other format must be refused by its signature.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/trace_check.h"
#include "dacrt/io/gltf.h"
#include "dacrt/io/texture_decode.h"
#include "dacrt/util/error.h"

namespace dacrt {

struct FuzzOutcome {
  enum Kind { loaded, decoded, refused } kind;
  std::string error;      // the Error's message when refused
  size_t wrong_hits = 0;  // rays where dacrt and brute disagree (loaded scenes)
};

inline bool looks_like_gltf(const uint8_t* data, size_t size) {
  size_t i = 0;
  while (i < size && (data[i] == ' ' || data[i] == '\t' || data[i] == '\n' || data[i] == '\r')) ++i;
  return (i < size && data[i] == '{') ||
         (size >= 4 && data[0] == 'g' && data[1] == 'l' && data[2] == 'T' && data[3] == 'F');
}

// `name` is the file name messages must hold; external buffers and images are looked for in a
// directory that does not exist, so they cannot be reached.
inline FuzzOutcome fuzz_input(const uint8_t* data, size_t size, const std::string& name) {
  try {
    if (!looks_like_gltf(data, size)) {
      decode_image(data, size, name);
      return {FuzzOutcome::decoded, "", 0};
    }
    const Scene scene = load_gltf_memory("/nonexistent/" + name, data, size);
    return {FuzzOutcome::loaded, "", trace_check(scene.geometry)};
  } catch (const Error& e) {
    return {FuzzOutcome::refused, e.what(), 0};
  }
}

}  // namespace dacrt
