// The texture sampler (materials/texture.h): nearest and bilinear filtering, sRGB decoded per
// texel before filtering, the repeat, mirror and clamp wrap modes, and coordinates far out of range
// or not numbers.
#include <doctest/doctest.h>

#include <cmath>

#include "dacrt/materials/texture.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

TextureImage image2x2() {
  TextureImage image;
  image.width = image.height = 2;
  image.rgba8.assign(kTexels.begin(), kTexels.end());
  return image;
}

}  // namespace

TEST_CASE("texture sampling: nearest and bilinear, sRGB per texel, wrap modes") {
  // The sRGB curve's known values: 188 → 0.5029, 0.5 → 0.2140, linear below 0.04045.
  CHECK(kGrey == doctest::Approx(0.50289).epsilon(1e-4));
  CHECK(srgb_to_linear(0.5f) == doctest::Approx(0.21404).epsilon(1e-4));
  CHECK(srgb_to_linear(0.04f) == doctest::Approx(0.04f / 12.92f));
  const TextureImage image = image2x2();
  Texture t;
  t.nearest = true;
  // uv (0, 0) is the image's top-left corner.
  CHECK(sample(image, t, {0.25f, 0.25f}, false) == glm::vec4(1, 0, 0, 1));
  CHECK(sample(image, t, {0.75f, 0.25f}, false) == glm::vec4(0, 1, 0, 128.f / 255.f));
  CHECK(sample(image, t, {0.25f, 0.75f}, false) == glm::vec4(0, 0, 1, 1));
  CHECK(sample(image, t, {0.75f, 0.75f}, true) == glm::vec4(kGrey, kGrey, kGrey, 1));

  t.nearest = false;
  // At a texel centre bilinear filtering returns the texel; at the middle, the mean of the four
  // texels after sRGB decoding (not the decoded mean of the bytes).
  CHECK(sample(image, t, {0.75f, 0.75f}, true) == glm::vec4(kGrey, kGrey, kGrey, 1));
  const glm::vec4 mid = sample(image, t, {0.5f, 0.5f}, true);
  CHECK(mid.r == doctest::Approx((1.f + kGrey) / 4));
  CHECK(mid.a == doctest::Approx((3.f + 128.f / 255.f) / 4));
  // Halfway between the two top texels, a quarter of the way down from the top edge: with
  // repeat, the top row blends with the bottom row (the texel above wraps around).
  const glm::vec4 edge = sample(image, t, {0.5f, 0.0f}, false);
  CHECK(edge.r == doctest::Approx(0.25f * (1.f + 0.f + 0.f + 188.f / 255.f)));
  t.wrap_t = Wrap::clamp;
  CHECK(sample(image, t, {0.5f, 0.0f}, false).r == doctest::Approx(0.5f));

  t.nearest = true;
  t.wrap_s = t.wrap_t = Wrap::repeat;
  CHECK(sample(image, t, {1.25f, 0.25f}, false) == sample(image, t, {0.25f, 0.25f}, false));
  CHECK(sample(image, t, {-0.75f, 2.25f}, false) == sample(image, t, {0.25f, 0.25f}, false));
  t.wrap_s = Wrap::mirror;
  CHECK(sample(image, t, {1.25f, 0.25f}, false) == sample(image, t, {0.75f, 0.25f}, false));
  CHECK(sample(image, t, {2.25f, 0.25f}, false) == sample(image, t, {0.25f, 0.25f}, false));
  CHECK(sample(image, t, {-0.25f, 0.25f}, false) == sample(image, t, {0.25f, 0.25f}, false));
  t.wrap_s = Wrap::clamp;
  CHECK(sample(image, t, {7.f, 0.25f}, false) == sample(image, t, {0.75f, 0.25f}, false));
  CHECK(sample(image, t, {-7.f, 0.25f}, false) == sample(image, t, {0.25f, 0.25f}, false));

  // Coordinates far out or not numbers still give a texel, never an out-of-bounds read.
  for (Wrap wrap : {Wrap::repeat, Wrap::mirror, Wrap::clamp})
    for (bool nearest : {true, false})
      for (float u : {1e30f, -1e30f, INFINITY, NAN, 16777217.f}) {
        t.wrap_s = t.wrap_t = wrap;
        t.nearest = nearest;
        const glm::vec4 c = sample(image, t, {u, u}, false);
        CHECK((std::isfinite(c.r) && c.r >= 0.f && c.r <= 1.f));
      }
}

TEST_CASE("texture sampling: an 8-bit image's lookups are the filtered texels, bit for bit") {
  // A 7 × 5 image of arbitrary bytes: every lookup is the bilinear mix (or the nearest texel) of
  // texels decoded as v / 255, through the sRGB curve for colour (never alpha).
  TextureImage image;
  image.width = 7, image.height = 5;
  image.rgba8.resize(4 * 7 * 5);
  uint32_t state = 51;
  for (uint8_t& b : image.rgba8) b = uint8_t((state = state * 1664525u + 1013904223u) >> 24);
  auto texel = [&](int x, int y, bool srgb) {
    const uint8_t* p = &image.rgba8[4 * size_t(y * 7 + x)];
    glm::vec4 c(float(p[0]) / 255.f, float(p[1]) / 255.f, float(p[2]) / 255.f, float(p[3]) / 255.f);
    if (srgb) c = {srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b), c.a};
    return c;
  };
  int differ = 0, texels_differ = 0;
  for (int k = 0; k < 2000; ++k) {
    const glm::vec2 uv(float(k % 41) / 41.f + 0.004f, float(k % 37) / 37.f + 0.007f);
    for (bool srgb : {false, true}) {
      for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x) texels_differ += image.texel(x, y, srgb) != texel(x, y, srgb);
      Texture t;
      t.nearest = true;
      const int nx = int(std::floor(uv.x * 7.f)), ny = int(std::floor(uv.y * 5.f));
      differ += sample(image, t, uv, srgb) != texel(nx, ny, srgb);
      t.nearest = false;  // repeat: the texel before column 0 is column 6
      const float fx = uv.x * 7.f - 0.5f, fy = uv.y * 5.f - 0.5f;
      const float x0 = std::floor(fx), y0 = std::floor(fy);
      const int xa = (int(x0) + 7) % 7, xb = (int(x0) + 8) % 7;
      const int ya = (int(y0) + 5) % 5, yb = (int(y0) + 6) % 5;
      const glm::vec4 top = glm::mix(texel(xa, ya, srgb), texel(xb, ya, srgb), fx - x0);
      const glm::vec4 bottom = glm::mix(texel(xa, yb, srgb), texel(xb, yb, srgb), fx - x0);
      differ += sample(image, t, uv, srgb) != glm::mix(top, bottom, fy - y0);
    }
  }
  CHECK(texels_differ == 0);
  CHECK(differ == 0);
}
