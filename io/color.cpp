// Display previews through OpenColorIO. With $OCIO set, the config's scene_linear role goes through
// one of its displays and views (its default one unless DisplayOptions::view names another).
// Without it, OCIO 2.1 ships no config file, so each built-in view is a chain built in a raw
// config: linear Rec.709 → CIE XYZ (D65) by a matrix, for the ACES views then → ACES2065-1 (the
// inverse of the built-in "UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD", as the ACES studio config's
// "Linear Rec.709 (sRGB)" does) → an ACES output transform (display-referred XYZ), then a built-in
// display transform such as "DISPLAY - CIE-XYZ-D65_to_sRGB" (piecewise sRGB encoding). The ACES
// chain is the ACES studio config's view "ACES 1.0 - SDR Video" of its display "sRGB - Display".
#include "dacrt/io/color.h"

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

#include "dacrt/io/image_file.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/text.h"
#include "dacrt/util/paths.h"

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

// A view of the built-in ones: an optional ACES output transform, then a display's encoding.
struct BuiltinView {
  const char* name;
  const char* aces_output;  // ACES2065-1 → display-referred XYZ (D65), or nullptr: no tone mapping
  const char* display;      // CIE XYZ (D65) → the display's encoded values
};

constexpr const char* kAcesSdrVideo = "ACES-OUTPUT - ACES2065-1_to_CIE-XYZ-D65 - SDR-VIDEO_1.0";
constexpr const char* kSrgbDisplay = "DISPLAY - CIE-XYZ-D65_to_sRGB";
constexpr const char* kRec1886Display = "DISPLAY - CIE-XYZ-D65_to_REC.1886-REC.709";
// The first is the default.
constexpr BuiltinView kBuiltinViews[] = {
    {"sRGB", nullptr, kSrgbDisplay},
    {"ACES 1.0 SDR-video (sRGB)", kAcesSdrVideo, kSrgbDisplay},
    {"Rec.1886", nullptr, kRec1886Display},
    {"ACES 1.0 SDR-video (Rec.1886)", kAcesSdrVideo, kRec1886Display},
};

// $OCIO, or "" when it is unset (or empty).
std::string config_path() {
  const char* env = std::getenv("OCIO");
  return env ? env : "";
}

// Runs `build`, turning OpenColorIO's exceptions into an Error naming the config in `path` (or
// the built-in transforms when `path` is empty).
template <class Build>
auto with_ocio_errors(const std::string& path, Build build) {
  try {
    return build();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    if (path.empty())
      throw Error("cannot build OpenColorIO's built-in display transforms: " + one_line(e.what()));
    throw Error("cannot use OCIO config '" + path + "': " + one_line(e.what()));
  }
}

// "'a', 'b', 'c'": the valid names in an error.
std::string quoted_list(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "'" : ", '") + name + "'";
  return list;
}

std::vector<std::string> builtin_view_names() {
  std::vector<std::string> names;
  for (const BuiltinView& v : kBuiltinViews) names.push_back(v.name);
  return names;
}

OCIO::ConstProcessorRcPtr builtin_processor(const std::string& view) {
  const std::string name = view.empty() ? kBuiltinViews[0].name : view;
  const auto* found = std::find_if(std::begin(kBuiltinViews), std::end(kBuiltinViews),
                                   [&](const BuiltinView& v) { return name == v.name; });
  if (found == std::end(kBuiltinViews))
    throw SettingError("no view '" + name + "'" + did_you_mean(name, builtin_view_names()) +
                       " (without $OCIO the views are " + quoted_list(builtin_view_names()) + ")");
  return with_ocio_errors("", [&] {
    auto group = OCIO::GroupTransform::Create();
    auto to_xyz = OCIO::MatrixTransform::Create();
    const std::array<double, 16> m = rec709_to_xyz_d65();
    to_xyz->setMatrix(m.data());
    group->appendTransform(to_xyz);
    auto append_builtin = [&](const char* style, OCIO::TransformDirection direction) {
      auto transform = OCIO::BuiltinTransform::Create();
      transform->setStyle(style);
      transform->setDirection(direction);
      group->appendTransform(transform);
    };
    if (found->aces_output) {
      append_builtin("UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD", OCIO::TRANSFORM_DIR_INVERSE);
      append_builtin(found->aces_output, OCIO::TRANSFORM_DIR_FORWARD);
    }
    append_builtin(found->display, OCIO::TRANSFORM_DIR_FORWARD);
    return OCIO::Config::CreateRaw()->getProcessor(group);
  });
}

