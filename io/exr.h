// OpenEXR output: float RGB, scene-linear Rec.709 primaries, with render metadata in the header.
// Written to a temporary name beside the target and renamed, so no half-written file is left.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "io/image.h"

namespace dacrt {

struct ExrMetadata {
  int spp = 0;
  std::string backend;
  std::string integrator;
  double render_seconds = 0.0;
  std::vector<std::pair<std::string, std::string>> extra;  // more string attributes
};

void write_exr(const std::string& path, const Image& image, const ExrMetadata& metadata);
Image read_exr(const std::string& path);  // RGB channels as float (tests, comparisons)

}  // namespace dacrt
