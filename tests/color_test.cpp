// Display conversion through OpenColorIO: the built-in sRGB chain's known values, robustness to
// bad pixels, the PNG preview's 8-bit values, and $OCIO handling (a valid config, a missing one).
#include "io/color.h"

#include <doctest/doctest.h>
#include <stb_image.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>

#include "temp_dir.h"
#include "util/error.h"

namespace fs = std::filesystem;
using dacrt::test::TempDir;

namespace {

// Sets or unsets $OCIO for one scope and puts the previous value back afterwards.
struct ScopedOcioEnv {
  std::optional<std::string> saved;
  explicit ScopedOcioEnv(const char* value) {
    if (const char* old = std::getenv("OCIO")) saved = old;
    if (value)
      setenv("OCIO", value, 1);
    else
      unsetenv("OCIO");
  }
  ~ScopedOcioEnv() {
    if (saved)
      setenv("OCIO", saved->c_str(), 1);
    else
      unsetenv("OCIO");
  }
};

// One grey pixel per value.
dacrt::Image greys(const std::vector<float>& values) {
  dacrt::Image image(int(values.size()), 1);
  for (size_t i = 0; i < values.size(); ++i)
    for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] = values[i];
  return image;
}

// The sRGB encoding (IEC 61966-2-1), the reference for the built-in chain.
double srgb_encode(double v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
}

}  // namespace

TEST_CASE("to_display without $OCIO is the sRGB encoding of linear Rec.709") {
  ScopedOcioEnv env(nullptr);
  const std::vector<float> in = {0.f, 0.001f, 0.0031308f, 0.01f, 0.05f, 0.18f, 0.5f, 0.9f, 1.f};
  const std::vector<float> out = dacrt::to_display(greys(in));
  REQUIRE(out.size() == 3 * in.size());
  CHECK(std::abs(out[0]) <= 1e-6f);
  CHECK(std::abs(out[3 * 5] - 0.461f) <= 0.005f);
  CHECK(std::abs(out[3 * 8] - 1.f) <= 1e-5f);
  for (size_t i = 0; i < in.size(); ++i) {
    INFO("linear " << in[i]);
    CHECK(out[3 * i] == doctest::Approx(srgb_encode(in[i])).epsilon(2e-3));
    // Grey stays grey.
    CHECK(out[3 * i + 1] == doctest::Approx(out[3 * i]).epsilon(1e-5));
    CHECK(out[3 * i + 2] == doctest::Approx(out[3 * i]).epsilon(1e-5));
    if (i > 0) CHECK(out[3 * i] > out[3 * (i - 1)]);
  }
}

TEST_CASE("to_display is monotonic and stays in [0, 1] for any input") {
  ScopedOcioEnv env(nullptr);
  std::vector<float> in;
  for (float v = 0.f; v < 4.f; v += 1.f / 256) in.push_back(v);
  const std::vector<float> out = dacrt::to_display(greys(in));
  for (size_t i = 1; i < in.size(); ++i) CHECK(out[3 * i] >= out[3 * (i - 1)]);
  CHECK(out[3 * (in.size() - 1)] == 1.f);  // > 1 clamps to 1

  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> bad = dacrt::to_display(
      greys({nan, -nan, inf, -inf, -1.f, -1e-3f, 1e30f, std::numeric_limits<float>::max()}));
  for (float v : bad) {
    CHECK(!std::isnan(v));
    CHECK(v >= 0.f);
    CHECK(v <= 1.f);
  }
  CHECK(bad[0] == 0.f);  // NaN → 0
  CHECK(bad[3] == 0.f);
  CHECK(bad[6] == 1.f);  // +inf → white
  CHECK(bad[9] == 0.f);  // -inf → black

  // A NaN in one channel does not spill into its neighbours.
  dacrt::Image mixed(2, 1);
  mixed.rgb = {nan, 0.18f, 0.18f, 0.18f, 0.18f, 0.18f};
  const std::vector<float> m = dacrt::to_display(mixed);
  CHECK(m[3] == doctest::Approx(0.461).epsilon(0.01));
  CHECK(m[4] == doctest::Approx(0.461).epsilon(0.01));
  CHECK(m[5] == doctest::Approx(0.461).epsilon(0.01));
}

TEST_CASE("to_display of primaries keeps them saturated") {
  ScopedOcioEnv env(nullptr);
  dacrt::Image image(3, 1);
  image.rgb = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const std::vector<float> out = dacrt::to_display(image);
  for (int p = 0; p < 3; ++p)
    for (int c = 0; c < 3; ++c) CHECK(std::abs(out[3 * p + c] - (p == c ? 1.f : 0.f)) <= 1e-4f);
}

