// Image files for texture tests: 8-bit PNG and JPEG through stb_image_write (libstb); PNGs of
// every colour type, bit depth and interlacing written here with stored, uncompressed deflate
// blocks; grey, CMYK and progressive JPEGs through libjpeg.
#pragma once

#include <stb_image_write.h>

// clang-format off
#include <cstdio>  // before jpeglib.h, which uses size_t and FILE without including them
#include <jpeglib.h>
// clang-format on

#include <algorithm>
#include <cstdint>
#include <cstdlib>
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

// CRC-32 as PNG chunks use it.
inline uint32_t png_crc(const unsigned char* p, size_t n) {
  uint32_t c = 0xffffffffu;
  for (size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
  }
  return ~c;
}

inline void append_be32(std::vector<unsigned char>& v, uint32_t x) {
  for (int s = 24; s >= 0; s -= 8) v.push_back(uint8_t(x >> s));
}

// Appends the chunk `type` with `data` and its CRC to `png`.
inline void append_chunk(std::vector<unsigned char>& png, const char* type,
                         const std::vector<unsigned char>& data) {
  append_be32(png, uint32_t(data.size()));
  std::vector<unsigned char> body(type, type + 4);
  body.insert(body.end(), data.begin(), data.end());
  png.insert(png.end(), body.begin(), body.end());
  append_be32(png, png_crc(body.data(), body.size()));
}

// A zlib stream of `raw` in stored (uncompressed) deflate blocks.
inline std::vector<unsigned char> zlib_stored(const std::vector<unsigned char>& raw) {
  std::vector<unsigned char> z = {0x78, 0x01};
  for (size_t at = 0;; at += 65535) {
    const size_t n = std::min<size_t>(65535, raw.size() - at);
    z.push_back(at + n >= raw.size() ? 1 : 0);
    z.insert(z.end(), {uint8_t(n), uint8_t(n >> 8), uint8_t(~n), uint8_t(~n >> 8)});
    z.insert(z.end(), raw.begin() + long(at), raw.begin() + long(at + n));
    if (at + n >= raw.size()) break;
  }
  uint32_t a = 1, b = 0;
  for (unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
  append_be32(z, b << 16 | a);
  return z;
}

struct PngChunk {
  const char* type;
  std::vector<unsigned char> data;
};

// A PNG written here, independently of the decoder: colour type `type` (0 grey, 2 RGB, 3 palette,
// 4 grey + alpha, 6 RGBA) at `depth` bits per sample, `samples` one per channel per texel (rows
// from the top) packed big-endian and most significant bits first, filter 0 on every row, the
// seven Adam7 passes when `interlaced`, stored deflate blocks. `chunks` (PLTE, tRNS, ...) come
// between IHDR and IDAT.
inline std::vector<unsigned char> png_file(int width, int height, int depth, int type,
                                           const std::vector<uint16_t>& samples,
                                           const std::vector<PngChunk>& chunks = {},
                                           bool interlaced = false) {
  const int channels = type == 2 ? 3 : type == 4 ? 2 : type == 6 ? 4 : 1;
  std::vector<unsigned char> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<unsigned char> ihdr;
  append_be32(ihdr, uint32_t(width));
  append_be32(ihdr, uint32_t(height));
  ihdr.insert(ihdr.end(), {uint8_t(depth), uint8_t(type), 0, 0, uint8_t(interlaced)});
  append_chunk(out, "IHDR", ihdr);
  for (const PngChunk& c : chunks) append_chunk(out, c.type, c.data);
  // Adam7: (x0, y0, dx, dy) of the passes; one pass of step 1 when not interlaced.
  const int adam7[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                           {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};
  const int plain[1][4] = {{0, 0, 1, 1}};
  std::vector<unsigned char> raw;
  for (int p = 0; p < (interlaced ? 7 : 1); ++p) {
    const int* pass = interlaced ? adam7[p] : plain[0];
    if (pass[0] >= width) continue;  // an empty pass has no rows at all
    for (int y = pass[1]; y < height; y += pass[3]) {
      raw.push_back(0);
      uint32_t bits = 0;
      int held = 0;  // bits waiting in `bits`
      for (int x = pass[0]; x < width; x += pass[2])
        for (int c = 0; c < channels; ++c) {
          const uint16_t s = samples[(size_t(y) * size_t(width) + size_t(x)) * channels + c];
          bits = bits << depth | s;
          held += depth;
          while (held >= 8) raw.push_back(uint8_t(bits >> (held - 8))), held -= 8;
        }
      if (held) raw.push_back(uint8_t(bits << (8 - held)));
    }
  }
  append_chunk(out, "IDAT", zlib_stored(raw));
  append_chunk(out, "IEND", {});
  return out;
}

// RGB, 16 bits per channel.
inline std::vector<unsigned char> png16_rgb(int width, int height,
                                            const std::vector<uint16_t>& texels) {
  return png_file(width, height, 16, 2, texels);
}

// `png` with its IHDR claiming width × height texels (and a CRC to match).
inline std::vector<unsigned char> png_resized(std::vector<unsigned char> png, uint32_t width,
                                              uint32_t height) {
  for (int i = 0; i < 4; ++i) {
    png[size_t(16 + i)] = uint8_t(width >> (24 - 8 * i));
    png[size_t(20 + i)] = uint8_t(height >> (24 - 8 * i));
  }
  const uint32_t crc = png_crc(png.data() + 12, 17);
  for (int i = 0; i < 4; ++i) png[size_t(29 + i)] = uint8_t(crc >> (24 - 8 * i));
  return png;
}

// A JPEG through libjpeg: `components` 1 (grey), 3 (RGB, stored as YCbCr) or 4 (CMYK, stored as
// given, with the Adobe marker libjpeg writes for it), at `quality`, progressive when asked.
inline std::vector<unsigned char> jpeg_lib(int width, int height, int components,
                                           const std::vector<uint8_t>& texels,
                                           bool progressive = false, int quality = 95) {
  jpeg_compress_struct cinfo;
  jpeg_error_mgr errors;
  cinfo.err = jpeg_std_error(&errors);
  jpeg_create_compress(&cinfo);
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&cinfo, &buffer, &size);
  cinfo.image_width = JDIMENSION(width);
  cinfo.image_height = JDIMENSION(height);
  cinfo.input_components = components;
  cinfo.in_color_space = components == 1 ? JCS_GRAYSCALE : components == 3 ? JCS_RGB : JCS_CMYK;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, quality, TRUE);
  if (progressive) jpeg_simple_progression(&cinfo);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    auto* row = const_cast<JSAMPLE*>(texels.data()) +
                size_t(cinfo.next_scanline) * size_t(width) * size_t(components);
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  std::vector<unsigned char> out(buffer, buffer + size);
  std::free(buffer);
  return out;
}

}  // namespace dacrt::test
