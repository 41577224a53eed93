// Textures: the sampler (filtering, wrap modes, sRGB), image decoding, and the loader's texture
// features end to end through surface_at (what the path tracer shades with): baseColor with
// alpha, metallic-roughness, emissive, normal maps with file and generated tangents, vertex
// colours, TEXCOORD_0/1, KHR_texture_transform, normalised integer attributes, and the errors
// a broken texture gives. Image decoding: the formats refused by their signature (among them the
// files stb_image hung or overran on), PNG's colour types, bit depths and interlacing, JPEG's
// colour spaces, and the bounds on broken, truncated and bomb files.
#include "materials/texture.h"

#include <doctest/doctest.h>
#include <sys/wait.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>

#include "integrators/integrator.h"
#include "io/texture_decode.h"
#include "scene/surface.h"
#include "render/render_job.h"
#include "tests/allocations.h"
#include "tests/gltf_check.h"
#include "tests/gltf_writer.h"
#include "tests/png.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

bool near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) {
  return glm::all(glm::lessThanEqual(glm::abs(a - b), glm::vec3(eps)));
}

// 2 × 2 RGBA: red, half-transparent green / blue, grey 188 (sRGB 188 is linear 0.5029).
const std::vector<uint8_t> kTexels = {255, 0, 0,   255, 0,   255, 0,   128,
                                      0,   0, 255, 255, 188, 188, 188, 255};
const float kGrey = srgb_to_linear(188.f / 255.f);

TextureImage image2x2() {
  TextureImage image;
  image.width = image.height = 2;
  image.rgba8 = kTexels;
  return image;
}

// A unit quad in z = 0 facing +z, triangles (0, 1, 2) and (0, 2, 3) over the corners (0, 0),
// (1, 0), (1, 1), (0, 1), with TEXCOORD_0 = (x, 1 − y) (the image upright) and material 0.
// `attributes` adds or replaces attributes.
GltfWriter quad_file(const json& material, json attributes = json::object()) {
  GltfWriter w;
  const std::vector<glm::vec3> corners = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<glm::vec2> uv = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  json attr = {{"POSITION", w.add_vec3(corners)},
               {"TEXCOORD_0", w.add_accessor(w.add_view(uv.data(), 32), kFloat, 4, "VEC2")}};
  attr.update(attributes);
  w.add_material(material);
  int indices = w.add_indices(std::vector<uint8_t>{0, 1, 2, 0, 2, 3});
  int mesh = w.add_mesh({{"attributes", attr}, {"indices", indices}, {"material", 0}});
  w.set_scene({w.add_node({{"mesh", mesh}})});
  return w;
}

enum class Embed { data_uri, buffer_view, file };

// Adds `png` as image + texture (with `sampler` unless null); returns the texture index.
int add_texture(GltfWriter& w, const std::vector<unsigned char>& png, json sampler = nullptr,
                Embed embed = Embed::data_uri, const std::string& dir = "") {
  json image;
  if (embed == Embed::data_uri) {
    image = {{"uri", "data:image/png;base64," + base64(png)}};
  } else if (embed == Embed::buffer_view) {
    image = {{"bufferView", w.add_view(png.data(), png.size())}, {"mimeType", "image/png"}};
  } else {
    const std::string name = "image" + std::to_string(w.doc["images"].size()) + ".png";
    write_bytes(dir + "/" + name, png.data(), png.size());
    image = {{"uri", name}};
  }
  w.doc["images"].push_back(image);
  json texture = {{"source", w.doc["images"].size() - 1}};
  if (!sampler.is_null()) {
    w.doc["samplers"].push_back(sampler);
    texture["sampler"] = w.doc["samplers"].size() - 1;
  }
  w.doc["textures"].push_back(texture);
  return int(w.doc["textures"].size()) - 1;
}

const json kNearest = {{"magFilter", 9728}, {"minFilter", 9728}};

// The point (x, y) of the quad: its triangle and barycentrics there.
struct QuadPoint {
  uint32_t tri;
  float u, v;
};
QuadPoint quad_point(const Scene& scene, float x, float y) {
  REQUIRE(scene.geometry.size() == 2);
  return x >= y ? QuadPoint{0, x - y, y} : QuadPoint{1, x, y - x};
}

// The surface of the quad at (x, y).
SurfacePoint quad_surface(const Scene& scene, float x, float y) {
  const QuadPoint p = quad_point(scene, x, y);
  return surface_at(scene, p.tri, p.u, p.v, glm::vec3(0, 0, 1));
}

// Its alpha there (what the hit filter tests).
float quad_alpha(const Scene& scene, float x, float y) {
  const QuadPoint p = quad_point(scene, x, y);
  return alpha_at(scene, p.tri, p.u, p.v);
}

}  // namespace

