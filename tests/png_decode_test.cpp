// The PNG decoder (io/texture_decode.cpp, libpng): every colour type, bit depth and interlacing to
// exact RGBA, and hostile files: data cut short, bad CRCs and Adler-32, Apple's CgBI, headers
// claiming huge sizes, and zlib bombs, each refused or bounded before the memory is taken.
#include <doctest/doctest.h>
#include <zlib.h>

#include <cstring>

#include "tests/allocations.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

// The decoded 8-bit texels, as a std::vector to compare with expected values.
std::vector<uint8_t> texels8(const TextureImage& image) {
  return std::vector<uint8_t>(image.rgba8.begin(), image.rgba8.end());
}

// `raw` compressed by zlib at its best ratio.
std::vector<unsigned char> deflated(const std::vector<unsigned char>& raw) {
  uLongf size = compressBound(uLong(raw.size()));
  std::vector<unsigned char> out(size);
  REQUIRE(compress2(out.data(), &size, raw.data(), uLong(raw.size()), 9) == Z_OK);
  out.resize(size);
  return out;
}

// Where the first chunk `type` of `png` starts (its length field).
size_t chunk_at(const std::vector<unsigned char>& png, const char* type) {
  for (size_t at = 8; at + 8 <= png.size();) {
    if (std::memcmp(&png[at + 4], type, 4) == 0) return at;
    at += 12 + (size_t(png[at]) << 24 | size_t(png[at + 1]) << 16 | size_t(png[at + 2]) << 8 |
                png[at + 3]);
  }
  FAIL("no chunk " << type);
  return 0;
}

// `png` with a chunk of `type` and `data` inserted before its first IDAT.
std::vector<unsigned char> with_chunk(std::vector<unsigned char> png, const char* type,
                                      const std::vector<unsigned char>& data) {
  std::vector<unsigned char> chunk;
  append_chunk(chunk, type, data);
  png.insert(png.begin() + long(chunk_at(png, "IDAT")), chunk.begin(), chunk.end());
  return png;
}

}  // namespace

TEST_CASE("PNG: data cut short, bad CRCs, CgBI and huge headers are refused") {
  std::vector<uint16_t> samples;
  for (int i = 0; i < 4 * 4 * 4; ++i) samples.push_back(uint16_t(i * 3));
  const std::vector<unsigned char> good = png_file(4, 4, 8, 6, samples);
  REQUIRE(decode_error(png8(2, 2, 4, kTexels)) == "no error");
  REQUIRE(decode_image(good.data(), good.size(), "x").rgba8.size() == 64);

  const size_t idat = chunk_at(good, "IDAT");
  std::vector<unsigned char> cut(good.begin(), good.begin() + long(idat + 8 + 30));
  CHECK(has(decode_error(cut), "invalid PNG data: the data ends before the image does"));
  // The image data whole but no IEND: the file is cut short all the same.
  std::vector<unsigned char> no_end(good.begin(), good.end() - 12);
  CHECK(has(decode_error(no_end), "the data ends before the image does"));

  // The IDAT intact, its CRC wrong.
  std::vector<unsigned char> crc = good;
  crc[chunk_at(good, "IEND") - 1] ^= 1;
  CHECK(has(decode_error(crc), "invalid PNG data: IDAT: CRC error"));

  // The zlib stream's Adler-32 wrong, the chunk's CRC right: found when the stream ends.
  std::vector<unsigned char> adler = good;
  const size_t idat_end = chunk_at(good, "IEND") - 4;  // the IDAT's CRC
  adler[idat_end - 1] ^= 1;
  const uint32_t fixed = png_crc(&adler[idat + 4], idat_end - idat - 4);
  for (size_t i = 0; i < 4; ++i) adler[idat_end + i] = uint8_t(fixed >> (24 - 8 * i));
  CHECK(has(decode_error(adler), "invalid PNG data: IDAT: incorrect data check"));

  std::vector<unsigned char> cgbi = good;
  std::vector<unsigned char> chunk;
  append_chunk(chunk, "CgBI", {0x50, 0, 0x20, 2});
  cgbi.insert(cgbi.begin() + 8, chunk.begin(), chunk.end());
  CHECK(has(decode_error(cgbi), "is an Apple CgBI PNG"));

  // 10^10 texels: refused from the header, before any buffer for them exists.
  const std::vector<unsigned char> huge = png_resized(good, 100000, 100000);
  {
    AllocationWatch watch;
    const std::string e = decode_error(huge);
    CHECK(has(e, "100000 x 100000 texels is more than 2^27"));
    CHECK(watch.peak() < (1u << 20));
  }
  // 65536 × 65537 texels: their product in 32 bits wraps to 65536, far below the limit; in 64
  // bits it is 2^32 + 65536, far above. (10^10 wraps to 1 410 065 408, above it either way.)
  {
    AllocationWatch watch;
    CHECK(has(decode_error(png_resized(good, 65536, 65537)),
              "65536 x 65537 texels is more than 2^27"));
    CHECK(watch.peak() < (1u << 20));
  }
  CHECK(
      has(decode_error(png_resized(good, 1u << 28, 1)), "268435456 x 1 texels is more than 2^27"));
  CHECK(has(decode_error(png_resized(good, 0, 4)), "invalid PNG data"));
}

