// Display previews through OpenColorIO: scene-linear Rec.709 → a display/view, 8-bit PNG.
// Uses the config in $OCIO when it is set, else a few views built from OCIO's built-in transforms:
// plain sRGB (the default) and the ACES 1.0 SDR-video output transform, each for an sRGB and a
// Rec.1886 display.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dacrt/util/image.h"

namespace dacrt {

// How a preview is made from the scene-linear image.
struct DisplayOptions {
  // A name from display_views(): empty for the default view. With $OCIO, "DISPLAY/VIEW", or
  // "VIEW" for a view of the config's default display.
  std::string view;
  double exposure = 0.0;  // stops: the image is scaled by 2^exposure before the view
};

// The views a preview can use, from $OCIO's config when it is set, else the built-in ones.
struct DisplayViews {
  std::vector<std::string> names;
  std::string default_name;
};
DisplayViews display_views();

// Builds the display transform of `options` (a view from $OCIO's config, or a built-in one), so
// that a broken config or an unknown view is an error before a render rather than after. Throws
// dacrt::Error naming the view and the valid ones.
void check_display_transform(const DisplayOptions& options = {});
// The files a preview reads: $OCIO's config and every LUT its transforms name that resolves to a
// file (none without $OCIO), so that no output can overwrite them.
std::vector<std::string> display_input_files();
// Whether OpenColorIO's own warnings (a config's deprecated keys, say) reach stderr, each as one
// "dacrt: warning: OpenColorIO: …" line; --quiet turns them off.
void set_color_warnings(bool shown);
// Converts to the display's encoded values in [0, 1], interleaved RGB.
std::vector<float> to_display(const Image& image, const DisplayOptions& options = {});
// Writes a PNG preview (temporary name, then rename). Throws dacrt::Error on failure.
void write_preview_png(const std::string& path, const Image& image,
                       const DisplayOptions& options = {});
// Writes display-encoded 8-bit RGB (3 * width * height bytes, rows from the top) as a PNG, the
// same way: for images that are already display values (false-colour maps).
void write_png(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

}  // namespace dacrt