TEST_CASE("texture sampling: nearest and bilinear, sRGB per texel, wrap modes") {
  // The sRGB curve's known values: 188 → 0.5029, 0.5 → 0.2140, linear below 0.04045.
  CHECK(kGrey == doctest::Approx(0.50289).epsilon(1e-4));
  CHECK(srgb_to_linear(0.5f) == doctest::Approx(0.21404).epsilon(1e-4));
  CHECK(srgb_to_linear(0.04f) == doctest::Approx(0.04f / 12.92f));
  const TextureImage image = image2x2();
  Texture t;
  t.nearest = true;
  // uv (0, 0) is the image's top-left corner.
  CHECK(sample(image, t, {0.25f, 0.25f}, false) == glm::vec4(1, 0, 0, 1));
  CHECK(sample(image, t, {0.75f, 0.25f}, false) == glm::vec4(0, 1, 0, 128.f / 255.f));
  CHECK(sample(image, t, {0.25f, 0.75f}, false) == glm::vec4(0, 0, 1, 1));
  CHECK(sample(image, t, {0.75f, 0.75f}, true) == glm::vec4(kGrey, kGrey, kGrey, 1));

  t.nearest = false;
  // At a texel centre bilinear filtering returns the texel; at the middle, the mean of the four
  // texels after sRGB decoding (not the decoded mean of the bytes).
  CHECK(sample(image, t, {0.75f, 0.75f}, true) == glm::vec4(kGrey, kGrey, kGrey, 1));
  const glm::vec4 mid = sample(image, t, {0.5f, 0.5f}, true);
  CHECK(mid.r == doctest::Approx((1.f + kGrey) / 4));
  CHECK(mid.a == doctest::Approx((3.f + 128.f / 255.f) / 4));
  // Halfway between the two top texels, a quarter of the way down from the top edge: with
  // repeat, the top row blends with the bottom row (the texel above wraps around).
  const glm::vec4 edge = sample(image, t, {0.5f, 0.0f}, false);
  CHECK(edge.r == doctest::Approx(0.25f * (1.f + 0.f + 0.f + 188.f / 255.f)));
  t.wrap_t = Wrap::clamp;
  CHECK(sample(image, t, {0.5f, 0.0f}, false).r == doctest::Approx(0.5f));

  t.nearest = true;
  t.wrap_s = t.wrap_t = Wrap::repeat;
  CHECK(sample(image, t, {1.25f, 0.25f}, false) == sample(image, t, {0.25f, 0.25f}, false));
  CHECK(sample(image, t, {-0.75f, 2.25f}, false) == sample(image, t, {0.25f, 0.25f}, false));
  t.wrap_s = Wrap::mirror;
  CHECK(sample(image, t, {1.25f, 0.25f}, false) == sample(image, t, {0.75f, 0.25f}, false));
  CHECK(sample(image, t, {2.25f, 0.25f}, false) == sample(image, t, {0.25f, 0.25f}, false));
  CHECK(sample(image, t, {-0.25f, 0.25f}, false) == sample(image, t, {0.25f, 0.25f}, false));
  t.wrap_s = Wrap::clamp;
  CHECK(sample(image, t, {7.f, 0.25f}, false) == sample(image, t, {0.75f, 0.25f}, false));
  CHECK(sample(image, t, {-7.f, 0.25f}, false) == sample(image, t, {0.25f, 0.25f}, false));

  // Coordinates far out or not numbers still give a texel, never an out-of-bounds read.
  for (Wrap wrap : {Wrap::repeat, Wrap::mirror, Wrap::clamp})
    for (bool nearest : {true, false})
      for (float u : {1e30f, -1e30f, INFINITY, NAN, 16777217.f}) {
        t.wrap_s = t.wrap_t = wrap;
        t.nearest = nearest;
        const glm::vec4 c = sample(image, t, {u, u}, false);
        CHECK((std::isfinite(c.r) && c.r >= 0.f && c.r <= 1.f));
      }
}