// $OCIO's config, checked for what a preview needs (a scene_linear role, a default view). Read
// once per path, so that its warnings are said once.
OCIO::ConstConfigRcPtr load_config(const std::string& path) {
  check_input_file(path, "OCIO config ($OCIO)");
  static std::mutex mutex;
  static std::pair<std::string, OCIO::ConstConfigRcPtr> cached;
  std::lock_guard<std::mutex> lock(mutex);
  if (cached.second && cached.first == path) return cached.second;
  OCIO::ConstConfigRcPtr config =
      with_ocio_errors(path, [&] { return OCIO::Config::CreateFromFile(path.c_str()); });
  if (!config->hasRole(OCIO::ROLE_SCENE_LINEAR))
    throw Error("OCIO config '" + path + "' has no scene_linear role");
  const char* display = config->getDefaultDisplay();
  if (!display || !*display) throw Error("OCIO config '" + path + "' defines no display");
  const char* view = config->getDefaultView(display);
  if (!view || !*view)
    throw Error("OCIO config '" + path + "' defines no view for display '" + display + "'");
  cached = {path, config};
  return config;
}

struct ConfigView {
  std::string display, view;
  std::string name() const { return display + "/" + view; }
};

// Every display/view of the config, the default first.
std::vector<ConfigView> config_views(const OCIO::Config& config) {
  const std::string default_display = config.getDefaultDisplay();
  std::vector<ConfigView> views = {
      {default_display, config.getDefaultView(default_display.c_str())}};
  for (int d = 0; d < config.getNumDisplays(); ++d) {
    const char* display = config.getDisplay(d);
    for (int v = 0; v < config.getNumViews(display); ++v) {
      const ConfigView view{display, config.getView(display, v)};
      if (view.name() != views[0].name()) views.push_back(view);
    }
  }
  return views;
}

OCIO::ConstProcessorRcPtr config_processor(const std::string& path, const std::string& name) {
  OCIO::ConstConfigRcPtr config = load_config(path);
  const std::vector<ConfigView> views = config_views(*config);
  // "DISPLAY/VIEW" first, then "VIEW" of the default display.
  auto found = std::find_if(views.begin(), views.end(),
                            [&](const ConfigView& v) { return name.empty() || name == v.name(); });
  if (found == views.end())
    found = std::find_if(views.begin(), views.end(), [&](const ConfigView& v) {
      return v.display == views[0].display && name == v.view;
    });
  if (found == views.end()) {
    std::vector<std::string> names;
    for (const ConfigView& v : views) names.push_back(v.name());
    throw SettingError("OCIO config '" + path + "' ($OCIO) has no view '" + name + "'" +
                       did_you_mean(name, names) + " (its views are " + quoted_list(names) + ")");
  }
  return with_ocio_errors(path, [&] {
    auto transform = OCIO::DisplayViewTransform::Create();
    transform->setSrc(OCIO::ROLE_SCENE_LINEAR);
    transform->setDisplay(found->display.c_str());
    transform->setView(found->view.c_str());
    return config->getProcessor(transform);
  });
}

// One processor per process, rebuilt when $OCIO or the view changes.
OCIO::ConstCPUProcessorRcPtr display_processor(const std::string& view) {
  static std::mutex mutex;
  static std::pair<std::string, std::string> cached_key;  // $OCIO, view
  static OCIO::ConstCPUProcessorRcPtr cached;

  const std::string path = config_path();
  const std::pair<std::string, std::string> key = {path, view};
  std::lock_guard<std::mutex> lock(mutex);
  if (cached && cached_key == key) return cached;
  OCIO::ConstProcessorRcPtr processor =
      path.empty() ? builtin_processor(view) : config_processor(path, view);
  cached = with_ocio_errors(path, [&] { return processor->getDefaultCPUProcessor(); });
  cached_key = key;
  return cached;
}