TEST_CASE("PNG: zlib bombs are bounded: in a text chunk, past the image, a big image of zeros") {
  const std::vector<uint16_t> texel = {10, 20, 30, 40};
  const std::vector<unsigned char> small = png_file(1, 1, 8, 6, texel);
  const std::vector<uint8_t> expected = {10, 20, 30, 40};
  // A zTXt comment of 64 MiB (64 KiB compressed): skipped, never inflated.
  {
    std::vector<unsigned char> ztxt = bytes_of("Comment");
    ztxt.insert(ztxt.end(), {0, 0});  // keyword's end, deflate
    const std::vector<unsigned char> text = deflated(std::vector<unsigned char>(64 << 20, 'a'));
    ztxt.insert(ztxt.end(), text.begin(), text.end());
    const std::vector<unsigned char> png = with_chunk(small, "zTXt", ztxt);
    AllocationWatch watch;
    CHECK(texels8(decode_image(png.data(), png.size(), "x")) == expected);
    CHECK(watch.peak() < (1u << 20));
  }
  // A 1 × 1 image whose IDAT inflates to 64 MiB: one row is read, the rest is not inflated.
  {
    std::vector<unsigned char> raw = {0, 10, 20, 30, 40};
    raw.resize(raw.size() + (64 << 20));
    std::vector<unsigned char> png = small;
    const size_t idat = chunk_at(png, "IDAT");
    png.erase(png.begin() + long(idat), png.begin() + long(chunk_at(png, "IEND")));
    std::vector<unsigned char> chunk;
    append_chunk(chunk, "IDAT", deflated(raw));
    png.insert(png.begin() + long(idat), chunk.begin(), chunk.end());
    AllocationWatch watch;
    CHECK(texels8(decode_image(png.data(), png.size(), "x")) == expected);
    CHECK(watch.peak() < (1u << 20));
  }
  // 4096 × 4096 grey zeros, 16 KiB compressed: allowed, and decoded in its own size (64 MiB).
  {
    std::vector<unsigned char> png = png_file(1, 1, 8, 0, {0});
    png = png_resized(png, 4096, 4096);
    const size_t idat = chunk_at(png, "IDAT");
    png.erase(png.begin() + long(idat), png.begin() + long(chunk_at(png, "IEND")));
    std::vector<unsigned char> chunk;
    append_chunk(chunk, "IDAT", deflated(std::vector<unsigned char>(4097 * 4096, 0)));
    png.insert(png.begin() + long(idat), chunk.begin(), chunk.end());
    CHECK(png.size() < 100000);
    AllocationWatch watch;
    const TextureImage image = decode_image(png.data(), png.size(), "x");
    CHECK(watch.peak() < (64u << 20) + (1u << 20));
    REQUIRE(image.rgba8.size() == size_t(64) << 20);
    CHECK(image.texel(4095, 4095, false) == glm::vec4(0, 0, 0, 1));
  }
}

