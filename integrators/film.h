// Film: per-pixel sums of radiance samples (and of their squares, for error estimates).
// Samples that are not finite are dropped and counted, never averaged in.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "io/image.h"

namespace dacrt {

class Film {
 public:
  Film(int width, int height)
      : width_(width),
        height_(height),
        sum_(size_t(3) * width * height, 0.0),
        sum_sq_(size_t(width) * height, 0.0),
        count_(size_t(width) * height, 0) {}

  int width() const { return width_; }
  int height() const { return height_; }
  size_t pixels() const { return count_.size(); }

  void add(size_t pixel, const glm::vec3& radiance) {
    if (!std::isfinite(radiance.x) || !std::isfinite(radiance.y) || !std::isfinite(radiance.z)) {
      ++dropped_;
      return;
    }
    for (int c = 0; c < 3; ++c) sum_[3 * pixel + c] += radiance[c];
    double m = (double(radiance.x) + radiance.y + radiance.z) / 3.0;
    sum_sq_[pixel] += m * m;
    ++count_[pixel];
  }

  uint64_t dropped() const { return dropped_; }
  uint32_t count(size_t pixel) const { return count_[pixel]; }

  // The per-pixel mean.
  Image resolve() const {
    Image img(width_, height_);
    for (size_t p = 0; p < pixels(); ++p)
      for (int c = 0; c < 3; ++c)
        img.rgb[3 * p + c] = count_[p] ? float(sum_[3 * p + c] / count_[p]) : 0.f;
    return img;
  }

  // Mean and standard error of the mean of a pixel's channel average (R+G+B)/3.
  glm::dvec2 mean_and_error(size_t pixel) const {
    double n = count_[pixel];
    if (n < 1) return {0.0, 0.0};
    double mean = (sum_[3 * pixel] + sum_[3 * pixel + 1] + sum_[3 * pixel + 2]) / (3.0 * n);
    double var = n > 1 ? std::max(0.0, (sum_sq_[pixel] - n * mean * mean) / (n - 1)) : 0.0;
    return {mean, std::sqrt(var / n)};
  }

 private:
  int width_, height_;
  std::vector<double> sum_, sum_sq_;
  std::vector<uint32_t> count_;
  uint64_t dropped_ = 0;
};

}  // namespace dacrt
