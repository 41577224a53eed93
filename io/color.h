// Display previews through OpenColorIO: scene-linear Rec.709 → sRGB display, 8-bit PNG.
// Uses the config in $OCIO when it is set, else OCIO's built-in sRGB display transform.
#pragma once

#include <string>

#include "io/image.h"

namespace dacrt {

// Builds the display transform (from $OCIO's config and its default view, or the built-in one),
// so that a broken config is an error before a render rather than after. Throws dacrt::Error.
void check_display_transform();
// Converts to the display's encoded values in [0, 1], interleaved RGB.
std::vector<float> to_display(const Image& image);
// Writes a PNG preview (temporary name, then rename). Throws dacrt::Error on failure.
void write_preview_png(const std::string& path, const Image& image);

}  // namespace dacrt
