// Texture extensions that give a texture another image (io/gltf/images.cpp, io/gltf/file.cpp):
// EXT_texture_webp's WebP is used whether or not the texture has a PNG or JPEG fallback (which is
// then never read), required or only used, embedded, in a bufferView or in a file; a WebP that
// is cut short, damaged or claims a huge size is one error naming the image. KHR_texture_basisu
// (KTX2, which this version cannot decode) renders from its fallback with one warning, and
// without a fallback it is refused naming the texture and the extension.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

#include "dacrt/io/gltf.h"
#include "tests/allocations.h"
#include "tests/captured_stderr.h"
#include "tests/cli.h"
#include "tests/gltf_check.h"
#include "tests/temp_dir.h"
#include "tests/texture_fixtures.h"
#include "tests/webp.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

// kTexels with its rows swapped: blue top-left, where kTexels is red.
std::vector<uint8_t> flipped_texels() {
  std::vector<uint8_t> t = kTexels;
  std::swap_ranges(t.begin(), t.begin() + 8, t.begin() + 8);
  return t;
}

// The quad's base colour at its top-left texel.
glm::vec3 top_left(const Scene& scene) {
  return quad_surface(scene, 0.25f, 0.75f).brdf.base_color;
}

const json kBaseColor = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};

// Writes `w` as .glb when its images are in bufferViews, else as .gltf.
std::string write(GltfWriter& w, const std::string& path, Embed embed) {
  return embed == Embed::buffer_view ? w.write_glb(path + ".glb") : w.write_gltf(path + ".gltf");
}

}  // namespace

TEST_CASE("EXT_texture_webp: the WebP is used, with or without a fallback, required or not") {
  TempDir dir("texture-webp");
  const std::vector<unsigned char> webp = webp_lossless(2, 2, kTexels);
  const std::vector<unsigned char> fallback = png8(2, 2, 4, flipped_texels());
  for (Embed embed : {Embed::data_uri, Embed::buffer_view, Embed::file}) {
    const std::string name = dir / ("embed" + std::to_string(int(embed)));
    CAPTURE(name);
    // With a PNG fallback, image 0, which a client without WebP would show (blue top-left).
    GltfWriter w = quad_file(kBaseColor);
    const int png = add_image(w, fallback, embed, dir.path());
    const int image = add_image(w, webp, embed, dir.path(), "image/webp");
    w.doc["textures"] = {
        {{"source", png}, {"extensions", {{"EXT_texture_webp", {{"source", image}}}}}}};
    w.doc["extensionsUsed"] = {"EXT_texture_webp"};
    const std::string with_fallback = write(w, name + "-fallback", embed);
    std::string err = stderr_of([&] {
      const Scene scene = load_gltf(with_fallback);
      CHECK(near(top_left(scene), glm::vec3(1, 0, 0)));  // red: the WebP
      CHECK(near(quad_surface(scene, 0.75f, 0.25f).brdf.base_color, glm::vec3(kGrey)));
      CHECK(scene.images[size_t(png)].width == 0);  // the fallback is never decoded
      CHECK(std::equal(kTexels.begin(), kTexels.end(), scene.images[size_t(image)].rgba8.begin(),
                       scene.images[size_t(image)].rgba8.end()));
    });
    CHECK(err == "");  // image/webp is a type this version decodes: no warning

    // No fallback: the extension is required, or only used (the spec asks for required then, but
    // a file that only lists it still renders here).
    w.doc["textures"] = {{{"extensions", {{"EXT_texture_webp", {{"source", image}}}}}}};
    for (const bool required : {true, false}) {
      if (required)
        w.doc["extensionsRequired"] = {"EXT_texture_webp"};
      else
        w.doc.erase("extensionsRequired");
      const std::string only = write(w, name + (required ? "-required" : "-used"), embed);
      err = stderr_of([&] { CHECK(near(top_left(load_gltf(only)), glm::vec3(1, 0, 0))); });
      CHECK(err == "");
    }
  }
}

