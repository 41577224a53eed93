// WebP files for texture tests, written by libwebp's encoder (lossless and lossy, RGBA) and
// libwebpmux's animation encoder, and a lossless file whose header claims another size.
#pragma once

#include <doctest/doctest.h>
#include <webp/encode.h>
#include <webp/mux.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace dacrt::test {

// `rgba` (4 bytes a texel, rows from the top) as a lossless WebP that decodes to exactly these
// bytes (WebPEncodeLosslessRGBA leaves `exact` off, and changes the RGB of texels of alpha 0).
inline std::vector<unsigned char> webp_lossless(int width, int height,
                                                const std::vector<uint8_t>& rgba) {
  REQUIRE(rgba.size() == 4 * size_t(width) * size_t(height));
  WebPConfig config;
  REQUIRE(WebPConfigInit(&config));
  config.lossless = 1;
  config.exact = 1;  // keep the RGB of transparent texels
  WebPPicture picture;
  REQUIRE(WebPPictureInit(&picture));
  picture.use_argb = 1;
  picture.width = width;
  picture.height = height;
  REQUIRE(WebPPictureImportRGBA(&picture, rgba.data(), 4 * width));
  WebPMemoryWriter writer;
  WebPMemoryWriterInit(&writer);
  picture.writer = WebPMemoryWrite;
  picture.custom_ptr = &writer;
  const bool ok = WebPEncode(&config, &picture);
  WebPPictureFree(&picture);
  std::vector<unsigned char> out(writer.mem, writer.mem + writer.size);
  WebPMemoryWriterClear(&writer);
  REQUIRE(ok);
  return out;
}

// `rgba` as a lossy WebP at `quality` (0 to 100); with alpha below 255 somewhere, the file is
// VP8X with an ALPH chunk (alpha compressed losslessly).
inline std::vector<unsigned char> webp_lossy(int width, int height,
                                             const std::vector<uint8_t>& rgba, float quality) {
  REQUIRE(rgba.size() == 4 * size_t(width) * size_t(height));
  uint8_t* bytes = nullptr;
  const size_t size = WebPEncodeRGBA(rgba.data(), width, height, 4 * width, quality, &bytes);
  REQUIRE(size > 0);
  std::vector<unsigned char> out(bytes, bytes + size);
  WebPFree(bytes);
  return out;
}

// An animated WebP of `width` × `height` whose frames are each one flat colour (0xAARRGGBB).
inline std::vector<unsigned char> webp_animated(int width, int height,
                                                const std::vector<uint32_t>& argb_frames) {
  WebPAnimEncoderOptions options;
  REQUIRE(WebPAnimEncoderOptionsInit(&options));
  WebPAnimEncoder* encoder = WebPAnimEncoderNew(width, height, &options);
  REQUIRE(encoder != nullptr);
  WebPConfig config;
  REQUIRE(WebPConfigInit(&config));
  config.lossless = 1;
  int time = 0;
  for (uint32_t argb : argb_frames) {
    WebPPicture frame;
    REQUIRE(WebPPictureInit(&frame));
    frame.use_argb = 1;
    frame.width = width;
    frame.height = height;
    REQUIRE(WebPPictureAlloc(&frame));
    for (int i = 0; i < width * height; ++i) frame.argb[i] = argb;
    const bool added = WebPAnimEncoderAdd(encoder, &frame, time, &config);
    WebPPictureFree(&frame);
    REQUIRE(added);
    time += 100;
  }
  REQUIRE(WebPAnimEncoderAdd(encoder, nullptr, time, nullptr));
  WebPData data;
  WebPDataInit(&data);
  const bool assembled = WebPAnimEncoderAssemble(encoder, &data);
  WebPAnimEncoderDelete(encoder);
  std::vector<unsigned char> out(data.bytes, data.bytes + data.size);
  WebPDataClear(&data);
  REQUIRE(assembled);
  return out;
}

// A simple-format lossless WebP (RIFF, then one VP8L chunk) with its header rewritten to claim
// `width` × `height` (each 1 to 16384, the format's limit); the image data stays as it was.
inline std::vector<unsigned char> webp_resized(std::vector<unsigned char> webp, uint32_t width,
                                               uint32_t height) {
  REQUIRE(webp.size() >= 25);
  REQUIRE(std::memcmp(&webp[12], "VP8L", 4) == 0);
  REQUIRE(webp[20] == 0x2f);  // the VP8L signature
  // Then 32 bits, least significant first: width − 1 (14 bits), height − 1 (14), alpha, version.
  uint32_t bits = 0;
  for (int i = 0; i < 4; ++i) bits |= uint32_t(webp[size_t(21 + i)]) << (8 * i);
  bits = (bits & 0xf0000000u) | (width - 1) | (height - 1) << 14;
  for (int i = 0; i < 4; ++i) webp[size_t(21 + i)] = uint8_t(bits >> (8 * i));
  return webp;
}

}  // namespace dacrt::test
