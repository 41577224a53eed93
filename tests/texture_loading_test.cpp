// The glTF loader's images (io/gltf/images.cpp): images no used material samples are never
// decoded, copies of one image are decoded once, the decoded size of all images is bounded before
// any is decoded, a broken texture is one error naming the file and the element, and the textured
// scenes of ../shared load with their images, uvs and tangents.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

#include "dacrt/io/gltf.h"
#include "tests/captured_stderr.h"
#include "tests/gltf_check.h"
#include "tests/temp_dir.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

TEST_CASE("textures: images no used material samples are never decoded, copies once") {
  TempDir dir("unused-images");
  GltfWriter w = quad_file(json::object());
  w.doc["images"] = {{{"uri", "missing.png"}}, {{"uri", "data:image/png;base64,AAAA"}}};
  w.doc["textures"] = {{{"source", 0}}, {{"source", 1}}};
  // A material that samples them, but that no primitive uses.
  w.add_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}});
  const Scene scene = load_gltf(w.write_gltf(dir / "unused.gltf"));
  CHECK(scene.geometry.size() == 2);
  CHECK(scene.images.size() == 2);
  CHECK(scene.images[0].width == 0);

  // Images 0-7 on one bufferView, 8 and 9 data URIs with the same bytes: two decodes. Material 0
  // samples textures 0 and 7, material 1 textures 8 and 9.
  const json emissive = {1, 1, 1};
  GltfWriter copies = quad_file({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 7}}}}},
                                 {"emissiveFactor", emissive},
                                 {"emissiveTexture", {{"index", 0}}}});
  const std::vector<unsigned char> png = png8(2, 2, 4, kTexels);
  std::vector<uint8_t> flipped = kTexels;  // the rows swapped: blue top-left
  std::swap_ranges(flipped.begin(), flipped.begin() + 8, flipped.begin() + 8);
  const std::vector<unsigned char> other = png8(2, 2, 4, flipped);
  for (int k = 0; k < 8; ++k) add_texture(copies, png, nullptr, Embed::buffer_view);
  for (auto& image : copies.doc["images"])
    image["bufferView"] = copies.doc["images"][0]["bufferView"];
  add_texture(copies, other);
  add_texture(copies, other);
  copies.add_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 9}}}}},
                       {"emissiveFactor", emissive},
                       {"emissiveTexture", {{"index", 8}}}});
  json second = copies.doc["meshes"][0]["primitives"][0];
  second["material"] = 1;
  copies.doc["meshes"][0]["primitives"].push_back(second);
  const Scene deduped = load_gltf(copies.write_glb(dir / "copies.glb"));
  size_t decoded = 0;
  for (const TextureImage& i : deduped.images) decoded += i.width > 0;
  CHECK(decoded == 2);
  CHECK(deduped.textures[7].image == deduped.textures[0].image);
  CHECK(deduped.textures[9].image == deduped.textures[8].image);
  CHECK(deduped.textures[8].image != deduped.textures[0].image);
  // The point (0.25, 0.75) of triangle 1 (of 3 for material 1): top-left, red in the first image,
  // blue in the other.
  CHECK(near(surface_at(deduped, 1, 0.25f, 0.5f, glm::vec3(0, 0, 1)).brdf.base_color,
             glm::vec3(1, 0, 0)));
  CHECK(near(surface_at(deduped, 3, 0.25f, 0.5f, glm::vec3(0, 0, 1)).brdf.base_color,
             glm::vec3(0, 0, 1)));
}

TEST_CASE("texture errors: the decoded size of all images is bounded before decoding") {
  TempDir dir("image-budget");
  GltfWriter w = quad_file({{"emissiveFactor", {1, 1, 1}}});
  // Five different 16-bit PNGs whose headers claim 11000 × 11000 texels: 968 MB each decoded.
  for (int k = 0; k < 5; ++k) {
    const std::vector<unsigned char> png =
        png_resized(png16_rgb(1, 1, {uint16_t(k), 2, 3}), 11000, 11000);
    add_texture(w, png);
    w.add_material({{"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", {{"index", k}}}});
    json primitive = w.doc["meshes"][0]["primitives"][0];
    primitive["material"] = k + 1;
    w.doc["meshes"][0]["primitives"].push_back(primitive);
  }
  check_error(w.write_gltf(dir / "huge.gltf"), {"images would take", "MiB limit"});
  // Five copies of one such image count once: within the budget, they fail only at decoding
  // (their data is not 11000² texels).
  for (auto& image : w.doc["images"]) image = w.doc["images"][0];
  check_error(w.write_gltf(dir / "copies.gltf"), {"image 0", "cannot be decoded"});
}