TEST_CASE("texture images: 8- and 16-bit PNGs and JPEGs decode to RGBA; bad data is one error") {
  const TextureImage rgb = decode_image(png8(2, 1, 3, {10, 20, 30, 40, 50, 60}).data(),
                                        png8(2, 1, 3, {10, 20, 30, 40, 50, 60}).size(), "x");
  CHECK(rgb.width == 2);
  CHECK(rgb.height == 1);
  CHECK(rgb.rgba8 == std::vector<uint8_t>{10, 20, 30, 255, 40, 50, 60, 255});

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

// ---- Image decoding: which formats, which limits (io/texture_decode.cpp) -----------------------

namespace {

// The error decode_image throws for `bytes`, or "no error".
std::string decode_error(const std::vector<unsigned char>& bytes) {
  try {
    decode_image(bytes.data(), bytes.size(), "x.png");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Where `part` first occurs in `bytes`, or bytes.size().
size_t find_bytes(const std::vector<unsigned char>& bytes, const std::vector<unsigned char>& part) {
  return size_t(std::search(bytes.begin(), bytes.end(), part.begin(), part.end()) - bytes.begin());
}

std::vector<unsigned char> bytes_of(const std::string& s) {
  return {s.begin(), s.end()};
}

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

// `raw` compressed by zlib at its best ratio.
std::vector<unsigned char> deflated(const std::vector<unsigned char>& raw) {
  uLongf size = compressBound(uLong(raw.size()));
  std::vector<unsigned char> out(size);
  REQUIRE(compress2(out.data(), &size, raw.data(), uLong(raw.size()), 9) == Z_OK);
  out.resize(size);
  return out;
}

// Where the first chunk `type` of `png` starts (its length field).
size_t chunk_at(const std::vector<unsigned char>& png, const char* type) {
  for (size_t at = 8; at + 8 <= png.size();) {
    if (std::memcmp(&png[at + 4], type, 4) == 0) return at;
    at += 12 + (size_t(png[at]) << 24 | size_t(png[at + 1]) << 16 | size_t(png[at + 2]) << 8 |
                png[at + 3]);
  }
  FAIL("no chunk " << type);
  return 0;
}

// `png` with a chunk of `type` and `data` inserted before its first IDAT.
std::vector<unsigned char> with_chunk(std::vector<unsigned char> png, const char* type,
                                      const std::vector<unsigned char>& data) {
  std::vector<unsigned char> chunk;
  append_chunk(chunk, type, data);
  png.insert(png.begin() + long(chunk_at(png, "IDAT")), chunk.begin(), chunk.end());
  return png;
}

struct CliRun {
  int code;
  std::string err;
};

// The dacrt command line with `args`, killed after 60 s (exit code 124).
CliRun cli(const TempDir& dir, const std::string& args) {
  const std::string err = dir / "stderr.txt";
  const std::string cmd =
      "timeout 60 " + std::string(DACRT_CLI) + " " + args + " >/dev/null 2>" + err + " </dev/null";
  const int status = std::system(cmd.c_str());
  std::ifstream in(err);
  std::stringstream text;
  text << in.rdbuf();
  std::filesystem::remove(err);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

}  // namespace

TEST_CASE("image formats: only PNG and JPEG are decoded; others are refused by their signature") {
  const struct {
    const char* name;
    std::vector<unsigned char> bytes;
    const char* says;
  } cases[] = {
      {"truncated Radiance HDR", truncated_hdr(), "is a Radiance HDR image, not PNG or JPEG"},
      {"16-bit PGM, 16 x 16", pgm16(16), "is a Netpbm"},
      {"16-bit PGM, 2048 x 2048", pgm16(2048), "is a Netpbm"},
      {"BMP", bmp(), "is a BMP image"},
      {"GIF", gif(), "is a GIF image"},
      {"PSD", psd(), "is a Photoshop (PSD) image"},
      // TGA has no signature: stb_image decodes whatever its header checks let through.
      {"TGA", tga(), "its first bytes (00 00 0a 00 00 00 00 00) are not a PNG or JPEG signature"},
      {"eight bytes", {1, 2, 3, 4, 5, 6, 7, 8}, "its first bytes (01 02 03 04 05 06 07 08)"},
      {"two bytes", {0xff, 0xd8}, "is a damaged JPEG"},
  };
  for (const auto& c : cases) {
    INFO(c.name);
    const std::string e = decode_error(c.bytes);
    INFO(e);
    CHECK(e.rfind("x.png cannot be decoded: ", 0) == 0);
    CHECK(has(e, c.says));
    CHECK(has(e, "(only PNG and JPEG are supported)"));
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
      const CliRun r = cli(dir, command);
      INFO(r.err);
      CHECK(r.code == 1);
      CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
      CHECK(has(r.err, path + ": image 0 cannot be decoded: it is a Radiance HDR image"));
      CHECK(!std::filesystem::exists(dir / "out.exr"));
    }
  check_error(glb, {"image 0 cannot be decoded", "Radiance HDR", "only PNG and JPEG"});
  check_error(gltf, {"image 0 cannot be decoded", "Radiance HDR", "only PNG and JPEG"});
}

TEST_CASE("PNG: data cut short, bad CRCs, CgBI and huge headers are refused") {
  std::vector<uint16_t> samples;
  for (int i = 0; i < 4 * 4 * 4; ++i) samples.push_back(uint16_t(i * 3));
  const std::vector<unsigned char> good = png_file(4, 4, 8, 6, samples);
  REQUIRE(decode_error(png8(2, 2, 4, kTexels)) == "no error");
  REQUIRE(decode_image(good.data(), good.size(), "x").rgba8.size() == 64);

  const size_t idat = chunk_at(good, "IDAT");
  std::vector<unsigned char> cut(good.begin(), good.begin() + long(idat + 8 + 30));
  CHECK(has(decode_error(cut), "invalid PNG data: the data ends before the image does"));
  // The image data whole but no IEND: the file is cut short all the same.
  std::vector<unsigned char> no_end(good.begin(), good.end() - 12);
  CHECK(has(decode_error(no_end), "the data ends before the image does"));

  // The IDAT intact, its CRC wrong.
  std::vector<unsigned char> crc = good;
  crc[chunk_at(good, "IEND") - 1] ^= 1;
  CHECK(has(decode_error(crc), "invalid PNG data: IDAT: CRC error"));

  // The zlib stream's Adler-32 wrong, the chunk's CRC right: found when the stream ends.
  std::vector<unsigned char> adler = good;
  const size_t idat_end = chunk_at(good, "IEND") - 4;  // the IDAT's CRC
  adler[idat_end - 1] ^= 1;
  const uint32_t fixed = png_crc(&adler[idat + 4], idat_end - idat - 4);
  for (size_t i = 0; i < 4; ++i) adler[idat_end + i] = uint8_t(fixed >> (24 - 8 * i));
  CHECK(has(decode_error(adler), "invalid PNG data: IDAT: incorrect data check"));

  std::vector<unsigned char> cgbi = good;
  std::vector<unsigned char> chunk;
  append_chunk(chunk, "CgBI", {0x50, 0, 0x20, 2});
  cgbi.insert(cgbi.begin() + 8, chunk.begin(), chunk.end());
  CHECK(has(decode_error(cgbi), "is an Apple CgBI PNG"));

  // 10^10 texels: refused from the header, before any buffer for them exists.
  const std::vector<unsigned char> huge = png_resized(good, 100000, 100000);
  {
    AllocationWatch watch;
    const std::string e = decode_error(huge);
    CHECK(has(e, "100000 x 100000 texels is more than 2^27"));
    CHECK(watch.peak() < (1u << 20));
  }
  CHECK(
      has(decode_error(png_resized(good, 1u << 28, 1)), "268435456 x 1 texels is more than 2^27"));
  CHECK(has(decode_error(png_resized(good, 0, 4)), "invalid PNG data"));
}

TEST_CASE("PNG: zlib bombs are bounded: in a text chunk, past the image, a big image of zeros") {
  const std::vector<uint16_t> texel = {10, 20, 30, 40};
  const std::vector<unsigned char> small = png_file(1, 1, 8, 6, texel);
  const std::vector<uint8_t> expected = {10, 20, 30, 40};
  // A zTXt comment of 64 MiB (64 KiB compressed): skipped, never inflated.
  {
    std::vector<unsigned char> ztxt = bytes_of("Comment");
    ztxt.insert(ztxt.end(), {0, 0});  // keyword's end, deflate
    const std::vector<unsigned char> text = deflated(std::vector<unsigned char>(64 << 20, 'a'));
    ztxt.insert(ztxt.end(), text.begin(), text.end());
    const std::vector<unsigned char> png = with_chunk(small, "zTXt", ztxt);
    AllocationWatch watch;
    CHECK(decode_image(png.data(), png.size(), "x").rgba8 == expected);
    CHECK(watch.peak() < (1u << 20));
  }
  // A 1 × 1 image whose IDAT inflates to 64 MiB: one row is read, the rest is not inflated.
  {
    std::vector<unsigned char> raw = {0, 10, 20, 30, 40};
    raw.resize(raw.size() + (64 << 20));
    std::vector<unsigned char> png = small;
    const size_t idat = chunk_at(png, "IDAT");
    png.erase(png.begin() + long(idat), png.begin() + long(chunk_at(png, "IEND")));
    std::vector<unsigned char> chunk;
    append_chunk(chunk, "IDAT", deflated(raw));
    png.insert(png.begin() + long(idat), chunk.begin(), chunk.end());
    AllocationWatch watch;
    CHECK(decode_image(png.data(), png.size(), "x").rgba8 == expected);
    CHECK(watch.peak() < (1u << 20));
  }
  // 4096 × 4096 grey zeros, 16 KiB compressed: allowed, and decoded in its own size (64 MiB).
  {
    std::vector<unsigned char> png = png_file(1, 1, 8, 0, {0});
    png = png_resized(png, 4096, 4096);
    const size_t idat = chunk_at(png, "IDAT");
    png.erase(png.begin() + long(idat), png.begin() + long(chunk_at(png, "IEND")));
    std::vector<unsigned char> chunk;
    append_chunk(chunk, "IDAT", deflated(std::vector<unsigned char>(4097 * 4096, 0)));
    png.insert(png.begin() + long(idat), chunk.begin(), chunk.end());
    CHECK(png.size() < 100000);
    AllocationWatch watch;
    const TextureImage image = decode_image(png.data(), png.size(), "x");
    CHECK(watch.peak() < (64u << 20) + (1u << 20));
    REQUIRE(image.rgba8.size() == size_t(64) << 20);
    CHECK(image.texel(4095, 4095, false) == glm::vec4(0, 0, 0, 1));
  }
}

TEST_CASE("PNG: palette, grey, grey + alpha, tRNS, 1 and 2 bits, 16 bits, Adam7: exact RGBA") {
  auto rgba8 = [](const std::vector<unsigned char>& png) {
    const TextureImage image = decode_image(png.data(), png.size(), "x");
    CHECK(image.rgba16.empty());
    return image.rgba8;
  };
  auto rgba16 = [](const std::vector<unsigned char>& png) {
    const TextureImage image = decode_image(png.data(), png.size(), "x");
    CHECK(image.rgba8.empty());
    return image.rgba16;
  };
  const PngChunk palette = {"PLTE", {10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120}};
  const PngChunk transparency = {"tRNS", {255, 0}};  // entries 2 and 3: opaque
  CHECK(rgba8(png_file(3, 1, 8, 3, {2, 0, 1}, {palette, transparency})) ==
        std::vector<uint8_t>{70, 80, 90, 255, 10, 20, 30, 255, 40, 50, 60, 0});
  CHECK(rgba8(png_file(5, 1, 2, 3, {3, 2, 1, 0, 3}, {palette})) ==
        std::vector<uint8_t>{100, 110, 120, 255, 70, 80,  90,  255, 40,  50,
                             60,  255, 10,  20,  30, 255, 100, 110, 120, 255});
  // 1 bit: 0 and 1 are black and white; 10 texels a row, padded to 2 bytes.
  const std::vector<uint16_t> bits = {1, 0, 0, 1, 1, 1, 0, 1, 0, 1, 0, 1, 1, 0, 0, 0, 0, 0, 1, 1};
  std::vector<uint8_t> expected;
  for (uint16_t b : bits)
    expected.insert(expected.end(), {uint8_t(255 * b), uint8_t(255 * b), uint8_t(255 * b), 255});
  CHECK(rgba8(png_file(10, 2, 1, 0, bits)) == expected);
  CHECK(rgba8(png_file(2, 1, 8, 4, {100, 200, 7, 0})) ==
        std::vector<uint8_t>{100, 100, 100, 200, 7, 7, 7, 0});
  CHECK(rgba8(png_file(2, 1, 8, 0, {7, 8}, {{"tRNS", {0, 7}}})) ==
        std::vector<uint8_t>{7, 7, 7, 0, 8, 8, 8, 255});
  CHECK(rgba8(png_file(2, 1, 8, 2, {1, 2, 3, 4, 5, 6}, {{"tRNS", {0, 4, 0, 5, 0, 6}}})) ==
        std::vector<uint8_t>{1, 2, 3, 255, 4, 5, 6, 0});

  // 16 bits: every sample exact, high and low bytes not swapped.
  CHECK(rgba16(png_file(2, 1, 16, 6, {0x0102, 0xfffe, 0, 0x8001, 1, 0x7fff, 0xff00, 0x00ff})) ==
        std::vector<uint16_t>{0x0102, 0xfffe, 0, 0x8001, 1, 0x7fff, 0xff00, 0x00ff});
  CHECK(rgba16(png_file(1, 2, 16, 0, {0x1234, 0xabcd})) ==
        std::vector<uint16_t>{0x1234, 0x1234, 0x1234, 0xffff, 0xabcd, 0xabcd, 0xabcd, 0xffff});
  CHECK(rgba16(png_file(1, 1, 16, 4, {0x0203, 0x0405})) ==
        std::vector<uint16_t>{0x0203, 0x0203, 0x0203, 0x0405});

  // Adam7: an 11 × 9 RGBA image (every pass non-empty, ragged edges) texel for texel.
  std::vector<uint16_t> samples;
  for (int i = 0; i < 11 * 9 * 4; ++i) samples.push_back(uint16_t((i * 37 + i / 4) % 256));
  const std::vector<uint8_t> flat(samples.begin(), samples.end());
  CHECK(rgba8(png_file(11, 9, 8, 6, samples)) == flat);
  CHECK(rgba8(png_file(11, 9, 8, 6, samples, {}, true)) == flat);
  std::vector<uint16_t> wide;
  for (int i = 0; i < 11 * 9 * 4; ++i) wide.push_back(uint16_t(i * 611));
  CHECK(rgba16(png_file(11, 9, 16, 6, wide, {}, true)) == wide);
}

TEST_CASE("JPEG: grey, progressive and Adobe CMYK decode to RGBA; data cut short is refused") {
  auto texel = [](const TextureImage& image, int x, int y) {
    return glm::ivec4(image.texel(x, y, false) * 255.f + 0.5f);
  };
  auto close = [](glm::ivec4 a, glm::ivec4 b, int within) {
    INFO(a.r << " " << a.g << " " << a.b << " " << a.a << " vs " << b.r << " " << b.g << " " << b.b
             << " " << b.a);
    CHECK(glm::all(glm::lessThanEqual(glm::abs(a - b), glm::ivec4(within))));
  };
  // 16 × 16 in four 8 × 8 blocks (one JPEG block each): grey, RGB.
  auto quadrants = [](int channels, const std::vector<std::vector<uint8_t>>& colors) {
    std::vector<uint8_t> t;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        const std::vector<uint8_t>& c = colors[size_t(y / 8 * 2 + x / 8)];
        t.insert(t.end(), c.begin(), c.begin() + channels);
      }
    return t;
  };
  const std::vector<unsigned char> grey =
      jpeg_lib(16, 16, 1, quadrants(1, {{30}, {90}, {160}, {220}}));
  const TextureImage g = decode_image(grey.data(), grey.size(), "x");
  REQUIRE(g.rgba8.size() == 4 * 256);
  close(texel(g, 3, 3), {30, 30, 30, 255}, 2);
  close(texel(g, 12, 4), {90, 90, 90, 255}, 2);
  close(texel(g, 4, 12), {160, 160, 160, 255}, 2);
  close(texel(g, 12, 12), {220, 220, 220, 255}, 2);

  const std::vector<std::vector<uint8_t>> colors = {
      {200, 40, 40}, {40, 200, 40}, {40, 40, 200}, {220, 220, 50}};
  const std::vector<unsigned char> progressive =
      jpeg_lib(16, 16, 3, quadrants(3, colors), true, 100);
  CHECK(find_bytes(progressive, {0xff, 0xc2}) < progressive.size());  // SOF2: progressive
  const TextureImage p = decode_image(progressive.data(), progressive.size(), "x");
  REQUIRE(p.width == 16);
  close(texel(p, 3, 3), {200, 40, 40, 255}, 6);
  close(texel(p, 12, 3), {40, 200, 40, 255}, 6);
  close(texel(p, 3, 12), {40, 40, 200, 255}, 6);
  close(texel(p, 12, 12), {220, 220, 50, 255}, 6);

  // CMYK with an Adobe marker stores 255 − ink: no cyan, half magenta, full yellow, no black is
  // (255, 127, 0, 255) in the file, and RGB (255, 127, 0).
  const std::vector<uint8_t> cmyk = [] {
    std::vector<uint8_t> t;
    for (int i = 0; i < 256; ++i) t.insert(t.end(), {255, 127, 0, 255});
    return t;
  }();
  const std::vector<unsigned char> adobe = jpeg_lib(16, 16, 4, cmyk, false, 100);
  CHECK(find_bytes(adobe, {'A', 'd', 'o', 'b', 'e'}) < adobe.size());
  const TextureImage k = decode_image(adobe.data(), adobe.size(), "x");
  REQUIRE(k.rgba8.size() == 4 * 256);
  close(texel(k, 5, 9), {255, 127, 0, 255}, 3);

  // Cut in the middle of the scan: libjpeg would pad the rest with grey.
  std::vector<uint8_t> noise;
  for (int i = 0; i < 64 * 64 * 3; ++i) noise.push_back(uint8_t(i * 7919 % 251));
  const std::vector<unsigned char> whole = jpeg_lib(64, 64, 3, noise);
  REQUIRE(decode_error(whole) == "no error");
  const std::vector<unsigned char> cut(whole.begin(), whole.begin() + long(whole.size() * 2 / 3));
  CHECK(has(decode_error(cut), "invalid JPEG data: Premature end of JPEG file"));
  const std::vector<unsigned char> header_only(whole.begin(), whole.begin() + 100);
  CHECK(has(decode_error(header_only), "invalid JPEG data"));

  // A frame header claiming 65000 × 65000 texels: refused before decoding.
  std::vector<unsigned char> huge = whole;
  const size_t sof = find_bytes(huge, {0xff, 0xc0});
  REQUIRE(sof < huge.size());
  for (size_t i : {5, 7}) huge[sof + i] = 0xfd, huge[sof + i + 1] = 0xe8;  // height, width: 65000
  CHECK(has(decode_error(huge), "65000 x 65000 texels is more than 2^27"));
}

TEST_CASE("textures: baseColor × factor × vertex colour, sRGB-decoded, with alpha") {
  TempDir dir("base-color");
  for (Embed embed : {Embed::data_uri, Embed::buffer_view, Embed::file}) {
    INFO("embedding " << int(embed));
    const std::vector<glm::vec4> colors(4, glm::vec4(1.f, 0.5f, 1.f, 0.5f));
    GltfWriter w = quad_file(
        {{"pbrMetallicRoughness",
          {{"baseColorFactor", {0.5, 1, 1, 0.8}}, {"baseColorTexture", {{"index", 0}}}}}});
    w.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
        w.add_accessor(w.add_view(colors.data(), 64), kFloat, 4, "VEC4");
    add_texture(w, png8(2, 2, 4, kTexels), kNearest, embed, dir.path());
    const std::string path = embed == Embed::buffer_view ? w.write_glb(dir / "quad.glb")
                                                         : w.write_gltf(dir / "quad.gltf");
    const Scene scene = load_gltf(path);
    REQUIRE(scene.images.size() == 1);
    CHECK(scene.images[0].width == 2);
    CHECK(scene.texcoords[1].empty());  // no material samples set 1
    // Point (x, y) has uv (x, 1 − y): the image's top-left texel is at the quad's top left.
    const SurfacePoint red = quad_surface(scene, 0.25f, 0.75f);
    CHECK(near(red.brdf.base_color, glm::vec3(0.5f, 0.f, 0.f)));
    CHECK(quad_alpha(scene, 0.25f, 0.75f) == doctest::Approx(0.8f * 0.5f));
    const SurfacePoint green = quad_surface(scene, 0.75f, 0.75f);
    CHECK(near(green.brdf.base_color, glm::vec3(0.f, 0.5f, 0.f)));
    CHECK(quad_alpha(scene, 0.75f, 0.75f) == doctest::Approx(0.8f * 0.5f * 128.f / 255.f));
    const SurfacePoint grey = quad_surface(scene, 0.75f, 0.25f);
    CHECK(near(grey.brdf.base_color, glm::vec3(0.5f, 0.5f, 1.f) * kGrey));
    CHECK(grey.normal == glm::vec3(0, 0, 1));
  }
}

TEST_CASE("textures: metallic-roughness (G, B), emissive (sRGB) and the sampler's wrap modes") {
  TempDir dir("metal-rough");
  GltfWriter w = quad_file({{"pbrMetallicRoughness",
                             {{"metallicFactor", 0.5},
                              {"roughnessFactor", 1.0},
                              {"metallicRoughnessTexture", {{"index", 0}}}}},
                            {"emissiveFactor", {1, 1, 0.5}},
                            {"emissiveTexture", {{"index", 1}}}});
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);
  add_texture(w, png8(2, 2, 4, kTexels), {{"magFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33648}});
  const Scene scene = load_gltf(w.write_gltf(dir / "quad.gltf"));
  REQUIRE(scene.textures.size() == 2);
  CHECK(scene.textures[0].wrap_s == Wrap::repeat);
  CHECK(scene.textures[1].wrap_s == Wrap::clamp);
  CHECK(scene.textures[1].wrap_t == Wrap::mirror);
  CHECK(scene.textures[1].nearest);
  const SurfacePoint blue = quad_surface(scene, 0.25f, 0.25f);  // texel (0, 1): 0, 0, 255
  CHECK(blue.brdf.metallic == doctest::Approx(0.5f));
  CHECK(blue.brdf.roughness == 0.f);
  CHECK(near(blue.emission, glm::vec3(0, 0, 0.5f)));
  const SurfacePoint green = quad_surface(scene, 0.75f, 0.75f);  // texel (1, 0): 0, 255, 0
  CHECK(green.brdf.metallic == 0.f);
  CHECK(green.brdf.roughness == doctest::Approx(1.f));
  CHECK(near(green.emission, glm::vec3(0, 1, 0)));
  CHECK(near(emission_at(scene, 0, 0.f, 0.75f), green.emission));  // the point (0.75, 0.75)
}

TEST_CASE("textures: KHR_materials_transmission's factor × transmissionTexture (R)") {
  TempDir dir("transmission");
  GltfWriter w =
      quad_file({{"extensions",
                  {{"KHR_materials_transmission",
                    {{"transmissionFactor", 0.8},
                     {"transmissionTexture",
                      {{"index", 0},
                       {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0}}}}}}}}}}}}});
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);
  const Scene scene = load_gltf(w.write_gltf(dir / "quad.gltf"));
  CHECK(scene.materials[0].transmission == doctest::Approx(0.8f));
  // (0.75, 0.75) has uv (0.75, 0.25), shifted by 0.5: (0.25, 0.25), the red texel.
  CHECK(quad_surface(scene, 0.75f, 0.75f).brdf.transmission == doctest::Approx(0.8f));
  CHECK(quad_surface(scene, 0.25f, 0.75f).brdf.transmission == 0.f);  // green: R = 0
  w.doc["materials"][0]["extensions"]["KHR_materials_transmission"]["transmissionTexture"] =
      json{{"texCoord", 0}};
  check_error(
      w.write_gltf(dir / "no-index.gltf"),
      {"/materials/0/extensions/KHR_materials_transmission/transmissionTexture/index", "missing"});
}

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

