#include "apps/convert.h"

#include <cstdio>
#include <string>
#include <vector>

#include "dacrt/io/color.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/image_file.h"
#include "dacrt/render/request.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/paths.h"
#include "dacrt/util/text.h"

namespace dacrt {
namespace {

constexpr const char* convert_help = R"help(Usage: dacrt convert IN.exr OUT [options]

Writes the image of an OpenEXR file (a dacrt render's, or any EXR with R, G and B channels) in
the format OUT's name says: .png (8-bit) or .jpg/.jpeg (quality 95) through a display view, as
render's --preview makes them (a render's EXR converted with the same --view and --exposure gives
the bytes its --preview gave); .hdr (Radiance RGBE) or .exr (float RGB), scene-linear. The
extension's case does not matter. A file of several layers converts its image (R, G, B), or the
layer --layer names. An A channel goes into a PNG or EXR (a JPEG or HDR holds none: a warning
says so).

Options
  --view NAME                the display view of a PNG or JPEG (default sRGB, or $OCIO's default
                             view; `dacrt views` lists them)
  --exposure STOPS           scales the scene-linear values by 2^STOPS before the view (PNG, JPEG)
  --layer NAME               a layer instead of the image: albedo, N (or normal), Z (depth),
                             P (position), variance, samples, or any NAME.R/G/B or NAME.X/Y/Z;
                             a layer of one channel (Z) as grey
  --quiet                    no line on stderr for the file written
  -h, --help                 this text
)help";

struct ConvertArgs {
  std::string input, output, layer, display_flag;
  DisplayOptions display;
  bool quiet = false, help = false;
};

ConvertArgs parse_convert(const std::vector<std::string>& given) {
  ConvertArgs c;
  std::vector<std::string> args = given;
  const std::vector<std::string> flags = {"--quiet", "--help"};
  for (size_t i = 0; i < args.size(); ++i) {
    split_option_value(args, i, flags);
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") {
      c.help = true;
      return c;
    } else if (parse_display_option(args, i, c.display, c.display_flag)) {
    } else if (a == "--layer") {
      if (i + 1 >= args.size() || args[i + 1].empty()) throw UsageError("--layer needs a NAME");
      c.layer = args[++i];
    } else if (a == "--quiet") {
      c.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError("unknown option " + a +
                       did_you_mean(a, {"--view", "--exposure", "--layer", "--quiet", "--help"}));
    } else if (c.input.empty()) {
      c.input = a;
    } else if (c.output.empty()) {
      c.output = a;
    } else {
      throw UsageError("unexpected argument '" + a + "' (one IN.exr and one OUT)");
    }
  }
  if (c.output.empty())
    throw UsageError("convert needs IN.exr and OUT: dacrt convert IN.exr OUT.png");
  const ImageFormat format = output_format("OUT", c.output);
  if (!c.display_flag.empty() && !holds_display_values(format))
    throw UsageError(c.display_flag + " changes only display values (PNG, JPEG), and OUT " +
                     c.output + " is " + format_name(format) + " (scene-linear)");
  return c;
}

}  // namespace

int convert_main(const std::vector<std::string>& args) {
  const ConvertArgs c = parse_convert(args);
  if (c.help) return std::fputs(convert_help, stdout), 0;
  check_input_file(c.input, "EXR image");
  std::vector<NamedFile> inputs = {{"the input", c.input}};
  if (holds_display_values(*image_format(c.output))) {
    set_color_warnings(!c.quiet);
    check_display_transform(c.display);
    for (const std::string& file : display_input_files())
      inputs.push_back({"the display configuration's file", file});
  }
  check_writable(c.output);
  check_outputs({{"OUT", c.output}}, inputs);
  std::vector<float> alpha;
  const Image image = read_exr_layer(c.input, c.layer, &alpha);
  const ImageFormat format = *image_format(c.output);
  if (!alpha.empty() && format != ImageFormat::png && format != ImageFormat::exr) {
    print_message("warning: " + c.output + " is " + format_name(format) + ", which holds no " +
                  "alpha: the A channel of " + c.input + " is not written");
    alpha.clear();
  }
  write_image(c.output, image, c.display, {}, alpha, "OUT");
  if (!c.quiet)
    print_message(c.output + ": " + std::to_string(image.width) + " x " +
                  std::to_string(image.height) + " " + format_name(*image_format(c.output)) +
                  (c.layer.empty() ? "" : ", layer " + c.layer) + " from " + c.input);
  return 0;
}

}  // namespace dacrt
