// Film: per-pixel sums of radiance samples (and of their squares, for error estimates).
// Samples that are not finite are dropped and counted, never averaged in.
#pragma once

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
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

  // The bytes a film of this size holds (its sums and counts).
  static uint64_t bytes(int width, int height) {
    return uint64_t(width) * uint64_t(height) * (4 * sizeof(double) + sizeof(uint32_t));
  }

  int width() const { return width_; }
  int height() const { return height_; }
  size_t pixels() const { return count_.size(); }

  void add(size_t pixel, const glm::vec3& radiance) { dropped_ += !accumulate(pixel, radiance); }

  // add(pixel_of(i), radiance_of(i)) for i in [0, n), in parallel, and with every pixel's samples
  // added in the order of i, so the sums are the same bit for bit for any number of threads. The
  // samples are sorted into ranges of pixels (a counting sort, stable), one task per range.
  template <class PixelOf, class RadianceOf>
  void add_in_order(size_t n, PixelOf pixel_of, RadianceOf radiance_of) {
    constexpr size_t block = 8192;
    const size_t ranges = std::clamp<size_t>(pixels() / 64, 1, 1024);
    const size_t blocks = (n + block - 1) / block;
    auto range_of = [&](size_t i) { return size_t(uint64_t(pixel_of(i)) * ranges / pixels()); };
    // start[r * blocks + b]: where block b's samples of range r go.
    std::vector<uint32_t>& start = start_;
    start.assign(ranges * blocks + 1, 0);
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
      for (size_t i = b * block, end = std::min(n, (b + 1) * block); i < end; ++i)
        ++start[range_of(i) * blocks + b + 1];
    });
    for (size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
    order_.resize(n);
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
      std::vector<uint32_t> next(ranges);
      for (size_t r = 0; r < ranges; ++r) next[r] = start[r * blocks + b];
      for (size_t i = b * block, end = std::min(n, (b + 1) * block); i < end; ++i)
        order_[next[range_of(i)]++] = uint32_t(i);
    });
    std::atomic<uint64_t> dropped{0};
    tbb::parallel_for(size_t(0), ranges, [&](size_t r) {
      uint64_t own = 0;
      for (uint32_t k = start[r * blocks], end = start[(r + 1) * blocks]; k < end; ++k) {
        const size_t i = order_[k];
        own += !accumulate(pixel_of(i), radiance_of(i));
      }
      dropped += own;
    });
    dropped_ += dropped;
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
  // False (and nothing added) for a sample that is not finite.
  bool accumulate(size_t pixel, const glm::vec3& radiance) {
    if (!std::isfinite(radiance.x) || !std::isfinite(radiance.y) || !std::isfinite(radiance.z))
      return false;
    for (int c = 0; c < 3; ++c) sum_[3 * pixel + c] += radiance[c];
    double m = (double(radiance.x) + radiance.y + radiance.z) / 3.0;
    sum_sq_[pixel] += m * m;
    ++count_[pixel];
    return true;
  }

  int width_, height_;
  std::vector<uint32_t> order_, start_;  // add_in_order's scratch
  std::vector<double> sum_, sum_sq_;
  std::vector<uint32_t> count_;
  uint64_t dropped_ = 0;
};

}  // namespace dacrt
