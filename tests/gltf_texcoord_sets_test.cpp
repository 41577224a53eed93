// Any TEXCOORD_n a material samples (the spec allows any n): each set's texture coordinates reach
// the texture lookups that name it, TEXCOORD_3 as well as TEXCOORD_0; the sets the scene keeps are
// numbered as materials name them, so a set number of two billion costs one set, not two billion.
#include <doctest/doctest.h>

#include "dacrt/io/gltf.h"
#include "tests/gltf_check.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

// A 4 × 1 image: red, green, blue, white; texel k is at u = (k + 0.5) / 4.
const std::vector<uint8_t> kFour = {255, 0, 0,   255, 0,   255, 0,   255,
                                    0,   0, 255, 255, 255, 255, 255, 255};
const glm::vec3 kColours[4] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};

// The unit quad whose TEXCOORD_k (k = 0..3, every vertex alike) points at texel k, and whose
// material's base colour texture (nearest) is `texture_info`.
GltfWriter four_sets(const json& texture_info) {
  GltfWriter w = quad_file({{"pbrMetallicRoughness", {{"baseColorTexture", texture_info}}}});
  json& attributes = w.doc["meshes"][0]["primitives"][0]["attributes"];
  for (int k = 0; k < 4; ++k) {
    const std::vector<glm::vec2> uv(4, glm::vec2((k + 0.5f) / 4.f, 0.5f));
    attributes["TEXCOORD_" + std::to_string(k)] =
        w.add_accessor(w.add_view(uv.data(), 32), kFloat, 4, "VEC2");
  }
  add_texture(w, png8(4, 1, 4, kFour), kNearest);
  return w;
}

glm::vec3 colour_at_middle(const Scene& scene) {
  return quad_surface(scene, 0.6f, 0.3f).brdf.base_color;
}

}  // namespace

TEST_CASE("TEXCOORD sets: a texture on TEXCOORD_2 or TEXCOORD_3 shows that set's texels") {
  TempDir dir("gltf-texcoord-sets");
  for (int set = 0; set < 4; ++set) {
    INFO("texCoord " << set);
    const Scene scene = load_gltf(four_sets({{"index", 0}, {"texCoord", set}})
                                      .write_gltf(dir / ("set" + std::to_string(set) + ".gltf")));
    CHECK(near(colour_at_middle(scene), kColours[set]));
  }
  // KHR_texture_transform's texCoord overrides the textureInfo's: set 3 again.
  GltfWriter w =
      four_sets({{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 3}}}}}});
  w.doc["extensionsUsed"] = {"KHR_texture_transform"};
  const Scene transformed = load_gltf(w.write_gltf(dir / "transform.gltf"));
  CHECK(near(colour_at_middle(transformed), kColours[3]));
  CHECK(transformed.texcoord_sets == std::vector<uint32_t>{0, 1, 3});
  CHECK(transformed.texcoords[0].empty());  // only set 3 is sampled, and kept
  CHECK(transformed.texcoords[2].size() == 6);
}

TEST_CASE("TEXCOORD sets: numbered as materials name them, bounded by the file's references") {
  TempDir dir("gltf-texcoord-numbers");
  // Material 0 (no primitive uses it) names set 5 first; the primitive's material 1 samples set 3:
  // the kept streams are 0, 1 (TEXCOORD_0 and _1, empty), 5 (empty) and 3.
  GltfWriter w = four_sets({{"index", 0}, {"texCoord", 5}});
  w.add_material(
      {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 3}}}}}});
  w.doc["meshes"][0]["primitives"][0]["material"] = 1;
  const Scene scene = load_gltf(w.write_gltf(dir / "numbers.gltf"));
  CHECK(scene.texcoord_sets == std::vector<uint32_t>{0, 1, 5, 3});
  REQUIRE(scene.texcoords.size() == 4);
  CHECK(scene.texcoords[2].empty());
  CHECK(scene.texcoords[3].size() == 6);
  CHECK(scene.materials[1].base_color_texture.texcoord == 3u);  // the slot of set 3
  CHECK(near(quad_surface(scene, 0.6f, 0.3f).brdf.base_color, kColours[3]));

  // TEXCOORD_2000000000: one more set, read like any other.
  GltfWriter big = four_sets({{"index", 0}, {"texCoord", 2000000000}});
  json& attributes = big.doc["meshes"][0]["primitives"][0]["attributes"];
  attributes["TEXCOORD_2000000000"] = attributes["TEXCOORD_2"];
  const Scene far = load_gltf(big.write_gltf(dir / "big.gltf"));
  CHECK(far.texcoord_sets == std::vector<uint32_t>{0, 1, 2000000000});
  CHECK(far.texcoords.size() == 3);
  CHECK(near(colour_at_middle(far), kColours[2]));
  // A set the primitive lacks is refused, naming it.
  attributes.erase("TEXCOORD_2000000000");
  check_error(
      big.write_gltf(dir / "missing.gltf"),
      {"mesh 0 primitive 0", "samples TEXCOORD_2000000000", "which the primitive does not have"});
}