TEST_CASE("PNG: palette, grey, grey + alpha, tRNS, 1 and 2 bits, 16 bits, Adam7: exact RGBA") {
  auto rgba8 = [](const std::vector<unsigned char>& png) {
    const TextureImage image = decode_image(png.data(), png.size(), "x");
    CHECK(image.rgba16.empty());
    return texels8(image);
  };
  auto rgba16 = [](const std::vector<unsigned char>& png) {
    const TextureImage image = decode_image(png.data(), png.size(), "x");
    CHECK(image.rgba8.empty());
    return std::vector<uint16_t>(image.rgba16.begin(), image.rgba16.end());
  };
  const PngChunk palette = {"PLTE", {10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120}};
  const PngChunk transparency = {"tRNS", {255, 0}};  // entries 2 and 3: opaque
  CHECK(rgba8(png_file(3, 1, 8, 3, {2, 0, 1}, {palette, transparency})) ==
        std::vector<uint8_t>{70, 80, 90, 255, 10, 20, 30, 255, 40, 50, 60, 0});
  CHECK(rgba8(png_file(5, 1, 2, 3, {3, 2, 1, 0, 3}, {palette})) ==
        std::vector<uint8_t>{100, 110, 120, 255, 70, 80,  90,  255, 40,  50,
                             60,  255, 10,  20,  30, 255, 100, 110, 120, 255});
  // 1 bit: 0 and 1 are black and white; 10 texels a row, padded to 2 bytes.
  const std::vector<uint16_t> bits = {1, 0, 0, 1, 1, 1, 0, 1, 0, 1, 0, 1, 1, 0, 0, 0, 0, 0, 1, 1};
  std::vector<uint8_t> expected;
  for (uint16_t b : bits)
    expected.insert(expected.end(), {uint8_t(255 * b), uint8_t(255 * b), uint8_t(255 * b), 255});
  CHECK(rgba8(png_file(10, 2, 1, 0, bits)) == expected);
  CHECK(rgba8(png_file(2, 1, 8, 4, {100, 200, 7, 0})) ==
        std::vector<uint8_t>{100, 100, 100, 200, 7, 7, 7, 0});
  CHECK(rgba8(png_file(2, 1, 8, 0, {7, 8}, {{"tRNS", {0, 7}}})) ==
        std::vector<uint8_t>{7, 7, 7, 0, 8, 8, 8, 255});
  CHECK(rgba8(png_file(2, 1, 8, 2, {1, 2, 3, 4, 5, 6}, {{"tRNS", {0, 4, 0, 5, 0, 6}}})) ==
        std::vector<uint8_t>{1, 2, 3, 255, 4, 5, 6, 0});

  // 16 bits: every sample exact, high and low bytes not swapped.
  CHECK(rgba16(png_file(2, 1, 16, 6, {0x0102, 0xfffe, 0, 0x8001, 1, 0x7fff, 0xff00, 0x00ff})) ==
        std::vector<uint16_t>{0x0102, 0xfffe, 0, 0x8001, 1, 0x7fff, 0xff00, 0x00ff});
  CHECK(rgba16(png_file(1, 2, 16, 0, {0x1234, 0xabcd})) ==
        std::vector<uint16_t>{0x1234, 0x1234, 0x1234, 0xffff, 0xabcd, 0xabcd, 0xabcd, 0xffff});
  CHECK(rgba16(png_file(1, 1, 16, 4, {0x0203, 0x0405})) ==
        std::vector<uint16_t>{0x0203, 0x0203, 0x0203, 0x0405});

  // Adam7: an 11 × 9 RGBA image (every pass non-empty, ragged edges) texel for texel.
  std::vector<uint16_t> samples;
  for (int i = 0; i < 11 * 9 * 4; ++i) samples.push_back(uint16_t((i * 37 + i / 4) % 256));
  const std::vector<uint8_t> flat(samples.begin(), samples.end());
  CHECK(rgba8(png_file(11, 9, 8, 6, samples)) == flat);
  CHECK(rgba8(png_file(11, 9, 8, 6, samples, {}, true)) == flat);
  std::vector<uint16_t> wide;
  for (int i = 0; i < 11 * 9 * 4; ++i) wide.push_back(uint16_t(i * 611));
  CHECK(rgba16(png_file(11, 9, 16, 6, wide, {}, true)) == wide);
}
