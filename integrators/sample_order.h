// SampleOrder: the order in which a render call's camera samples start. Samples [first, last) of
// every pixel are taken a group of pixels at a time, all of the call's samples of the group
// before the next. In textured scenes a group is 64 pixels, in 8 × 8 tiles (tiles in rows, pixels
// in rows inside each): a pixel's samples run close together in time, and on the DamagedHelmet
// at 384², where each pixel covers about 7 × 7 texels of its 2048² textures, its samples read
// them again while they are in the cache instead of once per wavefront (32 spp, sky sampled:
// render 0.90×; sponza inside 0.99×). Elsewhere a group is the whole image (sample by sample, in
// rows): the Cornell box measured 1.04× in tiles. Which samples a pixel gets never depends on
// the order; only when a stop cuts a call short do some groups have all of its samples and
// others none.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace dacrt {

struct SampleOrder {
  static constexpr uint32_t tile = 8;                   // pixels on a tile's side
  static constexpr uint64_t tiled_group = uint64_t(tile) * tile;

  uint64_t pixels = 0;              // in the call
  uint32_t first = 0, samples = 0;  // the call's sample indices: [first, first + samples)
  uint64_t group = tiled_group;     // pixels whose samples go together

  // The k-th sample of the call: the index of its pixel in the call's pixel order (tiled()) and
  // its sample index.
  std::pair<uint64_t, uint32_t> at(uint64_t k) const;

  // at(k), at(k + 1)… without a division per sample (camera ray generation's loop).
  class Cursor {
   public:
    Cursor(const SampleOrder& order, uint64_t k) : order_(order) {
      const uint64_t per_group = order.group * order.samples;
      base_ = k / per_group * order.group;
      const uint64_t r = k % per_group;
      size_ = std::min(order.group, order.pixels - base_);
      column_ = r % size_, row_ = uint32_t(r / size_);
    }
    std::pair<uint64_t, uint32_t> operator*() const {
      return {base_ + column_, order_.first + row_};
    }
    Cursor& operator++() {
      if (++column_ < size_) return *this;
      column_ = 0;
      if (++row_ < order_.samples) return *this;
      row_ = 0, base_ += order_.group;
      size_ = std::min(order_.group, order_.pixels - std::min(order_.pixels, base_));
      return *this;
    }

   private:
    const SampleOrder& order_;
    uint64_t base_, size_, column_;  // the group's first pixel, its pixels, the pixel in it
    uint32_t row_;                   // the sample in the call
  };

  // After the first `taken` samples of the call: the fewest and the most of its samples any
  // pixel has.
  std::pair<uint32_t, uint32_t> counts(uint64_t taken) const {
    if (pixels == 0 || taken >= pixels * samples) return {samples, samples};
    const uint64_t per_group = group * samples, g = taken / per_group, r = taken % per_group;
    const uint64_t size = std::min(group, pixels - g * group);
    const uint32_t low = uint32_t(r / size), high = low + (r % size ? 1 : 0);
    const bool last_group = g * group + size == pixels;
    return {last_group ? low : 0, g > 0 ? samples : high};
  }

  // The pixels of a width × height image by tiles: 8 × 8 tiles in rows, rows inside each.
  static std::vector<uint32_t> tiled(uint32_t width, uint32_t height) {
    std::vector<uint32_t> order;
    order.reserve(size_t(width) * height);
    for (uint32_t ty = 0; ty < height; ty += tile)
      for (uint32_t tx = 0; tx < width; tx += tile)
        for (uint32_t y = ty; y < std::min(height, ty + tile); ++y)
          for (uint32_t x = tx; x < std::min(width, tx + tile); ++x) order.push_back(y * width + x);
    return order;
  }
};

inline std::pair<uint64_t, uint32_t> SampleOrder::at(uint64_t k) const { return *Cursor(*this, k); }

}  // namespace dacrt