TEST_CASE("textures: COLOR_0 as normalised UNSIGNED_BYTE VEC3 is linear and interpolated") {
  TempDir dir("colors");
  GltfWriter w = quad_file(json::object());
  const std::vector<uint8_t> colors = {255, 0, 0, 255, 0, 0, 0, 0, 255, 0, 0, 255};
  int a = w.add_accessor(w.add_view(colors.data(), colors.size()), kUnsignedByte, 4, "VEC3");
  w.doc["accessors"][a]["normalized"] = true;
  w.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = a;
  const Scene scene = load_gltf(w.write_gltf(dir / "colors.gltf"));
  REQUIRE(scene.colors.size() == 6);
  // Red along y = 0, blue along y = 1: halfway up, half of each, alpha 1.
  const SurfacePoint s = quad_surface(scene, 0.7f, 0.5f);
  CHECK(near(s.brdf.base_color, glm::vec3(0.5f, 0.f, 0.5f)));
  CHECK(quad_alpha(scene, 0.7f, 0.5f) == 1.f);
  CHECK(scene.texcoords[0].empty());  // nothing samples a texture

  w.doc["accessors"][a]["normalized"] = false;
  check_error(w.write_gltf(dir / "unnormalized.gltf"), {"accessor", "COLOR_0", "normalized"});
}

