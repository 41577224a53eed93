// Display previews through OpenColorIO. With $OCIO set, the config's scene_linear role goes through
// its default display and view. Without it, OCIO 2.1 ships no config file, so the chain is built
// from a raw config: linear Rec.709 → CIE XYZ (D65) by a matrix, then the built-in display
// transform "DISPLAY - CIE-XYZ-D65_to_sRGB" (piecewise sRGB encoding).
#include "io/color.h"

#include <OpenColorIO/OpenColorIO.h>
#include <stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <system_error>

#include "util/atomic_file.h"
#include "util/error.h"
#include "util/paths.h"

namespace OCIO = OCIO_NAMESPACE;

namespace dacrt {
namespace {

// Keeps values that a matrix and a curve can carry without overflowing to inf (inf − inf = NaN in
// the matrices); anything this bright is white on any display anyway.
constexpr float kMaxSceneValue = 1e6f;

// RGB → XYZ for the Rec.709 primaries and D65 white, derived as in SMPTE RP 177 from the same
// chromaticities OCIO's built-ins use, so that white maps to exactly (1, 1, 1) after its inverse.
std::array<double, 16> rec709_to_xyz_d65() {
  const double xy[4][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}, {0.3127, 0.3290}};
  double p[3][3];  // columns: XYZ of each primary with Y = 1
  for (int c = 0; c < 3; ++c) {
    p[0][c] = xy[c][0] / xy[c][1];
    p[1][c] = 1.0;
    p[2][c] = (1.0 - xy[c][0] - xy[c][1]) / xy[c][1];
  }
  const double w[3] = {xy[3][0] / xy[3][1], 1.0, (1.0 - xy[3][0] - xy[3][1]) / xy[3][1]};
  // Solve p · s = w for the primaries' scales s (Cramer's rule).
  auto det3 = [](const double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double d = det3(p);
  double s[3];
  for (int c = 0; c < 3; ++c) {
    double q[3][3];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) q[r][k] = (k == c) ? w[r] : p[r][k];
    s[c] = det3(q) / d;
  }
  std::array<double, 16> m{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m[4 * r + c] = p[r][c] * s[c];
  m[15] = 1.0;
  return m;
}

OCIO::ConstProcessorRcPtr builtin_srgb_processor() {
  auto to_xyz = OCIO::MatrixTransform::Create();
  const std::array<double, 16> m = rec709_to_xyz_d65();
  to_xyz->setMatrix(m.data());
  auto to_display = OCIO::BuiltinTransform::Create();
  to_display->setStyle("DISPLAY - CIE-XYZ-D65_to_sRGB");
  auto group = OCIO::GroupTransform::Create();
  group->appendTransform(to_xyz);
  group->appendTransform(to_display);
  return OCIO::Config::CreateRaw()->getProcessor(group);
}

OCIO::ConstProcessorRcPtr config_processor(const std::string& config_path) {
  OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromEnv();
  if (!config->hasRole(OCIO::ROLE_SCENE_LINEAR))
    throw Error("OCIO config '" + config_path + "' has no scene_linear role");
  const char* display = config->getDefaultDisplay();
  if (!display || !*display) throw Error("OCIO config '" + config_path + "' defines no display");
  const char* view = config->getDefaultView(display);
  if (!view || !*view)
    throw Error("OCIO config '" + config_path + "' defines no view for display '" + display + "'");
  auto transform = OCIO::DisplayViewTransform::Create();
  transform->setSrc(OCIO::ROLE_SCENE_LINEAR);
  transform->setDisplay(display);
  transform->setView(view);
  return config->getProcessor(transform);
}

// One processor per process, rebuilt when $OCIO changes (the value is the cache key).
OCIO::ConstCPUProcessorRcPtr display_processor() {
  static std::mutex mutex;
  static std::string cached_key;
  static OCIO::ConstCPUProcessorRcPtr cached;

  const char* env = std::getenv("OCIO");
  const std::string config_path = env ? env : "";
  const std::string key =
      config_path.empty() ? std::string("builtin:sRGB") : "config:" + config_path;

  std::lock_guard<std::mutex> lock(mutex);
  if (cached && cached_key == key) return cached;
  if (!config_path.empty()) check_input_file(config_path, "OCIO config ($OCIO)");
  try {
    OCIO::ConstProcessorRcPtr processor =
        config_path.empty() ? builtin_srgb_processor() : config_processor(config_path);
    cached = processor->getDefaultCPUProcessor();
    cached_key = key;
    return cached;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    if (config_path.empty())
      throw Error("cannot build OpenColorIO's built-in sRGB display transform: " +
                  one_line(e.what()));
    throw Error("cannot use OCIO config '" + config_path + "': " + one_line(e.what()));
  }
}

float sanitize_scene(float v) {
  if (std::isnan(v)) return 0.f;
  return std::clamp(v, -kMaxSceneValue, kMaxSceneValue);
}

float sanitize_display(float v) {
  if (std::isnan(v)) return 0.f;
  return std::clamp(v, 0.f, 1.f);
}

}  // namespace

std::vector<float> to_display(const Image& image) {
  const size_t count =
      size_t(3) * size_t(std::max(image.width, 0)) * size_t(std::max(image.height, 0));
  if (image.rgb.size() != count)
    throw Error("image of " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                " has " + std::to_string(image.rgb.size()) + " values, not " +
                std::to_string(count));
  std::vector<float> out(image.rgb.size());
  std::transform(image.rgb.begin(), image.rgb.end(), out.begin(), sanitize_scene);
  if (out.empty()) return out;

  OCIO::ConstCPUProcessorRcPtr processor = display_processor();
  try {
    OCIO::PackedImageDesc desc(out.data(), image.width, image.height, 3);
    processor->apply(desc);
  } catch (const std::exception& e) {
    throw Error("OpenColorIO could not convert the preview: " + one_line(e.what()));
  }
  std::transform(out.begin(), out.end(), out.begin(), sanitize_display);
  return out;
}

void check_display_transform() {
  display_processor();
}

void write_preview_png(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0)
    throw Error("cannot write PNG '" + path + "': the image is empty");
  const std::vector<float> display = to_display(image);
  std::vector<uint8_t> pixels(display.size());
  // Round to nearest: values are already clamped to [0, 1].
  std::transform(display.begin(), display.end(), pixels.begin(),
                 [](float v) { return uint8_t(std::lround(v * 255.f)); });

  std::vector<unsigned char> png;
  auto append = [](void* context, void* data, int size) {
    auto* bytes = static_cast<std::vector<unsigned char>*>(context);
    bytes->insert(bytes->end(), static_cast<unsigned char*>(data),
                  static_cast<unsigned char*>(data) + size);
  };
  if (!stbi_write_png_to_func(append, &png, image.width, image.height, 3, pixels.data(),
                              3 * image.width))
    throw Error("cannot write PNG '" + path + "': encoding failed");
  write_atomically(path, "PNG", [&](std::ofstream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
  });
}

}  // namespace dacrt