// 2^stops, checked.
float exposure_scale(double stops) {
  if (!std::isfinite(stops))
    throw Error("the exposure must be a finite number of stops, not " + std::to_string(stops));
  return float(std::exp2(stops));
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

DisplayViews display_views() {
  const std::string path = config_path();
  DisplayViews views;
  if (path.empty()) {
    views.names = builtin_view_names();
  } else {
    for (const ConfigView& v : config_views(*load_config(path))) views.names.push_back(v.name());
  }
  views.default_name = views.names.front();
  return views;
}

std::vector<float> to_display(const Image& image, const DisplayOptions& options) {
  const size_t count =
      size_t(3) * size_t(std::max(image.width, 0)) * size_t(std::max(image.height, 0));
  if (image.rgb.size() != count)
    throw Error("image of " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                " has " + std::to_string(image.rgb.size()) + " values, not " +
                std::to_string(count));
  const float scale = exposure_scale(options.exposure);
  std::vector<float> out(image.rgb.size());
  std::transform(image.rgb.begin(), image.rgb.end(), out.begin(),
                 [scale](float v) { return sanitize_scene(v * scale); });
  if (out.empty()) return out;

  OCIO::ConstCPUProcessorRcPtr processor = display_processor(options.view);
  try {
    OCIO::PackedImageDesc desc(out.data(), image.width, image.height, 3);
    processor->apply(desc);
  } catch (const std::exception& e) {
    throw Error("OpenColorIO could not convert the preview: " + one_line(e.what()));
  }
  std::transform(out.begin(), out.end(), out.begin(), sanitize_display);
  return out;
}

namespace {

// The FileTransform sources in `t` and the groups it holds.
void collect_sources(const OCIO::ConstTransformRcPtr& t, std::vector<std::string>& sources) {
  if (!t) return;
  if (auto file = OCIO::DynamicPtrCast<const OCIO::FileTransform>(t)) {
    if (file->getSrc() && *file->getSrc()) sources.emplace_back(file->getSrc());
  } else if (auto group = OCIO::DynamicPtrCast<const OCIO::GroupTransform>(t)) {
    for (int i = 0; i < group->getNumTransforms(); ++i)
      collect_sources(group->getTransform(i), sources);
  }
}

bool color_warnings_shown = true;

extern "C" void print_ocio_message(const char* message) {
  if (color_warnings_shown)
    std::fprintf(stderr, "dacrt: warning: OpenColorIO: %s\n", one_line(message).c_str());
}

}  // namespace

void set_color_warnings(bool shown) {
  color_warnings_shown = shown;
  OCIO::SetLoggingFunction(&print_ocio_message);
}

std::vector<std::string> display_input_files() {
  const std::string path = config_path();
  if (path.empty()) return {};
  std::vector<std::string> files = {path};
  const OCIO::ConstConfigRcPtr config = load_config(path);
  std::vector<std::string> sources;
  with_ocio_errors(path, [&] {
    for (int i = 0;
         i < config->getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL);
         ++i) {
      auto space = config->getColorSpace(config->getColorSpaceNameByIndex(
          OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL, i));
      if (!space) continue;
      collect_sources(space->getTransform(OCIO::COLORSPACE_DIR_TO_REFERENCE), sources);
      collect_sources(space->getTransform(OCIO::COLORSPACE_DIR_FROM_REFERENCE), sources);
    }
    for (int i = 0; i < config->getNumLooks(); ++i) {
      auto look = config->getLook(config->getLookNameByIndex(i));
      if (!look) continue;
      collect_sources(look->getTransform(), sources);
      collect_sources(look->getInverseTransform(), sources);
    }
    for (int i = 0; i < config->getNumViewTransforms(); ++i) {
      auto view = config->getViewTransform(config->getViewTransformNameByIndex(i));
      if (!view) continue;
      collect_sources(view->getTransform(OCIO::VIEWTRANSFORM_DIR_TO_REFERENCE), sources);
      collect_sources(view->getTransform(OCIO::VIEWTRANSFORM_DIR_FROM_REFERENCE), sources);
    }
    for (int i = 0; i < config->getNumNamedTransforms(OCIO::NAMEDTRANSFORM_ALL); ++i) {
      auto named = config->getNamedTransform(
          config->getNamedTransformNameByIndex(OCIO::NAMEDTRANSFORM_ALL, i));
      if (!named) continue;
      collect_sources(named->getTransform(OCIO::TRANSFORM_DIR_FORWARD), sources);
      collect_sources(named->getTransform(OCIO::TRANSFORM_DIR_INVERSE), sources);
    }
    return 0;
  });
  const OCIO::ConstContextRcPtr context = config->getCurrentContext();
  for (const std::string& src : sources) {
    try {
      files.emplace_back(context->resolveFileLocation(src.c_str()));
    } catch (const std::exception&) {
      // A file the config names but that is not there: an output there is no input either.
    }
  }
  return files;
}

void check_display_transform(const DisplayOptions& options) {
  exposure_scale(options.exposure);
  display_processor(options.view);
}

void write_preview_png(const std::string& path, const Image& image, const DisplayOptions& options) {
  if (image.width <= 0 || image.height <= 0)
    throw Error("cannot write PNG '" + path + "': the image is empty");
  write_png(path, image.width, image.height, display_bytes(image, options));
}

void write_png(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != size_t(3) * size_t(width) * size_t(height))
    throw Error("cannot write PNG '" + path + "': the image is empty or its size is wrong");
  std::vector<unsigned char> png;
  auto append = [](void* context, void* data, int size) {
    auto* bytes = static_cast<std::vector<unsigned char>*>(context);
    bytes->insert(bytes->end(), static_cast<unsigned char*>(data),
                  static_cast<unsigned char*>(data) + size);
  };
  if (!stbi_write_png_to_func(append, &png, width, height, 3, rgb.data(), 3 * width))
    throw Error("cannot write PNG '" + path + "': encoding failed");
  write_atomically(path, "PNG", [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
  });
}

}  // namespace dacrt