TEST_CASE("normal maps: tangents from the file or generated agree; mirrors and +Y up") {
  TempDir dir("normal-map");
  // A constant normal map tilted towards +X of tangent space, or +Y.
  const float s = std::sin(0.5f), c = std::cos(0.5f);
  auto byte = [](float x) { return uint8_t(std::lround((x * 0.5f + 0.5f) * 255.f)); };
  const std::vector<uint8_t> towards_x = {byte(s), byte(0), byte(c)};
  const std::vector<uint8_t> towards_y = {byte(0), byte(s), byte(c)};
  auto file = [&](const std::vector<uint8_t>& texel, bool tangents, bool mirror_uv, json node) {
    GltfWriter w = quad_file({{"normalTexture", {{"index", 0}, {"scale", 1.0}}}});
    const std::vector<glm::vec3> normals(4, glm::vec3(0, 0, 1));
    w.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = w.add_vec3(normals, false);
    if (tangents) {
      // A mirrored layout runs +u along −x and keeps +Y up: w = −1.
      const float sign = mirror_uv ? -1.f : 1.f;
      const std::vector<glm::vec4> t(4, glm::vec4(sign, 0, 0, sign));
      w.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] =
          w.add_accessor(w.add_view(t.data(), 64), kFloat, 4, "VEC4");
    } else {
      // Tangents that would tilt the wrong way, but without NORMAL the spec says to ignore them.
      const std::vector<glm::vec4> wrong(4, glm::vec4(0, -1, 0, 1));
      w.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] =
          w.add_accessor(w.add_view(wrong.data(), 64), kFloat, 4, "VEC4");
      w.doc["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
    }
    if (mirror_uv) {
      const std::vector<glm::vec2> uv = {{1, 1}, {0, 1}, {0, 0}, {1, 0}};
      w.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] =
          w.add_accessor(w.add_view(uv.data(), 32), kFloat, 4, "VEC2");
    }
    std::vector<uint8_t> image;
    for (int i = 0; i < 4; ++i) image.insert(image.end(), texel.begin(), texel.end());
    add_texture(w, png8(2, 2, 3, image), kNearest);
    w.doc["nodes"][0].update(node);
    return load_gltf(w.write_gltf(dir / "quad.gltf"));
  };
  const glm::vec3 tilted_x(s, 0, c), tilted_y(0, s, c);
  for (bool tangents : {true, false}) {
    INFO("tangents from the file: " << tangents);
    const Scene plain = file(towards_x, tangents, false, json::object());
    REQUIRE(plain.tangents.size() == 6);
    CHECK(near(glm::vec3(plain.tangents[0]), glm::vec3(1, 0, 0)));
    CHECK(plain.tangents[0].w == 1.f);
    // +X of tangent space is +u, here +x; +Y is up the image (−v), here +y.
    CHECK(near(quad_surface(plain, 0.6f, 0.3f).normal, tilted_x, 0.01f));
    CHECK(near(quad_surface(file(towards_y, tangents, false, json::object()), 0.3f, 0.6f).normal,
               tilted_y, 0.01f));
    // The image mirrored left to right: +u runs along −x, and so does the tilt; +Y stays up.
    const Scene mirrored_uv = file(towards_x, tangents, true, json::object());
    CHECK(near(quad_surface(mirrored_uv, 0.6f, 0.3f).normal, glm::vec3(-s, 0, c), 0.01f));
    CHECK(near(quad_surface(file(towards_y, tangents, true, json::object()), 0.3f, 0.6f).normal,
               tilted_y, 0.01f));
    // A node that mirrors x (and flips the winding back) mirrors the tilt with the geometry.
    const Scene mirrored_node = file(towards_y, tangents, false, {{"scale", {-1, 1, 1}}});
    const glm::vec3 n = surface_at(mirrored_node, 0, 0.3f, 0.3f, glm::vec3(0, 0, 1)).normal;
    CHECK(near(n, tilted_y, 0.01f));
    const Scene mirrored_x = file(towards_x, tangents, false, {{"scale", {-1, 1, 1}}});
    CHECK(near(surface_at(mirrored_x, 0, 0.3f, 0.3f, glm::vec3(0, 0, 1)).normal,
               glm::vec3(-s, 0, c), 0.01f));
  }
}

