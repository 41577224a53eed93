// Images written by their names (io/image_file.h): the extension picks the format in any case,
// each file starts with its format's signature and decodes (stb_image) to the image's size and
// values (PNG and JPEG: the display's 8-bit values; HDR: the linear ones within RGBE's
// precision), alpha where the format holds it, and an unknown extension is a usage error that
// writes nothing.
#include <doctest/doctest.h>
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/image_file.h"
#include "dacrt/util/error.h"
#include "ocio_config.h"

using namespace dacrt;
using namespace dacrt::test;
namespace fs = std::filesystem;

namespace {

// A 5 × 3 ramp with a few hard values: 0, mid-grey, above 1, negative, NaN.
Image ramp() {
  Image image(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      float* p = image.pixel(x, y);
      p[0] = 0.1f * float(x), p[1] = 0.18f * float(y + 1), p[2] = 0.05f * float(x + y);
    }
  image.pixel(4, 2)[0] = 37.5f;
  image.pixel(3, 2)[1] = -2.f;
  image.pixel(2, 2)[2] = std::nanf("");
  return image;
}

struct Decoded {
  int width = 0, height = 0, channels = 0;
  std::vector<float> values;  // as stb_image gives them: 8-bit values, or HDR's floats
};

Decoded decode(const std::string& path, bool hdr, int channels = 3) {
  Decoded d;
  if (hdr) {
    std::unique_ptr<float, void (*)(void*)> p(
        stbi_loadf(path.c_str(), &d.width, &d.height, &d.channels, channels), stbi_image_free);
    REQUIRE(p != nullptr);
    d.values.assign(p.get(), p.get() + size_t(d.width) * d.height * channels);
  } else {
    std::unique_ptr<unsigned char, void (*)(void*)> p(
        stbi_load(path.c_str(), &d.width, &d.height, &d.channels, channels), stbi_image_free);
    REQUIRE(p != nullptr);
    d.values.assign(p.get(), p.get() + size_t(d.width) * d.height * channels);
  }
  return d;
}

bool starts_with(const std::string& bytes, const std::string& magic) {
  return bytes.compare(0, magic.size(), magic) == 0;
}

size_t files_in(const TempDir& dir) {
  size_t n = 0;
  for (auto it = fs::directory_iterator(dir.path()); it != fs::directory_iterator(); ++it) ++n;
  return n;
}

}  // namespace

TEST_CASE("image files: the extension names the format, in any case") {
  CHECK(image_format("a.exr") == ImageFormat::exr);
  CHECK(image_format("dir.png/a.EXR") == ImageFormat::exr);
  CHECK(image_format("a.PNG") == ImageFormat::png);
  CHECK(image_format("a.jpg") == ImageFormat::jpeg);
  CHECK(image_format("a.JpEg") == ImageFormat::jpeg);
  CHECK(image_format("a.hdr") == ImageFormat::hdr);
  CHECK_FALSE(image_format("a.tiff"));
  CHECK_FALSE(image_format("a"));
  CHECK_FALSE(image_format("a.png.bak"));
  CHECK_FALSE(image_format(".png"));  // a hidden file named "png", no extension
  CHECK(holds_display_values(ImageFormat::png));
  CHECK(holds_display_values(ImageFormat::jpeg));
  CHECK_FALSE(holds_display_values(ImageFormat::hdr));
  CHECK_FALSE(holds_display_values(ImageFormat::exr));
  try {
    output_format("-o", "out.tif");
    FAIL("out.tif was taken");
  } catch (const UsageError& e) {
    const std::string m = e.what();
    CHECK(m.find("-o out.tif") != std::string::npos);
    CHECK(m.find("'.tif'") != std::string::npos);
    CHECK(m.find(".exr, .png, .jpg, .jpeg or .hdr") != std::string::npos);
  }
  CHECK_THROWS_AS(output_format("--preview", "noext"), UsageError);
}