TEST_CASE("write_preview_png writes rounded 8-bit sRGB that stb_image reads back") {
  ScopedOcioEnv env(nullptr);
  TempDir dir;
  const std::string path = (dir.path() / "preview.png").string();
  // 0.18 → 0.4613 → 117.6 → 118 rounded (truncation would give 117); 0.5 → 0.7354 → 187.5 → 188.
  const dacrt::Image image = greys({0.f, 0.18f, 0.5f, 1.f, 7.f, -1.f});
  dacrt::write_preview_png(path, image);

  int w = 0, h = 0, n = 0;
  unsigned char* pixels = stbi_load(path.c_str(), &w, &h, &n, 3);
  REQUIRE(pixels != nullptr);
  CHECK(w == 6);
  CHECK(h == 1);
  CHECK(n == 3);
  const int expected[] = {0, 118, 188, 255, 255, 0};
  for (int i = 0; i < 6; ++i)
    for (int c = 0; c < 3; ++c) {
      INFO("pixel " << i << " channel " << c);
      CHECK(int(pixels[3 * i + c]) == expected[i]);
    }
  stbi_image_free(pixels);
  size_t files = 0;
  for (auto it = fs::directory_iterator(dir.path()); it != fs::directory_iterator(); ++it) ++files;
  CHECK(files == 1);  // no temporary left behind
}

TEST_CASE("write_preview_png into a missing directory throws, naming the path") {
  ScopedOcioEnv env(nullptr);
  TempDir dir;
  const std::string path = (dir.path() / "missing" / "preview.png").string();
  bool threw = false;
  try {
    dacrt::write_preview_png(path, greys({0.5f}));
  } catch (const dacrt::Error& e) {
    threw = true;
    CHECK(std::string(e.what()).find(path) != std::string::npos);
  }
  CHECK(threw);
  CHECK(fs::is_empty(dir.path()));
}

TEST_CASE("to_display with $OCIO naming a missing config throws, naming the config") {
  TempDir dir;
  const std::string config = (dir.path() / "no-such-config.ocio").string();
  {
    ScopedOcioEnv env(config.c_str());
    bool threw = false;
    try {
      dacrt::to_display(greys({0.18f}));
    } catch (const dacrt::Error& e) {
      threw = true;
      const std::string message = e.what();
      CHECK(message.find(config) != std::string::npos);
      CHECK(message.find('\n') == std::string::npos);
    }
    CHECK(threw);
    CHECK_THROWS_AS(dacrt::write_preview_png((dir.path() / "p.png").string(), greys({0.18f})),
                    dacrt::Error);
    CHECK(fs::is_empty(dir.path()));
  }
  // The cache is keyed by $OCIO: unset again, the built-in transform works.
  ScopedOcioEnv env(nullptr);
  CHECK(dacrt::to_display(greys({0.18f}))[0] == doctest::Approx(0.461).epsilon(0.01));
}

TEST_CASE("to_display with $OCIO uses the config's default display and view") {
  TempDir dir;
  const fs::path config = dir.path() / "config.ocio";
  // scene_linear → default display "Test" → its first view, a gamma 2.0 encoding. Different
  // from the built-in sRGB curve, so the test sees which path was taken.
  std::ofstream(config) << R"(ocio_profile_version: 2
roles:
  default: linear
  scene_linear: linear
displays:
  Test:
    - !<View> {name: Gamma2, colorspace: gamma2}
    - !<View> {name: Raw, colorspace: linear}
colorspaces:
  - !<ColorSpace>
    name: linear
  - !<ColorSpace>
    name: gamma2
    from_reference: !<ExponentTransform> {value: 2, direction: inverse}
)";
  {
    ScopedOcioEnv env(config.c_str());
    const std::vector<float> out = dacrt::to_display(greys({0.f, 0.25f, 1.f, 4.f}));
    CHECK(out[0] == doctest::Approx(0.0));
    CHECK(out[3] == doctest::Approx(0.5).epsilon(1e-4));
    CHECK(out[6] == doctest::Approx(1.0).epsilon(1e-4));
    CHECK(out[9] == 1.f);
  }
  ScopedOcioEnv env(nullptr);
  CHECK(dacrt::to_display(greys({0.25f}))[0] == doctest::Approx(srgb_encode(0.25)).epsilon(2e-3));
}
