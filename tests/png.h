// Image files for texture tests: 8-bit PNG and JPEG through stb_image_write (libstb), 16-bit PNG
// written here (stb_image_write has none) with stored, uncompressed deflate blocks.
#pragma once

#include <stb_image_write.h>

#include <cstdint>
#include <vector>

namespace dacrt::test {

// stb_image_write's callback: appends the bytes to the std::vector<unsigned char> `context`.
inline void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<unsigned char>*>(context);
  const auto* bytes = static_cast<const unsigned char*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

// `channels` (1 to 4) bytes per texel, rows from the top.
inline std::vector<unsigned char> png8(int width, int height, int channels,
                                       const std::vector<uint8_t>& texels) {
  std::vector<unsigned char> out;
  stbi_write_png_to_func(append_bytes, &out, width, height, channels, texels.data(),
                         width * channels);
  return out;
}

// A JPEG of `channels` (1 or 3) bytes per texel, at quality 100.
inline std::vector<unsigned char> jpeg(int width, int height, int channels,
                                       const std::vector<uint8_t>& texels) {
  std::vector<unsigned char> out;
  stbi_write_jpg_to_func(append_bytes, &out, width, height, channels, texels.data(), 100);
  return out;
}

// RGB, 16 bits per channel.
inline std::vector<unsigned char> png16_rgb(int width, int height,
                                            const std::vector<uint16_t>& texels) {
  auto crc = [](const unsigned char* p, size_t n, uint32_t c = 0xffffffffu) {
    for (size_t i = 0; i < n; ++i) {
      c ^= p[i];
      for (int k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
    }
    return c;
  };
  std::vector<unsigned char> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  auto be32 = [](std::vector<unsigned char>& v, uint32_t x) {
    for (int s = 24; s >= 0; s -= 8) v.push_back(uint8_t(x >> s));
  };
  auto chunk = [&](const char* type, const std::vector<unsigned char>& data) {
    be32(out, uint32_t(data.size()));
    std::vector<unsigned char> body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    out.insert(out.end(), body.begin(), body.end());
    be32(out, ~crc(body.data(), body.size()));
  };
  std::vector<unsigned char> ihdr;
  be32(ihdr, uint32_t(width));
  be32(ihdr, uint32_t(height));
  ihdr.insert(ihdr.end(), {16, 2, 0, 0, 0});  // 16 bits, RGB, deflate, no filter, no interlace
  chunk("IHDR", ihdr);
  std::vector<unsigned char> raw;  // each row: filter 0, then big-endian samples
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);
    for (int i = 0; i < 3 * width; ++i) {
      uint16_t s = texels[size_t(y) * 3 * size_t(width) + size_t(i)];
      raw.push_back(uint8_t(s >> 8));
      raw.push_back(uint8_t(s));
    }
  }
  std::vector<unsigned char> z = {0x78, 0x01};
  for (size_t at = 0; at < raw.size() || at == 0; at += 65535) {
    const size_t n = std::min<size_t>(65535, raw.size() - at);
    z.push_back(at + n >= raw.size() ? 1 : 0);
    z.insert(z.end(), {uint8_t(n), uint8_t(n >> 8), uint8_t(~n), uint8_t(~n >> 8)});
    z.insert(z.end(), raw.begin() + long(at), raw.begin() + long(at + n));
    if (at + n >= raw.size()) break;
  }
  uint32_t a = 1, b = 0;
  for (unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
  be32(z, b << 16 | a);
  chunk("IDAT", z);
  chunk("IEND", {});
  return out;
}

}  // namespace dacrt::test