TEST_CASE("textures: images no used material samples are never decoded; copies once") {
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
    w.doc["textures"] = {json::object()};
    check_error(w.write_gltf(dir / "no-source.gltf"), {"texture 0", "no PNG or JPEG source"});
  }
  {
    GltfWriter w = textured({{"index", 4}});
    check_error(w.write_gltf(dir / "index.gltf"),
                {"/materials/0/pbrMetallicRoughness/baseColorTexture/index", "4"});
  }
  {
    GltfWriter w = textured({{"index", 0}, {"texCoord", 2}});
    add_texture(w, png8(2, 2, 4, kTexels));
    check_error(w.write_gltf(dir / "texcoord.gltf"), {"material 0", "texCoord 2"});
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

TEST_CASE("an emissive texture renders texel for texel (uv, barycentrics and sRGB end to end)") {
  TempDir dir("emissive-render");
  GltfWriter w = quad_file({{"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", {{"index", 0}}}});
  add_texture(w, png8(2, 2, 4, kTexels), kNearest);
  Scene scene = load_gltf(w.write_gltf(dir / "quad.gltf"));
  // An orthographic camera whose 8 × 8 pixels cover exactly the quad.
  Camera cam;
  cam.orthographic = true;
  cam.ymag = 0.5f;
  cam.to_world = glm::inverse(
      glm::lookAt(glm::vec3(0.5f, 0.5f, 3.f), glm::vec3(0.5f, 0.5f, 0.f), glm::vec3(0, 1, 0)));
  scene.cameras = {cam};
  RenderSettings s;
  s.width = s.height = 8;
  s.spp = 4;
  s.max_depth = 0;
  auto backend = Backend::create("dacrt", scene.geometry);
  RenderJob job(scene, *backend, s);
  Film film = job.film();
  Progress quiet("test", 1, false);
  job.run(film, 0, uint32_t(s.spp), quiet);
  const glm::vec3 expected[2][2] = {{{1, 0, 0}, {0, 1, 0}}, {{0, 0, 1}, glm::vec3(kGrey)}};
  const Image image = film.resolve();
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      INFO("pixel " << x << ", " << y);
      const float* p = image.pixel(x, y);
      CHECK(near(glm::vec3(p[0], p[1], p[2]), expected[y / 4][x / 4]));
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

TEST_CASE("generated tangents: corners with the same position, normal and uv share one tangent") {
  // Two unindexed triangles of a quad (six vertices): the corners they share get the same
  // tangent, the angle-weighted mean of their different uv tangents, as MikkTSpace welds them.
  TempDir dir("welded");
  GltfWriter w;
  const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},
                                    {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  // uv (x, 1 − y), except the last corner: v 0.2, which turns the second triangle's ∂p/∂u.
  // The shared corner (0, 0, 0) has u = −0 once and +0 once: the same uv.
  const std::vector<glm::vec2> uv = {{-0.f, 1}, {1, 1}, {1, 0}, {0, 1}, {1, 0}, {0, 0.2f}};
  const std::vector<glm::vec3> n(6, glm::vec3(0, 0, 1));
  w.add_material({{"normalTexture", {{"index", 0}}}});
  json attributes = {{"POSITION", w.add_vec3(p)},
                     {"NORMAL", w.add_vec3(n, false)},
                     {"TEXCOORD_0", w.add_accessor(w.add_view(uv.data(), 48), kFloat, 6, "VEC2")}};
  w.set_scene({w.add_node({{"mesh", w.add_mesh({{"attributes", attributes}, {"material", 0}})}})});
  add_texture(w, png8(2, 2, 4, kTexels));
  const Scene scene = load_gltf(w.write_gltf(dir / "welded.gltf"));
  REQUIRE(scene.tangents.size() == 6);
  // Corner 0 of each triangle is (0, 0, 0); corner 2 of the first and 1 of the second (1, 1, 0).
  CHECK(near(glm::vec3(scene.tangents[0]), glm::vec3(scene.tangents[3])));
  CHECK(near(glm::vec3(scene.tangents[2]), glm::vec3(scene.tangents[4])));
  // Between the first triangle's +x and the second's (1, −0.25, 0) direction.
  CHECK(scene.tangents[0].y < -0.01f);
  CHECK(scene.tangents[0].y > -0.24f);
  CHECK(near(glm::vec3(scene.tangents[1]), glm::vec3(1, 0, 0)));  // its own vertex: +x
}
