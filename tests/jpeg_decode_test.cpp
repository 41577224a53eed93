// The JPEG decoder (io/texture_decode.cpp, libjpeg-turbo): grey, progressive and Adobe CMYK files
// to RGBA, and files cut short or claiming huge sizes refused.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

// Where `part` first occurs in `bytes`, or bytes.size().
size_t find_bytes(const std::vector<unsigned char>& bytes, const std::vector<unsigned char>& part) {
  return size_t(std::search(bytes.begin(), bytes.end(), part.begin(), part.end()) - bytes.begin());
}

}  // namespace

TEST_CASE("JPEG: grey, progressive and Adobe CMYK decode to RGBA, data cut short is refused") {
  auto texel = [](const TextureImage& image, int x, int y) {
    return glm::ivec4(image.texel(x, y, false) * 255.f + 0.5f);
  };
  auto close = [](glm::ivec4 a, glm::ivec4 b, int within) {
    INFO(a.r << " " << a.g << " " << a.b << " " << a.a << " vs " << b.r << " " << b.g << " " << b.b
             << " " << b.a);
    CHECK(glm::all(glm::lessThanEqual(glm::abs(a - b), glm::ivec4(within))));
  };
  // 16 × 16 in four 8 × 8 blocks (one JPEG block each): grey, RGB.
  auto quadrants = [](int channels, const std::vector<std::vector<uint8_t>>& colors) {
    std::vector<uint8_t> t;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        const std::vector<uint8_t>& c = colors[size_t(y / 8 * 2 + x / 8)];
        t.insert(t.end(), c.begin(), c.begin() + channels);
      }
    return t;
  };
  const std::vector<unsigned char> grey =
      jpeg_lib(16, 16, 1, quadrants(1, {{30}, {90}, {160}, {220}}));
  const TextureImage g = decode_image(grey.data(), grey.size(), "x");
  REQUIRE(g.rgba8.size() == 4 * 256);
  close(texel(g, 3, 3), {30, 30, 30, 255}, 2);
  close(texel(g, 12, 4), {90, 90, 90, 255}, 2);
  close(texel(g, 4, 12), {160, 160, 160, 255}, 2);
  close(texel(g, 12, 12), {220, 220, 220, 255}, 2);

  const std::vector<std::vector<uint8_t>> colors = {
      {200, 40, 40}, {40, 200, 40}, {40, 40, 200}, {220, 220, 50}};
  const std::vector<unsigned char> progressive =
      jpeg_lib(16, 16, 3, quadrants(3, colors), true, 100);
  CHECK(find_bytes(progressive, {0xff, 0xc2}) < progressive.size());  // SOF2: progressive
  const TextureImage p = decode_image(progressive.data(), progressive.size(), "x");
  REQUIRE(p.width == 16);
  close(texel(p, 3, 3), {200, 40, 40, 255}, 6);
  close(texel(p, 12, 3), {40, 200, 40, 255}, 6);
  close(texel(p, 3, 12), {40, 40, 200, 255}, 6);
  close(texel(p, 12, 12), {220, 220, 50, 255}, 6);

  // CMYK with an Adobe marker stores 255 − ink: no cyan, half magenta, full yellow, no black is
  // (255, 127, 0, 255) in the file, and RGB (255, 127, 0).
  const std::vector<uint8_t> cmyk = [] {
    std::vector<uint8_t> t;
    for (int i = 0; i < 256; ++i) t.insert(t.end(), {255, 127, 0, 255});
    return t;
  }();
  const std::vector<unsigned char> adobe = jpeg_lib(16, 16, 4, cmyk, false, 100);
  CHECK(find_bytes(adobe, {'A', 'd', 'o', 'b', 'e'}) < adobe.size());
  const TextureImage k = decode_image(adobe.data(), adobe.size(), "x");
  REQUIRE(k.rgba8.size() == 4 * 256);
  close(texel(k, 5, 9), {255, 127, 0, 255}, 3);

  // Cut in the middle of the scan: libjpeg would pad the rest with grey.
  std::vector<uint8_t> noise;
  for (int i = 0; i < 64 * 64 * 3; ++i) noise.push_back(uint8_t(i * 7919 % 251));
  const std::vector<unsigned char> whole = jpeg_lib(64, 64, 3, noise);
  REQUIRE(decode_error(whole) == "no error");
  const std::vector<unsigned char> cut(whole.begin(), whole.begin() + long(whole.size() * 2 / 3));
  CHECK(has(decode_error(cut), "invalid JPEG data: Premature end of JPEG file"));
  const std::vector<unsigned char> header_only(whole.begin(), whole.begin() + 100);
  CHECK(has(decode_error(header_only), "invalid JPEG data"));

  // A frame header claiming 65000 × 65000 texels: refused before decoding.
  std::vector<unsigned char> huge = whole;
  const size_t sof = find_bytes(huge, {0xff, 0xc0});
  REQUIRE(sof < huge.size());
  for (size_t i : {5, 7}) huge[sof + i] = 0xfd, huge[sof + i + 1] = 0xe8;  // height, width: 65000
  CHECK(has(decode_error(huge), "65000 x 65000 texels is more than 2^27"));
}