TEST_CASE("texture errors name the file and the element") {
  TempDir dir("texture-errors");
  auto textured = [&](json info = {{"index", 0}}) {
    return quad_file({{"pbrMetallicRoughness", {{"baseColorTexture", info}}}});
  };
  {
    GltfWriter w = textured();
    w.doc["images"] = {{{"uri", "missing.png"}}};
    w.doc["textures"] = {{{"source", 0}}};
    check_error(w.write_gltf(dir / "missing.gltf"), {"image 0", "missing.png", "cannot be read"});
    w.doc["images"] = {{{"uri", "data:image/png;base64,AAAAAAAA"}}};
    check_error(w.write_gltf(dir / "garbage.gltf"), {"image 0", "cannot be decoded"});
    w.doc["textures"] = {{{"source", 3}}};
    check_error(w.write_gltf(dir / "source.gltf"), {"/textures/0/source", "3"});
  }
  {
    // A texture without a source image (valid; the spec leaves what it shows undefined) is not
    // sampled, with a warning: the material renders by its factors.
    GltfWriter w = textured();
    add_texture(w, png8(2, 2, 4, kTexels));
    w.doc["textures"] = {json::object()};
    CapturedStderr err;
    const Scene scene = load_gltf(w.write_gltf(dir / "no-source.gltf"));
    const std::string text = err.text();
    CHECK_FALSE(scene.materials[0].base_color_texture);
    CHECK(scene.ignored.sourceless_textures == 1);
    CHECK(text.find("1 textures without a source image (materials rendered without them)") !=
          std::string::npos);
  }
  {
    GltfWriter w = textured({{"index", 4}});
    check_error(w.write_gltf(dir / "index.gltf"),
                {"/materials/0/pbrMetallicRoughness/baseColorTexture/index", "4"});
  }
  {
    // A set the primitive lacks is refused where a primitive samples it, not in a material no
    // primitive uses (gltf_texcoord_sets_test.cpp reads the sets a primitive has).
    GltfWriter w = textured({{"index", 0}, {"texCoord", 2}});
    add_texture(w, png8(2, 2, 4, kTexels));
    check_error(w.write_gltf(dir / "texcoord.gltf"),
                {"mesh 0 primitive 0", "samples TEXCOORD_2", "which the primitive does not have"});
    w.doc["materials"].push_back(w.doc["materials"][0]);
    w.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 0;
    CHECK(load_gltf(w.write_gltf(dir / "texcoord-unused.gltf")).materials.size() == 2);
    // A set the primitive does not have (the validator's MESH_PRIMITIVE_TOO_FEW_TEXCOORDS).
    w.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1;
    check_error(w.write_gltf(dir / "texcoord-missing.gltf"),
                {"mesh 0 primitive 0", "samples TEXCOORD_1", "which the primitive does not have"});
  }
  {
    GltfWriter w = textured();
    add_texture(w, png8(2, 2, 4, kTexels), {{"wrapS", 1234}});
    check_error(w.write_gltf(dir / "wrap.gltf"), {"/samplers/0/wrapS", "1234"});
  }
  {
    GltfWriter w = textured(
        {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {1, "x"}}}}}}});
    add_texture(w, png8(2, 2, 4, kTexels));
    check_error(w.write_gltf(dir / "transform.gltf"), {"KHR_texture_transform", "scale"});
  }
  {
    GltfWriter w = textured();
    const std::vector<unsigned char> png = png8(2, 2, 4, kTexels);
    add_texture(w, png, nullptr, Embed::buffer_view);
    w.doc["bufferViews"].back()["byteLength"] = 100000;  // past the buffer
    check_error(w.write_glb(dir / "overrun.glb"), {"image 0", "overruns buffer"});
  }
  {
    GltfWriter w = textured();
    add_texture(w, png8(2, 2, 4, kTexels));
    const std::vector<uint8_t> uv(8, 0);
    w.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] =
        w.add_accessor(w.add_view(uv.data(), 8), kUnsignedByte, 4, "VEC2");
    check_error(w.write_gltf(dir / "uv-normalized.gltf"), {"TEXCOORD_0", "normalized"});
    const std::vector<glm::vec2> three(3, glm::vec2(0.f));
    w.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] =
        w.add_accessor(w.add_view(three.data(), 24), kFloat, 3, "VEC2");
    check_error(w.write_gltf(dir / "uv-count.gltf"), {"TEXCOORD_0", "3 elements"});
  }
}

TEST_CASE("textured scenes of ../shared load with their images, uvs and tangents") {
  const std::filesystem::path root = DACRT_SOURCE_DIR "/../shared/scenes/khronos";
  if (!std::filesystem::exists(root)) {
    MESSAGE("../shared/scenes is absent: skipped");
    return;
  }
  const Scene helmet = load_gltf((root / "DamagedHelmet/DamagedHelmet.glb").string());
  size_t decoded = 0;
  for (const TextureImage& i : helmet.images) decoded += i.width == 2048;
  CHECK(decoded == 4);  // baseColor, metal-rough, normal, emissive; occlusion is not decoded
  CHECK(helmet.tangents.size() == 3 * helmet.geometry.size());  // generated: the file has none
  size_t made = 0;
  for (const glm::vec4& t : helmet.tangents) made += t.w != 0.f;
  CHECK(made > helmet.tangents.size() * 99 / 100);
  const Scene bottle = load_gltf((root / "WaterBottle/WaterBottle.gltf").string());
  CHECK(bottle.tangents.size() == 3 * bottle.geometry.size());  // from the file
  CHECK(!bottle.texcoords[0].empty());
}