TEST_CASE("EXT_texture_webp: the fallback image is never read") {
  TempDir dir("texture-webp-fallback");
  GltfWriter w = quad_file(kBaseColor);
  // The fallback is 2 GiB of holes, which a reader refuses by its size (over 1 GiB).
  write_text(dir / "fallback.png", "");
  std::filesystem::resize_file(dir / "fallback.png", uint64_t(2) << 30);
  w.doc["images"] = {{{"uri", "fallback.png"}}};
  const int image =
      add_image(w, webp_lossless(2, 2, kTexels), Embed::file, dir.path(), "image/webp");
  w.doc["textures"] = {
      {{"source", 0}, {"extensions", {{"EXT_texture_webp", {{"source", image}}}}}}};
  w.doc["extensionsUsed"] = {"EXT_texture_webp"};
  const Scene scene = load_gltf(w.write_gltf(dir / "webp.gltf"));
  CHECK(near(top_left(scene), glm::vec3(1, 0, 0)));
  // The same file without the extension reads the fallback, and refuses it.
  w.doc["textures"][0].erase("extensions");
  check_error(w.write_gltf(dir / "plain.gltf"), {"image 0 (fallback.png)", "2.0 GiB"});
}

TEST_CASE("EXT_texture_webp: a WebP cut short, damaged or claiming 2^28 texels is one error") {
  TempDir dir("texture-webp-errors");
  std::vector<uint8_t> noise;
  for (int i = 0; i < 32 * 32; ++i)
    noise.insert(noise.end(), {uint8_t(i * 7919 % 251), uint8_t(i * 31 % 253), uint8_t(i), 255});
  const std::vector<unsigned char> whole = webp_lossless(32, 32, noise);
  std::vector<unsigned char> damaged = whole;
  std::fill(damaged.begin() + 25, damaged.end(), 0xff);
  const struct {
    const char* name;
    std::vector<unsigned char> bytes;
    const char* says;
  } cases[] = {
      {"cut",
       {whole.begin(), whole.begin() + long(whole.size() / 2)},
       "invalid WebP data: the data ends before the image does (truncated file)"},
      {"damaged", damaged, "invalid WebP data: bitstream error"},
      {"huge", webp_resized(whole, 16384, 16384), "16384 x 16384 texels is more than 2^27"},
  };
  for (const auto& c : cases) {
    CAPTURE(c.name);
    // As the texture's WebP, with a PNG fallback that would load.
    for (Embed embed : {Embed::file, Embed::buffer_view}) {
      GltfWriter w = quad_file(kBaseColor);
      const int png = add_image(w, png8(2, 2, 4, kTexels), embed, dir.path());
      const int image = add_image(w, c.bytes, embed, dir.path(), "image/webp");
      w.doc["textures"] = {
          {{"source", png}, {"extensions", {{"EXT_texture_webp", {{"source", image}}}}}}};
      w.doc["extensionsUsed"] = {"EXT_texture_webp"};
      const std::string path = write(w, dir / c.name, embed);
      AllocationWatch watch;
      check_error(path, {embed == Embed::file ? "image 1 (image1.webp) cannot be decoded: "
                                              : "image 1 cannot be decoded: ",
                         c.says});
      CHECK(watch.peak() < (4u << 20));
    }
  }
  // The command line: one line, exit code 1.
  GltfWriter w = quad_file(kBaseColor);
  const int cut = add_image(w, cases[0].bytes, Embed::file, dir.path(), "image/webp");
  w.doc["textures"] = {{{"source", cut}}};
  const std::string path = w.write_gltf(dir / "cli.gltf");
  const Run r = run(dir, "info " + path);
  INFO(r.err);
  CHECK(r.code == 1);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK(has(r.err, path + ": image 0 (image0.webp) cannot be decoded: invalid WebP data"));
}

