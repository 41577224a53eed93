// Image decoding (io/texture_decode.cpp) as a whole: PNGs, JPEGs and WebPs decode to 8- or 16-bit
// RGBA, a bad file is one error naming the image, and every other format is refused by its
// signature (among them the files stb_image hung or overran on), in the loader and the command
// line too.
// The PNG, JPEG and WebP decoders in detail: png_decode_test.cpp, jpeg_decode_test.cpp,
// webp_decode_test.cpp.
#include "dacrt/io/texture_decode.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

#include "tests/cli.h"
#include "tests/gltf_check.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;

TEST_CASE("texture images: 8- and 16-bit PNGs and JPEGs decode to RGBA, bad data is one error") {
  const TextureImage rgb = decode_image(png8(2, 1, 3, {10, 20, 30, 40, 50, 60}).data(),
                                        png8(2, 1, 3, {10, 20, 30, 40, 50, 60}).size(), "x");
  CHECK(rgb.width == 2);
  CHECK(rgb.height == 1);
  CHECK(std::vector<uint8_t>(rgb.rgba8.begin(), rgb.rgba8.end()) ==
        std::vector<uint8_t>{10, 20, 30, 255, 40, 50, 60, 255});

  const std::vector<unsigned char> wide = png16_rgb(1, 2, {0, 32768, 65535, 1, 2, 3});
  const TextureImage deep = decode_image(wide.data(), wide.size(), "x");
  REQUIRE(deep.rgba16.size() == 8);
  CHECK(deep.rgba8.empty());
  CHECK(deep.texel(0, 0, false) == glm::vec4(0.f, 32768.f / 65535.f, 1.f, 1.f));
  CHECK(deep.texel(0, 1, false).b == 3.f / 65535.f);
  CHECK(deep.texel(0, 0, true).g == doctest::Approx(srgb_to_linear(32768.f / 65535.f)));

  // JPEG: a flat 16 × 16 colour comes back within a step or two of its bytes (lossy).
  const std::vector<uint8_t> flat = [] {
    std::vector<uint8_t> t;
    for (int i = 0; i < 256; ++i) t.insert(t.end(), {200, 100, 50});
    return t;
  }();
  const std::vector<unsigned char> jpg = jpeg(16, 16, 3, flat);
  const TextureImage photo = decode_image(jpg.data(), jpg.size(), "x");
  REQUIRE(photo.width == 16);
  REQUIRE(photo.rgba8.size() == 4 * 256);
  const glm::vec4 c = photo.texel(7, 9, false) * 255.f;
  CHECK(std::abs(c.r - 200.f) <= 2.f);
  CHECK(std::abs(c.g - 100.f) <= 2.f);
  CHECK(std::abs(c.b - 50.f) <= 2.f);
  CHECK(c.a == 255.f);

  auto error = [](const std::vector<unsigned char>& bytes) {
    try {
      decode_image(bytes.data(), bytes.size(), "file.gltf: image 3");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error({1, 2, 3, 4, 5, 6, 7, 8}).find("file.gltf: image 3 cannot be decoded") == 0);
  CHECK(error({}).find("image 3 cannot be decoded") != std::string::npos);
  // A PNG header claiming 12000 × 12000 texels: refused before any allocation.
  const std::vector<unsigned char> huge = png_resized(png16_rgb(1, 1, {1, 2, 3}), 12000, 12000);
  INFO(error(huge));
  CHECK(error(huge).find("2^27") != std::string::npos);
}

namespace {

// 58 bytes of Radiance HDR whose one scanline (16 texels, run-length coded) ends after its first
// run: stb_image 2.27 loops forever on it.
std::vector<unsigned char> truncated_hdr() {
  std::vector<unsigned char> hdr = bytes_of("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 16\n");
  hdr.insert(hdr.end(), {2, 2, 0, 16, 0x88, 5, 0, 0, 0, 0, 0, 0});
  REQUIRE(hdr.size() == 58);
  return hdr;
}

// A binary PGM (P5) of size × size texels with 16-bit samples, which stb_image 2.27 decodes into a
// buffer of half the size it reports.
std::vector<unsigned char> pgm16(int size) {
  std::vector<unsigned char> pgm =
      bytes_of("P5\n" + std::to_string(size) + " " + std::to_string(size) + "\n65535\n");
  for (size_t i = 0; i < 2 * size_t(size) * size_t(size); ++i) pgm.push_back(uint8_t(i * 7));
  return pgm;
}

// 2 × 2 RGB images that stb_image decodes: BMP and TGA (run-length coded) by stb_image_write, GIF
// and Photoshop written here.
std::vector<unsigned char> bmp() {
  std::vector<unsigned char> out;
  stbi_write_bmp_to_func(append_bytes, &out, 2, 2, 3, kTexels.data());
  return out;
}
std::vector<unsigned char> tga() {
  std::vector<unsigned char> out;
  stbi_write_tga_to_func(append_bytes, &out, 2, 2, 3, kTexels.data());
  return out;
}
std::vector<unsigned char> gif() {  // 1 × 1, a two-colour table, LZW of one index
  return {'G', 'I',  'F', '8', '9', 'a', 1, 0, 1, 0, 0x80, 0, 0, 255,  0, 0, 0,   0,
          255, 0x2c, 0,   0,   0,   0,   1, 0, 1, 0, 0,    2, 2, 0x44, 1, 0, 0x3b};
}
std::vector<unsigned char> psd() {  // 1 × 1 RGB, raw
  std::vector<unsigned char> out = bytes_of("8BPS");
  out.insert(out.end(), {0, 1, 0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 0, 1, 0, 0, 0, 1, 0, 8, 0, 3});
  out.insert(out.end(), {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 10, 20, 30});
  return out;
}

}  // namespace

TEST_CASE("image formats: only PNG, JPEG and WebP are decoded, others are refused by signature") {
  const struct {
    const char* name;
    std::vector<unsigned char> bytes;
    const char* says;
  } cases[] = {
      {"truncated Radiance HDR", truncated_hdr(), "is a Radiance HDR image, not PNG, JPEG or WebP"},
      {"16-bit PGM, 16 x 16", pgm16(16), "is a Netpbm"},
      {"16-bit PGM, 2048 x 2048", pgm16(2048), "is a Netpbm"},
      {"BMP", bmp(), "is a BMP image"},
      {"GIF", gif(), "is a GIF image"},
      {"PSD", psd(), "is a Photoshop (PSD) image"},
      // TGA has no signature: stb_image decodes whatever its header checks let through.
      {"TGA", tga(),
       "its first bytes (00 00 0a 00 00 00 00 00) are not a PNG, JPEG or WebP signature"},
      {"eight bytes", {1, 2, 3, 4, 5, 6, 7, 8}, "its first bytes (01 02 03 04 05 06 07 08)"},
      {"two bytes", {0xff, 0xd8}, "is a damaged JPEG"},
      {"KTX2", ktx2(), "is a KTX2 (KHR_texture_basisu) image"},
  };
  for (const auto& c : cases) {
    INFO(c.name);
    const std::string e = decode_error(c.bytes);
    INFO(e);
    CHECK(e.rfind("x.png cannot be decoded: ", 0) == 0);
    CHECK(has(e, c.says));
    CHECK(has(e, "(only PNG, JPEG and WebP are supported)"));
    CHECK(!has(e, "\n"));
    CHECK_THROWS_WITH_AS(decoded_size(c.bytes.data(), c.bytes.size(), "x.png"), e.c_str(), Error);
  }
}

TEST_CASE("image formats: the truncated HDR labelled image/png fails at once, loader and CLI") {
  TempDir dir("hdr-as-png");
  GltfWriter w = quad_file({{"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", {{"index", 0}}}});
  add_texture(w, truncated_hdr(), kNearest, Embed::buffer_view);  // mimeType image/png
  const std::string glb = w.write_glb(dir / "hdr.glb");
  GltfWriter uri = quad_file({{"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", {{"index", 0}}}});
  add_texture(uri, truncated_hdr());  // data:image/png;base64,...
  const std::string gltf = uri.write_gltf(dir / "hdr.gltf");
  // Through the command line first: with stb_image both hang (and are killed after 60 s).
  for (const std::string& path : {glb, gltf})
    for (const std::string& command :
         {"info " + path, "render " + path + " -o " + (dir / "out.exr") + " --spp 1"}) {
      INFO(command);
      const Run r = run(dir, command, "timeout 60");  // killed after 60 s: exit code 124
      INFO(r.err);
      CHECK(r.code == 1);
      CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
      CHECK(has(r.err, path + ": image 0 cannot be decoded: it is a Radiance HDR image"));
      CHECK(!std::filesystem::exists(dir / "out.exr"));
    }
  check_error(glb, {"image 0 cannot be decoded", "Radiance HDR", "only PNG, JPEG and WebP"});
  check_error(gltf, {"image 0 cannot be decoded", "Radiance HDR", "only PNG, JPEG and WebP"});
}
