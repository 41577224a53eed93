// The WebP decoder (io/texture_decode.cpp, libwebp): lossless files to exactly their RGBA, lossy
// ones with and without alpha to close to it, and hostile files: data cut short or damaged, an
// animation, a header claiming a huge size (refused before anything is allocated).
#include <doctest/doctest.h>

#include "tests/allocations.h"
#include "tests/texture_fixtures.h"
#include "tests/webp.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

// 7 × 5 RGBA texels of many values; alpha 0, 1, 128 and 255 in turn.
std::vector<uint8_t> varied_texels() {
  std::vector<uint8_t> t(4 * 7 * 5);
  for (size_t i = 0; i < t.size(); ++i) t[i] = uint8_t(i * 53 + 7);
  for (size_t i = 0; i < t.size() / 4; ++i)
    t[4 * i + 3] = uint8_t(i % 4 == 0 ? 0 : i % 4 == 1 ? 128 : i % 4 == 2 ? 1 : 255);
  return t;
}

}  // namespace

TEST_CASE("WebP: lossless decodes to exactly its RGBA, lossy with or without alpha to near it") {
  const std::vector<uint8_t> texels = varied_texels();
  const std::vector<unsigned char> lossless = webp_lossless(7, 5, texels);
  const TextureImage image = decode_image(lossless.data(), lossless.size(), "x");
  CHECK(image.width == 7);
  CHECK(image.height == 5);
  CHECK(image.rgba16.empty());
  // Not premultiplied: the RGB under alpha 0 kept.
  CHECK(std::vector<uint8_t>(image.rgba8.begin(), image.rgba8.end()) == texels);
  CHECK(decoded_size(lossless.data(), lossless.size(), "x") == 4 * 7 * 5);
  CHECK(image.texel(0, 1, true).g == doctest::Approx(srgb_to_linear(texels[29] / 255.f)));

  // Lossy: 16 × 16 in four flat 8 × 8 quadrants, opaque, then with alpha (VP8X + ALPH).
  auto quadrants = [](const std::vector<std::vector<uint8_t>>& colors) {
    std::vector<uint8_t> t;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        const std::vector<uint8_t>& c = colors[size_t(y / 8 * 2 + x / 8)];
        t.insert(t.end(), c.begin(), c.end());
      }
    return t;
  };
  auto close = [](const TextureImage& i, int x, int y, glm::ivec4 want, int within) {
    const glm::ivec4 got(i.texel(x, y, false) * 255.f + 0.5f);
    INFO(x << ", " << y << ": " << got.r << " " << got.g << " " << got.b << " " << got.a);
    CHECK(glm::all(glm::lessThanEqual(glm::abs(got - want), glm::ivec4(within))));
  };
  const std::vector<unsigned char> opaque = webp_lossy(
      16, 16,
      quadrants({{200, 40, 40, 255}, {40, 200, 40, 255}, {40, 40, 200, 255}, {220, 220, 50, 255}}),
      95);
  CHECK(opaque.size() > 20);
  CHECK(std::memcmp(&opaque[12], "VP8 ", 4) == 0);
  const TextureImage o = decode_image(opaque.data(), opaque.size(), "x");
  REQUIRE(o.rgba8.size() == 4 * 256);
  close(o, 3, 3, {200, 40, 40, 255}, 8);
  close(o, 12, 3, {40, 200, 40, 255}, 8);
  close(o, 3, 12, {40, 40, 200, 255}, 8);
  close(o, 12, 12, {220, 220, 50, 255}, 8);
  const std::vector<unsigned char> translucent = webp_lossy(
      16, 16,
      quadrants({{200, 40, 40, 0}, {40, 200, 40, 60}, {40, 40, 200, 128}, {220, 220, 50, 255}}),
      95);
  CHECK(std::memcmp(&translucent[12], "VP8X", 4) == 0);
  const TextureImage t = decode_image(translucent.data(), translucent.size(), "x");
  REQUIRE(t.rgba8.size() == 4 * 256);
  close(t, 12, 3, {40, 200, 40, 60}, 8);  // not premultiplied: 60 × 200 / 255 would be 47
  close(t, 3, 12, {40, 40, 200, 128}, 8);
  CHECK(t.rgba8[4 * (3 * 16 + 3) + 3] == 0);  // alpha is lossless
  CHECK(t.rgba8[4 * (12 * 16 + 12) + 3] == 255);
}