TEST_CASE("image files: each format starts with its signature and decodes to the image") {
  ScopedOcioEnv env(nullptr);
  TempDir dir("image-files");
  const Image image = ramp();
  const std::vector<uint8_t> display = display_bytes(image);
  REQUIRE(display.size() == image.rgb.size());

  write_image(dir / "a.PNG", image);
  CHECK(starts_with(slurp(dir / "a.PNG"), "\x89PNG\r\n\x1a\n"));
  const Decoded png = decode(dir / "a.PNG", false);
  CHECK(png.width == 5);
  CHECK(png.height == 3);
  CHECK(png.channels == 3);
  for (size_t i = 0; i < display.size(); ++i) CHECK(png.values[i] == float(display[i]));

  write_image(dir / "a.jpg", image);
  write_image(dir / "b.jpeg", image);
  CHECK(starts_with(slurp(dir / "a.jpg"), "\xff\xd8\xff"));
  CHECK(slurp(dir / "a.jpg") == slurp(dir / "b.jpeg"));
  const Decoded jpg = decode(dir / "a.jpg", false);
  CHECK(jpg.width == 5);
  CHECK(jpg.height == 3);
  CHECK(jpg.channels == 3);
  // Lossy, but at quality 95 without subsampling each value stays near the display's.
  for (size_t i = 0; i < display.size(); ++i) CHECK(std::abs(jpg.values[i] - display[i]) <= 12);

  write_image(dir / "a.hdr", image);
  CHECK(starts_with(slurp(dir / "a.hdr"), "#?RADIANCE\n"));
  const Decoded hdr = decode(dir / "a.hdr", true);
  CHECK(hdr.width == 5);
  CHECK(hdr.height == 3);
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    const float v = image.rgb[i];
    const float want = v > 0.f ? v : 0.f;  // RGBE has no sign and no NaN
    INFO("value " << i << ": " << v << " read back as " << hdr.values[i]);
    // RGBE keeps 8 bits of mantissa for the pixel's largest channel.
    const float* px = &image.rgb[i - i % 3];
    float largest = 0.f;
    for (int c = 0; c < 3; ++c) largest = std::max(largest, px[c] > 0.f ? px[c] : 0.f);
    CHECK(std::abs(hdr.values[i] - want) <= largest / 128.f + 1e-30f);
  }
  CHECK(hdr.values[3 * (2 * 5 + 4)] == doctest::Approx(37.5).epsilon(1.0 / 128));

  write_image(dir / "a.exr", image);
  CHECK(starts_with(slurp(dir / "a.exr"), "\x76\x2f\x31\x01"));
  const Image back = read_exr(dir / "a.exr");
  CHECK(back.width == 5);
  CHECK(back.height == 3);
  for (size_t i = 0; i < image.rgb.size(); ++i)
    CHECK((back.rgb[i] == image.rgb[i] || (std::isnan(back.rgb[i]) && std::isnan(image.rgb[i]))));
  CHECK(files_in(dir) == 5);  // no temporary left behind
}

TEST_CASE("image files: the display view and exposure change PNG and JPEG only") {
  ScopedOcioEnv env(nullptr);
  TempDir dir("image-display");
  const Image image = ramp();
  const DisplayOptions aces{"ACES 1.0 SDR-video (sRGB)", 1.0};
  write_image(dir / "plain.png", image);
  write_image(dir / "aces.png", image, aces);
  const Decoded png = decode(dir / "aces.png", false);
  const std::vector<uint8_t> want = display_bytes(image, aces);
  CHECK(want != display_bytes(image));
  for (size_t i = 0; i < want.size(); ++i) CHECK(png.values[i] == float(want[i]));
  // The preview's writer gives the same file.
  write_preview_png(dir / "preview.png", image, aces);
  CHECK(slurp(dir / "preview.png") == slurp(dir / "aces.png"));
  write_image(dir / "plain.hdr", image);
  write_image(dir / "aces.hdr", image, aces);
  CHECK(slurp(dir / "plain.hdr") == slurp(dir / "aces.hdr"));
}

TEST_CASE("image files: alpha goes into EXR and PNG") {
  ScopedOcioEnv env(nullptr);
  TempDir dir("image-alpha");
  const Image image = ramp();
  std::vector<float> alpha(15);
  for (size_t p = 0; p < alpha.size(); ++p) alpha[p] = float(p) / 10.f - 0.2f;  // -0.2 .. 1.2
  write_image(dir / "a.png", image, {}, {}, alpha);
  const Decoded png = decode(dir / "a.png", false, 4);
  CHECK(png.channels == 4);
  const std::vector<uint8_t> rgb = display_bytes(image);
  for (size_t p = 0; p < alpha.size(); ++p) {
    INFO("pixel " << p);
    CHECK(png.values[4 * p] == float(rgb[3 * p]));
    CHECK(png.values[4 * p + 3] == float(std::lround(std::clamp(alpha[p], 0.f, 1.f) * 255.f)));
  }
  write_image(dir / "a.exr", image, {}, {}, alpha);
  const ExrFile exr = read_exr_file(dir / "a.exr");
  REQUIRE(exr.find("A") != nullptr);
  CHECK(exr.find("A")->values == alpha);
  CHECK_THROWS_AS(write_image(dir / "b.png", image, {}, {}, std::vector<float>(3)), Error);
}

TEST_CASE("image files: an unknown extension writes nothing, a bad image or place is one Error") {
  ScopedOcioEnv env(nullptr);
  TempDir dir("image-refused");
  CHECK_THROWS_AS(write_image(dir / "a.tif", ramp()), UsageError);
  CHECK_THROWS_AS(write_image(dir / "a", ramp()), UsageError);
  CHECK(files_in(dir) == 0);
  for (const char* name : {"a.png", "a.jpg", "a.hdr", "a.exr"}) {
    INFO(name);
    CHECK_THROWS_AS(write_image(dir / (std::string("missing/") + name), ramp()), Error);
    CHECK_THROWS_AS(write_image(dir / name, Image()), Error);
  }
  CHECK(files_in(dir) == 0);
}