TEST_CASE("KHR_texture_basisu: textures with a fallback render from it, with one warning") {
  TempDir dir("texture-ktx2");
  for (Embed embed : {Embed::data_uri, Embed::buffer_view}) {
    CAPTURE(int(embed));
    // Texture 0 (base colour) and 1 (emissive): each a KTX2 image and a fallback, PNG and WebP.
    GltfWriter w = quad_file({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}},
                              {"emissiveFactor", {1, 1, 1}},
                              {"emissiveTexture", {{"index", 1}}}});
    const int ktx = add_image(w, ktx2(), embed, dir.path(), "image/ktx2");
    const int png = add_image(w, png8(2, 2, 4, kTexels), embed, dir.path());
    const int webp =
        add_image(w, webp_lossless(2, 2, flipped_texels()), embed, dir.path(), "image/webp");
    w.doc["textures"] = {
        {{"source", png}, {"extensions", {{"KHR_texture_basisu", {{"source", ktx}}}}}},
        {{"source", webp}, {"extensions", {{"KHR_texture_basisu", {{"source", ktx}}}}}}};
    w.doc["extensionsUsed"] = {"KHR_texture_basisu"};
    const std::string path = write(w, dir / "fallback", embed);
    Scene scene;
    const std::string err = stderr_of([&] { scene = load_gltf(path); });
    CHECK(err == "warning: " + path +
                     ": not rendered as specified in this version: 2 KHR_texture_basisu textures "
                     "(rendered from their fallback images: no KTX2 decoder)\n");
    CHECK(scene.ignored.ktx2_textures == 2);
    CHECK(scene.images[size_t(ktx)].width == 0);
    const SurfacePoint p = quad_surface(scene, 0.25f, 0.75f);
    CHECK(near(p.brdf.base_color, glm::vec3(1, 0, 0)));  // the PNG's red
    CHECK(near(p.emission, glm::vec3(0, 0, 1)));         // the WebP's blue

    // A texture with a WebP as well: that is what it shows, without a word.
    w.doc["textures"][0]["extensions"]["EXT_texture_webp"] = {{"source", webp}};
    w.doc["textures"][1] = {{"source", png}};
    const std::string both = write(w, dir / "both", embed);
    CHECK(stderr_of([&] { scene = load_gltf(both); }) == "");
    CHECK(near(quad_surface(scene, 0.25f, 0.75f).brdf.base_color, glm::vec3(0, 0, 1)));
  }
}

TEST_CASE(
    "KHR_texture_basisu: without a fallback to decode, the error names texture and extension") {
  TempDir dir("texture-ktx2-errors");
  GltfWriter w = quad_file(kBaseColor);
  const int ktx = add_image(w, ktx2(), Embed::buffer_view, dir.path(), "image/ktx2");
  w.doc["extensionsUsed"] = {"KHR_texture_basisu"};
  // No source, or the KTX2 image again as the source.
  w.doc["textures"] = {{{"extensions", {{"KHR_texture_basisu", {{"source", ktx}}}}}}};
  const std::vector<std::string> only = {
      "texture 0 has only a KHR_texture_basisu image (KTX2), and this version has no KTX2 decoder",
      "no PNG, JPEG or WebP source to fall back to"};
  for (const char* name : {"none.glb", "same.glb"}) {
    check_error(w.write_glb(dir / name), {only[0], only[1]});
    w.doc["textures"][0]["source"] = ktx;
  }
  // A fallback that is KTX2 too.
  const int other = add_image(w, ktx2(), Embed::buffer_view, dir.path(), "image/ktx2");
  w.doc["textures"][0]["source"] = other;
  check_error(w.write_glb(dir / "ktx2-fallback.glb"),
              {"image 1, the fallback of texture 0's KHR_texture_basisu image (this version has "
               "no KTX2 decoder), cannot be decoded: it is a KTX2 (KHR_texture_basisu) image"});
  // Required: refused from the schema.
  w.doc["textures"][0]["source"] = ktx;
  w.doc["extensionsRequired"] = {"KHR_texture_basisu"};
  check_error(w.write_glb(dir / "required.glb"),
              {"/extensionsRequired/0", "KHR_texture_basisu", "no KTX2 decoder"});
}
