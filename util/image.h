// Image: a float RGB raster in scene-linear Rec.709, row-major from the top-left pixel,
// channels interleaved. What the film resolves to and what the writers read.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace dacrt {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;  // 3 * width * height

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(size_t(3) * w * h, 0.f) {}
  float* pixel(int x, int y) { return &rgb[3 * (size_t(y) * width + x)]; }
  const float* pixel(int x, int y) const { return &rgb[3 * (size_t(y) * width + x)]; }
};

// One named channel of a raster ("R", "albedo.R", "N.X", "Z"…), one float per pixel, row-major
// from the top-left pixel: what multi-layer EXR files are made of.
struct Channel {
  std::string name;
  std::vector<float> values;
};

}  // namespace dacrt
