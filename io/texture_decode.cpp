#include "io/texture_decode.h"

#include <stb_image.h>

#include <climits>
#include <cstring>
#include <memory>

#include "util/error.h"

namespace dacrt {

namespace {

[[noreturn]] void fail(const std::string& what, const std::string& why) {
  throw Error(what + " cannot be decoded: " + why);
}

struct Header {
  int width, height;
  bool wide;  // 16 bits per channel
};

// The image's size from its header, bounded (so a header that claims a huge image cannot exhaust
// memory) before anything is decoded.
Header header(const unsigned char* bytes, size_t size, const std::string& what) {
  if (size == 0) fail(what, "it has no data");
  if (size > size_t(INT_MAX)) fail(what, "it is larger than 2 GiB");
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_memory(bytes, int(size), &w, &h, &channels))
    fail(what, std::string(stbi_failure_reason() ? stbi_failure_reason() : "unknown format") +
                   " (PNG and JPEG are supported)");
  constexpr long long kMaxTexels = 1ll << 27;
  if (w <= 0 || h <= 0 || (long long)w * h > kMaxTexels)
    fail(what, std::to_string(w) + " x " + std::to_string(h) + " texels is more than 2^27");
  return {w, h, stbi_is_16_bit_from_memory(bytes, int(size)) != 0};
}

}  // namespace

uint64_t decoded_size(const unsigned char* bytes, size_t size, const std::string& what) {
  const Header h = header(bytes, size, what);
  return uint64_t(h.width) * uint64_t(h.height) * 4 * (h.wide ? 2 : 1);
}

TextureImage decode_image(const unsigned char* bytes, size_t size, const std::string& what) {
  const Header head = header(bytes, size, what);
  const int n = int(size);
  int w = 0, h = 0, channels = 0;
  auto fail = [&](const std::string& why) -> TextureImage { dacrt::fail(what, why); };
  TextureImage image;
  const bool wide = head.wide;
  if (wide) {
    std::unique_ptr<stbi_us, void (*)(void*)> data(
        stbi_load_16_from_memory(bytes, n, &w, &h, &channels, 4), stbi_image_free);
    if (!data) return fail(stbi_failure_reason() ? stbi_failure_reason() : "corrupt data");
    image.rgba16.assign(data.get(), data.get() + 4 * size_t(w) * size_t(h));
  } else {
    std::unique_ptr<stbi_uc, void (*)(void*)> data(
        stbi_load_from_memory(bytes, n, &w, &h, &channels, 4), stbi_image_free);
    if (!data) return fail(stbi_failure_reason() ? stbi_failure_reason() : "corrupt data");
    image.rgba8.assign(data.get(), data.get() + 4 * size_t(w) * size_t(h));
  }
  image.width = w;
  image.height = h;
  return image;
}

}  // namespace dacrt
