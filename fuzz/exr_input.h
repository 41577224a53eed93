// One fuzzing input for the EXR environment map reader, as the EXR fuzz target and the suite's
// EXR test both treat it: the bytes are read as `dacrt render --environment` reads its file
// (read_exr, then EnvironmentMap), which must give a map or one dacrt::Error naming the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <sstream>
#include <string>

#include "dacrt/io/exr.h"
#include "dacrt/scene/environment.h"
#include "dacrt/util/error.h"

namespace dacrt {

struct ExrFuzzOutcome {
  bool loaded = false;
  std::string error;  // the Error's message when refused
};

inline ExrFuzzOutcome fuzz_exr_input(const uint8_t* data, size_t size, const std::string& name) {
  try {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    const EnvironmentMap map(read_exr(in, name), name);
    const EnvironmentMap::Sample s = map.sample(glm::vec4(0.25f, 0.5f, 0.5f, 0.5f));
    (void)map.pdf(s.direction);
    return {true, ""};
  } catch (const Error& e) {
    return {false, e.what()};
  }
}

}  // namespace dacrt
