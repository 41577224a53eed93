// Decoding of glTF images (PNG through libpng, JPEG through libjpeg-turbo, WebP through libwebp)
// into textures.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "dacrt/materials/texture.h"

namespace dacrt {

// The image in `bytes`, as RGBA with 8 or 16 bits per channel (16 only for 16-bit PNGs). Throws
// Error("<what> cannot be decoded: <reason>") for data that is not a whole, valid PNG, JPEG or
// still WebP (whatever the mimeType says), or one larger than 2^27 texels. Thread-safe.
TextureImage decode_image(const unsigned char* bytes, size_t size, const std::string& what);

// The bytes decode_image will keep for this image, read from its header (the same errors).
uint64_t decoded_size(const unsigned char* bytes, size_t size, const std::string& what);

}  // namespace dacrt
