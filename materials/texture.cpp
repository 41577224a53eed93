#include "dacrt/materials/texture.h"

#include <array>
#include <cmath>

namespace dacrt {
namespace {

// An 8-bit value's float, v / 255, and its sRGB decoding: each texel read is table lookups, no
// division (the same floats: the tables hold what the divisions give).
constexpr std::array<float, 256> unorm8 = [] {
  std::array<float, 256> t{};
  for (int i = 0; i < 256; ++i) t[size_t(i)] = float(i) / 255.f;
  return t;
}();
// (Filled before main; nothing samples a texture during static initialisation.)
const std::array<float, 256> srgb8 = [] {
  std::array<float, 256> t{};
  for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_to_linear(float(i) / 255.f);
  return t;
}();

// Texel i / 4 of an 8-bit image, its colour through `rgb` (unorm8 or srgb8).
inline glm::vec4 texel8(const uint8_t* rgba, size_t i, const float* rgb) {
  const uint8_t* p = rgba + i;
  return {rgb[p[0]], rgb[p[1]], rgb[p[2]], unorm8[p[3]]};
}

// Reduces a texture coordinate (in texels, already wrapped into a small range) to a texel index.
int wrap_index(int i, int n, Wrap mode) {
  if (unsigned(i) < unsigned(n)) return i;  // inside: every mode keeps it (no division)
  switch (mode) {
    case Wrap::clamp:
      return i < 0 ? 0 : (i >= n ? n - 1 : i);
    case Wrap::repeat:
      i %= n;
      return i < 0 ? i + n : i;
    case Wrap::mirror: {
      int period = 2 * n;
      i %= period;
      if (i < 0) i += period;
      return i < n ? i : period - 1 - i;
    }
  }
  return 0;
}

// Brings a coordinate into a range where texel arithmetic cannot overflow, without changing what
// it samples: one period for repeat, two for mirror; clamp only needs [-1, 2].
float reduce(float x, Wrap mode) {
  if (!std::isfinite(x)) return 0.f;
  switch (mode) {
    case Wrap::clamp:
      return x < -1.f ? -1.f : (x > 2.f ? 2.f : x);
    case Wrap::repeat:
      return x - std::floor(x);
    case Wrap::mirror:
      return x - 2.f * std::floor(0.5f * x);
  }
  return 0.f;
}

}  // namespace

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

glm::vec4 TextureImage::texel(int x, int y, bool srgb) const {
  const size_t i = 4 * (size_t(y) * size_t(width) + size_t(x));
  if (!rgba8.empty()) return texel8(rgba8.data(), i, srgb ? srgb8.data() : unorm8.data());
  const uint16_t* p = &rgba16[i];
  glm::vec4 c = glm::vec4(p[0], p[1], p[2], p[3]) / 65535.f;
  if (srgb) c = {srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b), c.a};
  return c;
}

namespace {

// The texels sample() reads at uv: columns xa, xb of rows ya, yb, weighed by (tx, ty); one texel
// (xa, ya) for a NEAREST texture.
struct Footprint {
  int xa, xb, ya, yb;
  float tx, ty;
};
Footprint footprint(const TextureImage& image, const Texture& texture, glm::vec2 uv) {
  const int w = image.width, h = image.height;
  const float x = reduce(uv.x, texture.wrap_s) * float(w);
  const float y = reduce(uv.y, texture.wrap_t) * float(h);
  if (texture.nearest) {
    const int xa = wrap_index(int(std::floor(x)), w, texture.wrap_s);
    const int ya = wrap_index(int(std::floor(y)), h, texture.wrap_t);
    return {xa, xa, ya, ya, 0.f, 0.f};
  }
  // Bilinear between the four texel centres around (x, y); texel i's centre is at i + 0.5.
  const float fx = x - 0.5f, fy = y - 0.5f;
  const float x0 = std::floor(fx), y0 = std::floor(fy);
  const int ix = int(x0), iy = int(y0);
  return {wrap_index(ix, w, texture.wrap_s), wrap_index(ix + 1, w, texture.wrap_s),
          wrap_index(iy, h, texture.wrap_t), wrap_index(iy + 1, h, texture.wrap_t), fx - x0,
          fy - y0};
}

}  // namespace

glm::vec4 sample(const TextureImage& image, const Texture& texture, glm::vec2 uv, bool srgb) {
  const Footprint f = footprint(image, texture, uv);
  if (!image.rgba8.empty()) {
    // (TextureImage::texel's reads, inline: the image's format and table chosen once.)
    const uint8_t* rgba = image.rgba8.data();
    const float* rgb = srgb ? srgb8.data() : unorm8.data();
    const size_t w = size_t(image.width);
    auto at = [&](int x, int y) { return 4 * (size_t(y) * w + size_t(x)); };
    if (texture.nearest) return texel8(rgba, at(f.xa, f.ya), rgb);
    const glm::vec4 top =
        glm::mix(texel8(rgba, at(f.xa, f.ya), rgb), texel8(rgba, at(f.xb, f.ya), rgb), f.tx);
    const glm::vec4 bottom =
        glm::mix(texel8(rgba, at(f.xa, f.yb), rgb), texel8(rgba, at(f.xb, f.yb), rgb), f.tx);
    return glm::mix(top, bottom, f.ty);
  }
  if (texture.nearest) return image.texel(f.xa, f.ya, srgb);
  const glm::vec4 top = glm::mix(image.texel(f.xa, f.ya, srgb), image.texel(f.xb, f.ya, srgb), f.tx);
  const glm::vec4 bottom =
      glm::mix(image.texel(f.xa, f.yb, srgb), image.texel(f.xb, f.yb, srgb), f.tx);
  return glm::mix(top, bottom, f.ty);
}

void prefetch(const TextureImage& image, const Texture& texture, glm::vec2 uv) {
  const Footprint f = footprint(image, texture, uv);
  const size_t w = size_t(image.width);
  const size_t a = 4 * (size_t(f.ya) * w + size_t(f.xa)), b = 4 * (size_t(f.yb) * w + size_t(f.xa));
  // Each row's first texel: its neighbour is on the same cache line but where the row crosses one.
  if (!image.rgba8.empty()) {
    __builtin_prefetch(&image.rgba8[a]);
    __builtin_prefetch(&image.rgba8[b]);
  } else {
    __builtin_prefetch(&image.rgba16[a]);
    __builtin_prefetch(&image.rgba16[b]);
  }
}

}  // namespace dacrt
