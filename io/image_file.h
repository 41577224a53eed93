// Images written by their names: a file's extension picks its format. EXR (.exr) and Radiance
// HDR (.hdr) hold the scene-linear values; PNG (.png) and JPEG (.jpg, .jpeg) hold 8-bit display
// values through the preview's display transform (io/color.h: a view and an exposure). What
// `render -o` and `--preview`, `dacrt convert` and Python's write_image() write, by one writer, so
// the same image and display options give the same bytes from each. Every file is written to a
// temporary name and renamed (util/atomic_file.h).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "dacrt/io/color.h"
#include "dacrt/io/exr.h"
#include "dacrt/util/image.h"

namespace dacrt {

enum class ImageFormat : uint8_t { exr, png, jpeg, hdr };

// The format the extension of `path` names, in any case (".exr", ".PNG", ".Jpeg"), or nothing.
std::optional<ImageFormat> image_format(const std::string& path);
// The extensions written: ".exr, .png, .jpg, .jpeg or .hdr", for messages.
const char* image_extensions();
// "EXR", "PNG", "JPEG", "HDR".
const char* format_name(ImageFormat format);
// Whether the format holds display values (PNG, JPEG), which a view and an exposure change.
bool holds_display_values(ImageFormat format);

// The format of `path`, which `option` ("-o", "--preview", "OUT") names; a UsageError naming the
// option, the file and the extensions accepted when the extension is none of them.
ImageFormat output_format(const std::string& option, const std::string& path);

// The image's 8-bit display values (R, G, B per pixel, rows from the top): to_display's, rounded
// to nearest. What PNG and JPEG files hold.
std::vector<uint8_t> display_bytes(const Image& image, const DisplayOptions& options = {});

// Writes `image` to `path` in the format its name says (output_format(option, path)): EXR with
// `metadata` in its header; HDR as RGBE (negative and NaN values as 0); PNG (8-bit, alpha when
// given) and JPEG (quality 95, no chroma subsampling) through the display transform of `display`.
// `alpha`, empty or one value per pixel, goes into EXR's A channel and PNG's alpha (clamped to
// [0, 1]; the colours are written as given, not divided by it); JPEG and HDR hold none.
// Throws UsageError for an unknown extension, Error when the file cannot be written.
void write_image(const std::string& path, const Image& image, const DisplayOptions& display = {},
                 const ExrMetadata& metadata = {}, std::span<const float> alpha = {},
                 const std::string& option = "the output");

}  // namespace dacrt
