// Textures: decoded glTF images and the samplers that read them. Texels are kept as the file
// stored them (8 or 16 bits, expanded to RGBA) and turned into floats per lookup: colour textures
// (baseColor, emissive) are sRGB-decoded texel by texel before bilinear filtering, data textures
// (metallic-roughness, normal) are read linearly. No mipmaps: a path tracer's many samples per
// pixel average a minified texture over the pixel anyway.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "dacrt/util/large_array.h"

namespace dacrt {

// A decoded image: RGBA, row-major from the top-left texel (glTF's uv (0, 0)).
struct TextureImage {
  int width = 0, height = 0;
  // Exactly one of the two is filled, on huge pages: lookups land at random points of images of
  // up to 2^27 texels, which on 4 KiB pages missed the TLB on most texels.
  Array<uint8_t> rgba8;    // 8-bit images
  Array<uint16_t> rgba16;  // 16-bit images (PNG)

  // Texel (x, y) in [0, 1], sRGB-decoded to linear when `srgb` (alpha never is).
  glm::vec4 texel(int x, int y, bool srgb) const;
};

// glTF sampler wrap modes (10497, 33071, 33648).
enum class Wrap : uint8_t { repeat, clamp, mirror };

// A glTF texture: an image and how to sample it.
struct Texture {
  uint32_t image = 0;  // into Scene::images
  Wrap wrap_s = Wrap::repeat, wrap_t = Wrap::repeat;
  bool nearest = false;  // magFilter NEAREST; otherwise bilinear
};

// A material's use of a texture (glTF textureInfo with KHR_texture_transform): which texture,
// which TEXCOORD set, and the affine uv transform (offset · rotation · scale).
struct TextureRef {
  int32_t texture = -1;  // into Scene::textures; -1: none
  // Which of Scene::texcoords: TEXCOORD_0 and _1 are 0 and 1, later sets as the loader numbers
  // them (Scene::texcoord_sets says which set each is).
  uint32_t texcoord = 0;
  glm::mat3x2 transform{1.f};

  explicit operator bool() const { return texture >= 0; }
  glm::vec2 apply(const glm::vec2& uv) const { return transform * glm::vec3(uv, 1.f); }
};

// The filtered value at uv (glTF convention: u right, v down, (0, 0) the image's top-left corner).
glm::vec4 sample(const TextureImage& image, const Texture& texture, glm::vec2 uv, bool srgb);

// Asks the cache for the texels sample() would read at uv, without waiting for them: shading
// calls it for the hits it shades next (textures of tens of MiB miss the cache at every lookup).
void prefetch(const TextureImage& image, const Texture& texture, glm::vec2 uv);

// sRGB transfer function, decoding (IEC 61966-2-1).
float srgb_to_linear(float c);

}  // namespace dacrt
