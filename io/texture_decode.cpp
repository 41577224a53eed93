#include "io/texture_decode.h"

#include <stb_image.h>

#include <climits>
#include <cstring>
#include <memory>

#include "util/error.h"

namespace dacrt {

TextureImage decode_image(const unsigned char* bytes, size_t size, const std::string& what) {
  auto fail = [&](const std::string& why) -> TextureImage {
    throw Error(what + " cannot be decoded: " + why);
  };
  if (size == 0) return fail("it has no data");
  if (size > size_t(INT_MAX)) return fail("it is larger than 2 GiB");
  const int n = int(size);
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_memory(bytes, n, &w, &h, &channels))
    return fail(std::string(stbi_failure_reason() ? stbi_failure_reason() : "unknown format") +
                " (PNG and JPEG are supported)");
  // Bounded before decoding, so a header that claims a huge image cannot exhaust memory.
  constexpr long long kMaxTexels = 1ll << 27;
  if (w <= 0 || h <= 0 || (long long)w * h > kMaxTexels)
    return fail(std::to_string(w) + " x " + std::to_string(h) + " texels is more than 2^27");

  TextureImage image;
  const bool wide = stbi_is_16_bit_from_memory(bytes, n);
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