TEST_CASE("WebP: data cut short or damaged, an animation, a huge header: one error each") {
  const std::vector<uint8_t> texels = varied_texels();
  const std::vector<unsigned char> lossless = webp_lossless(7, 5, texels);
  std::vector<uint8_t> noise;
  for (int i = 0; i < 64 * 64; ++i)
    noise.insert(noise.end(), {uint8_t(i * 7919 % 251), uint8_t(i * 31 % 253), uint8_t(i), 255});
  const std::vector<unsigned char> lossy = webp_lossy(64, 64, noise, 80);
  REQUIRE(decode_error(lossless) == "no error");
  REQUIRE(decode_error(lossy) == "no error");
  auto one_line = [](const std::string& e, const std::string& says) {
    INFO(e);
    CHECK(e.rfind("x.png cannot be decoded: ", 0) == 0);
    CHECK(has(e, says));
    CHECK(!has(e, "\n"));
  };

  // Cut short: in the image data, and in the header.
  const std::string truncated = "invalid WebP data: the data ends before the image does";
  for (const std::vector<unsigned char>* whole : {&lossless, &lossy}) {
    one_line(decode_error({whole->begin(), whole->end() - 1}), truncated);
    one_line(decode_error({whole->begin(), whole->begin() + long(whole->size() * 2 / 3)}),
             truncated);
    one_line(decode_error({whole->begin(), whole->begin() + 20}), truncated);
  }
  // The RIFF and chunk sizes made to match the shorter data: the frame itself ends early.
  std::vector<unsigned char> resized(lossy.begin(), lossy.begin() + long(lossy.size() / 2));
  for (size_t at : {4, 16}) {
    const uint32_t size = uint32_t(resized.size() - at - 4);
    for (size_t i = 0; i < 4; ++i) resized[at + i] = uint8_t(size >> (8 * i));
  }
  one_line(decode_error(resized), truncated);

  // Damaged: the lossless bitstream (whose codes no longer decode), the RIFF signature.
  std::vector<unsigned char> damaged = lossless;
  for (size_t i = 25; i < damaged.size(); ++i) damaged[i] = 0xff;
  one_line(decode_error(damaged), "invalid WebP data: bitstream error");
  damaged = lossless;
  damaged[0] = 'X';
  one_line(decode_error(damaged), "it is a damaged WebP (its RIFF signature is altered)");

  // Animated: libwebp's still-image API has no first frame to give.
  const std::vector<unsigned char> animated = webp_animated(4, 4, {0xffff0000u, 0xff00ff00u});
  one_line(decode_error(animated), "it is an animated WebP (only still WebP images");
  CHECK_THROWS_WITH_AS(decoded_size(animated.data(), animated.size(), "x.png"),
                       decode_error(animated).c_str(), Error);

  // 16384 × 16384 texels (1 GiB decoded), 16384 × 8193: refused from the header, before any
  // buffer exists; 16384 × 8192 is 2^27 texels, which is allowed (and then fails as data cut
  // short).
  for (const uint32_t height : {16384u, 8193u}) {
    const std::vector<unsigned char> huge = webp_resized(lossless, 16384, height);
    AllocationWatch watch;
    const std::string e = decode_error(huge);
    one_line(e, "16384 x " + std::to_string(height) + " texels is more than 2^27");
    CHECK_THROWS_WITH_AS(decoded_size(huge.data(), huge.size(), "x.png"), e.c_str(), Error);
    CHECK(watch.peak() < (1u << 20));
  }
  const std::vector<unsigned char> most = webp_resized(lossless, 16384, 8192);
  CHECK(decoded_size(most.data(), most.size(), "x") == uint64_t(4) << 27);
}
