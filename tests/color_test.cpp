// Display conversion through OpenColorIO: the built-in sRGB chain's known values, the ACES views'
// tone mapping, exposure, robustness to bad pixels, the PNG preview's 8-bit values, and $OCIO
// handling (a valid config and its views, a missing one).
#include "dacrt/io/color.h"

#include <doctest/doctest.h>
#include <stb_image.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>

#include "ocio_config.h"
#include "temp_dir.h"
#include "dacrt/util/error.h"

namespace fs = std::filesystem;
using dacrt::test::ScopedOcioEnv;
using dacrt::test::TempDir;

namespace {

// One grey pixel per value.
dacrt::Image greys(const std::vector<float>& values) {
  dacrt::Image image(int(values.size()), 1);
  for (size_t i = 0; i < values.size(); ++i)
    for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] = values[i];
  return image;
}

// 'name', as error messages quote a view (appended: "'" + name + "'" meets GCC 12's false
// -Wrestrict warning).
std::string quoted(const std::string& name) {
  return std::string(1, '\'').append(name).append(1, '\'');
}

// The message of the Error that checking `view` throws, or "" when it does not throw.
std::string view_error(const std::string& view) {
  try {
    dacrt::check_display_transform({view});
  } catch (const dacrt::Error& e) {
    return e.what();
  }
  return "";
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

TEST_CASE("to_display is monotonic and stays in [0, 1] for any input, in every built-in view") {
  ScopedOcioEnv env(nullptr);
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const dacrt::DisplayViews views = dacrt::display_views();
  REQUIRE(views.names.size() >= 2);
  for (const std::string& view : views.names) {
    INFO("view " << view);
    std::vector<float> in;
    for (float v = 0.f; v < 64.f; v += 1.f / 256) in.push_back(v);
    const std::vector<float> out = dacrt::to_display(greys(in), {view});
    for (size_t i = 1; i < in.size(); ++i) CHECK(out[3 * i] >= out[3 * (i - 1)]);
    CHECK(out[3 * (in.size() - 1)] == 1.f);  // 64 is white in every view

    const std::vector<float> bad = dacrt::to_display(
        greys({nan, -nan, inf, -inf, -1.f, -1e-3f, 1e30f, std::numeric_limits<float>::max()}),
        {view});
    for (float v : bad) {
      CHECK(!std::isnan(v));
      CHECK(v >= 0.f);
      CHECK(v <= 1.f);
    }
    CHECK(bad[0] == bad[9]);  // NaN → what 0 gives, -inf → black
    CHECK(bad[3] == bad[9]);
    CHECK(bad[9] <= 1e-4f);
    CHECK(bad[6] == 1.f);  // +inf → white
    if (view == "sRGB") CHECK(bad[0] == 0.f);
  }

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

TEST_CASE(
    "the default view is the built-in sRGB one, and exposure 0 changes nothing, bit for bit") {
  ScopedOcioEnv env(nullptr);
  const dacrt::DisplayViews views = dacrt::display_views();
  CHECK(views.default_name == "sRGB");
  CHECK(views.names.front() == "sRGB");
  std::vector<float> in;
  for (float v = -1.f; v < 8.f; v += 1.f / 64) in.push_back(v);
  const dacrt::Image image = greys(in);
  const std::vector<float> by_default = dacrt::to_display(image);
  CHECK(dacrt::to_display(image, {"sRGB", 0.0}) == by_default);
  CHECK(dacrt::to_display(image, {"", -0.0}) == by_default);
}

TEST_CASE("ACES 1.0 SDR-video views tone-map: mid-grey 0.18 → 0.356 on sRGB, highlights below 1") {
  ScopedOcioEnv env(nullptr);
  const std::vector<float> in = {0.f, 0.18f, 0.5f, 1.f, 2.f, 4.f, 8.f};
  const std::vector<float> aces = dacrt::to_display(greys(in), {"ACES 1.0 SDR-video (sRGB)"});
  const std::vector<float> srgb = dacrt::to_display(greys(in), {"sRGB"});
  // From the ACES 1.0 CTL: the RRT and the 48-nit ODT tone scale map 0.18 to 4.8 cd/m²; the video
  // ODT makes that (4.8 − 0.02) / (48 − 0.02) = 0.09962 of white, its dark-to-dim surround
  // correction (Y^0.9811) 0.10406, and the sRGB encoding 0.35596 (8 bits: 91, against 118 in the
  // plain sRGB view). On Rec.1886 (gamma 2.4), 0.10406^(1/2.4) = 0.38954.
  CHECK(aces[3] == doctest::Approx(0.35596).epsilon(1e-3));
  CHECK(dacrt::to_display(greys({0.18f}), {"ACES 1.0 SDR-video (Rec.1886)"})[0] ==
        doctest::Approx(0.38954).epsilon(1e-3));
  CHECK(dacrt::to_display(greys({0.18f}), {"Rec.1886"})[0] ==
        doctest::Approx(std::pow(0.18, 1 / 2.4)).epsilon(1e-3));
  CHECK(aces[0] <= 1e-4f);
  for (size_t i = 0; i < in.size(); ++i) {
    INFO("linear " << in[i]);
    CHECK(aces[3 * i + 1] == doctest::Approx(aces[3 * i]).epsilon(1e-4));  // grey stays grey
    CHECK(aces[3 * i + 2] == doctest::Approx(aces[3 * i]).epsilon(1e-4));
    if (i > 0) CHECK(aces[3 * i] > aces[3 * (i - 1)]);
    // Highlights that sRGB clips to white keep their gradation (1 → 0.81, 4 → 0.955).
    if (in[i] > 1.f) CHECK(srgb[3 * i] == 1.f);
    if (in[i] >= 1.f) CHECK(aces[3 * i] < 0.99f);
  }
  CHECK(aces[3 * 3] == doctest::Approx(0.812).epsilon(2e-3));
  // A saturated red stays red: Rec.709 in, Rec.709 out.
  dacrt::Image red(1, 1);
  red.rgb = {0.5f, 0.f, 0.f};
  const std::vector<float> r = dacrt::to_display(red, {"ACES 1.0 SDR-video (sRGB)"});
  CHECK(r[0] > 0.5f);
  CHECK(r[1] < 0.05f);
  CHECK(r[2] < 0.05f);
}

TEST_CASE("exposure +1 is the image doubled, -1 halved, in every view, a non-finite one throws") {
  ScopedOcioEnv env(nullptr);
  std::vector<float> in;
  for (float v = 0.f; v < 2.f; v += 1.f / 32) in.push_back(v);
  const dacrt::Image image = greys(in);
  dacrt::Image doubled = image, halved = image;
  for (float& v : doubled.rgb) v *= 2.f;
  for (float& v : halved.rgb) v *= 0.5f;
  for (const std::string& view : dacrt::display_views().names) {
    INFO("view " << view);
    const std::vector<float> brighter = dacrt::to_display(image, {view, 1.0});
    CHECK(brighter == dacrt::to_display(doubled, {view}));
    CHECK(brighter != dacrt::to_display(image, {view}));
    CHECK(dacrt::to_display(image, {view, -1.0}) == dacrt::to_display(halved, {view}));
  }
  for (double stops : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    CHECK_THROWS_AS(dacrt::to_display(image, {"", stops}), dacrt::Error);
    CHECK_THROWS_AS(dacrt::check_display_transform({"", stops}), dacrt::Error);
  }
}

TEST_CASE("an unknown view throws one line naming it and the valid views") {
  ScopedOcioEnv env(nullptr);
  for (const char* view : {"Nope", "srgb", "Test/Gamma2"}) {
    const std::string message = view_error(view);
    INFO(view << " → " << message);
    CHECK(message.find(quoted(view)) != std::string::npos);
    CHECK(message.find("'sRGB'") != std::string::npos);
    CHECK(message.find("'ACES 1.0 SDR-video (sRGB)'") != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
    CHECK_THROWS_AS(dacrt::to_display(greys({0.18f}), {view}), dacrt::Error);
  }
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
  // scene_linear → default display "Test" → its first view, a gamma 2.0 encoding.
  std::ofstream(config) << dacrt::test::ocio_test_config;
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

TEST_CASE("with $OCIO, the views are the config's DISPLAY/VIEW pairs, each selectable") {
  TempDir dir;
  const fs::path config = dir.path() / "config.ocio";
  std::ofstream(config) << dacrt::test::ocio_test_config;
  ScopedOcioEnv env(config.c_str());
  const dacrt::DisplayViews views = dacrt::display_views();
  CHECK(views.default_name == "Test/Gamma2");
  CHECK(views.names == std::vector<std::string>{"Test/Gamma2", "Test/Raw", "Other/Half"});

  const dacrt::Image image = greys({0.25f, 1.f});
  const std::vector<float> gamma2 = {0.5f, 0.5f, 0.5f, 1.f, 1.f, 1.f};
  const std::vector<float> raw = {0.25f, 0.25f, 0.25f, 1.f, 1.f, 1.f};
  const std::vector<float> half = {0.125f, 0.125f, 0.125f, 0.5f, 0.5f, 0.5f};
  auto near = [](const std::vector<float>& a, const std::vector<float>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
      if (std::abs(a[i] - b[i]) > 1e-4f) return false;
    return true;
  };
  CHECK(near(dacrt::to_display(image), gamma2));
  CHECK(near(dacrt::to_display(image, {"Test/Raw"}), raw));
  CHECK(near(dacrt::to_display(image, {"Raw"}), raw));  // a view of the default display
  CHECK(near(dacrt::to_display(image, {"Other/Half"}), half));
  CHECK(near(dacrt::to_display(image, {"Other/Half", 1.0}), raw));
  // "Half" is not a view of the default display, and the built-in names are not the config's.
  for (const char* view : {"Half", "sRGB", "Other/Raw"}) {
    const std::string message = view_error(view);
    INFO(view << " → " << message);
    CHECK(message.find(config.string()) != std::string::npos);
    CHECK(message.find(quoted(view)) != std::string::npos);
    CHECK(message.find("'Other/Half'") != std::string::npos);
  }
}
