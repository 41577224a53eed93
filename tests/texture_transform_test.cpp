// Which uv a texture reads: TEXCOORD_0 or TEXCOORD_1 (here as normalised UNSIGNED_SHORT), and
// KHR_texture_transform's offset, scale, rotation and texCoord override.
#include <doctest/doctest.h>

#include <cmath>

#include "dacrt/io/gltf.h"
#include "tests/temp_dir.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

TEST_CASE("textures: KHR_texture_transform and TEXCOORD_1, normalised integer uvs") {
  TempDir dir("transform");
  // TEXCOORD_1 as normalised UNSIGNED_SHORT: (x, y) themselves, so the image is upside down.
  const std::vector<uint16_t> uv1 = {0, 0, 65535, 0, 65535, 65535, 0, 65535};
  auto file = [&](const json& info) {
    GltfWriter w = quad_file({{"pbrMetallicRoughness", {{"baseColorTexture", info}}}});
    int a = w.add_accessor(w.add_view(uv1.data(), 16), kUnsignedShort, 4, "VEC2");
    w.doc["accessors"][a]["normalized"] = true;
    w.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = a;
    add_texture(w, png8(2, 2, 4, kTexels), kNearest);
    return w;
  };
  auto color_at = [](const Scene& scene, float x, float y) {
    return quad_surface(scene, x, y).brdf.base_color;
  };
  const glm::vec3 red(1, 0, 0), green(0, 1, 0), blue(0, 0, 1), grey(kGrey);

  Scene set1 = load_gltf(file({{"index", 0}, {"texCoord", 1}}).write_gltf(dir / "set1.gltf"));
  CHECK(set1.texcoords[0].empty());
  CHECK(near(color_at(set1, 0.25f, 0.25f), red));  // uv (0.25, 0.25)
  CHECK(near(color_at(set1, 0.25f, 0.75f), blue));

  // Offset by half the image in u: the left half shows the right half of the texture.
  json offset = {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0}}}}}}};
  Scene shifted = load_gltf(file(offset).write_gltf(dir / "offset.gltf"));
  CHECK(near(color_at(shifted, 0.25f, 0.75f), green));
  CHECK(near(color_at(shifted, 0.75f, 0.75f), red));  // wraps around

  // Scale 0.5 shows the top-left texel everywhere; the override picks TEXCOORD_1.
  json scale = {
      {"index", 0},
      {"extensions", {{"KHR_texture_transform", {{"scale", {0.5, 0.5}}, {"texCoord", 1}}}}}};
  Scene scaled = load_gltf(file(scale).write_gltf(dir / "scale.gltf"));
  for (float x : {0.1f, 0.9f})
    for (float y : {0.1f, 0.9f}) CHECK(near(color_at(scaled, x, y), red));

  // Rotation by +90° maps uv (u, v) to (v, −u) (the markers of Khronos' TextureTransformTest
  // fix the direction): the point with uv (0.25, 0.75) samples uv (0.75, −0.25) → (0.75, 0.75).
  json rotation = {{"index", 0},
                   {"extensions", {{"KHR_texture_transform", {{"rotation", M_PI / 2}}}}}};
  Scene rotated = load_gltf(file(rotation).write_gltf(dir / "rotation.gltf"));
  CHECK(near(color_at(rotated, 0.25f, 0.25f), grey));
  CHECK(near(color_at(rotated, 0.25f, 0.75f), blue));  // uv (0.25, 0.25) → (0.25, −0.25)
}
