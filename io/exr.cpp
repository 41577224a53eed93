// OpenEXR output through OpenEXR 3.1's C++ API: scanline, ZIP, float R/G/B, Rec.709/D65
// chromaticities and the render's metadata as header attributes. The file goes through our own
// std::ofstream (Imf::StdOFStream) so that a failed final flush is seen, which OutputFile's
// destructor would swallow.
#include "io/exr.h"

#include <ImfChannelList.h>
#include <ImfDoubleAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "util/atomic_file.h"
#include "util/error.h"
#include "util/paths.h"

namespace dacrt {
namespace {

namespace fs = std::filesystem;

// The largest image read_exr accepts (16 384 x 8 192, 1.5 GiB of float RGB).
constexpr int64_t kMaxExrPixels = int64_t(1) << 27;

Error write_error(const std::string& path, const std::string& reason) {
  return Error("cannot write EXR '" + path + "': " + reason);
}

Imf::Header make_header(const std::string& path, const Image& image, const ExrMetadata& metadata) {
  Imf::Header header(image.width, image.height, 1.f, Imath::V2f(0, 0), 1.f, Imf::INCREASING_Y,
                     Imf::ZIP_COMPRESSION);
  for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  Imf::addChromaticities(header, Imf::Chromaticities());  // the default is Rec.709 with D65 white
  header.insert("spp", Imf::IntAttribute(metadata.spp));
  header.insert("backend", Imf::StringAttribute(metadata.backend));
  header.insert("integrator", Imf::StringAttribute(metadata.integrator));
  header.insert("renderSeconds", Imf::DoubleAttribute(metadata.render_seconds));
  for (const auto& [name, value] : metadata.extra) {
    // Replacing a standard attribute (or one above) with a string would corrupt the file.
    if (name.empty() || header.find(name) != header.end())
      throw write_error(path, "metadata name '" + name + "' is empty or reserved");
    header.insert(name, Imf::StringAttribute(value));
  }
  return header;
}

void write_scanlines(std::ofstream& stream, const std::string& tmp, const Imf::Header& header,
                     const Image& image) {
  Imf::StdOFStream exr_stream(stream, tmp.c_str());
  Imf::OutputFile file(exr_stream, header);
  Imf::FrameBuffer frame;
  const size_t x_stride = 3 * sizeof(float);
  const size_t y_stride = x_stride * size_t(image.width);
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c)
    frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, image.rgb.data() + c, header.dataWindow(),
                                            x_stride, y_stride));
  file.setFrameBuffer(frame);
  file.writePixels(image.height);
}

}  // namespace

void write_exr(const std::string& path, const Image& image, const ExrMetadata& metadata) {
  if (image.width <= 0 || image.height <= 0) throw write_error(path, "the image is empty");
  if (image.rgb.size() != size_t(3) * size_t(image.width) * size_t(image.height))
    throw write_error(path, "the image has " + std::to_string(image.rgb.size()) + " values for " +
                                std::to_string(image.width) + "x" + std::to_string(image.height) +
                                " pixels");

  const Imf::Header header = make_header(path, image, metadata);
  // OutputFile's destructor writes the line offsets; the stream is checked after that.
  write_atomically(path, "EXR",
                   [&](std::ofstream& stream) { write_scanlines(stream, path, header, image); });
}

Image read_exr(const std::string& path) {
  check_input_file(path, "EXR image");
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    // Bounded before anything is allocated: a header may claim any window.
    const int64_t width = int64_t(window.max.x) - window.min.x + 1,
                  height = int64_t(window.max.y) - window.min.y + 1;
    if (width < 1 || height < 1)
      throw Error("cannot read EXR '" + path + "': its data window is empty");
    if (width * height > kMaxExrPixels)
      throw Error("cannot read EXR '" + path + "': " + std::to_string(width) + " x " +
                  std::to_string(height) + " pixels is more than the 2^27 accepted");
    const Imf::ChannelList& channels = file.header().channels();
    for (const char* name : {"R", "G", "B"})
      if (!channels.findChannel(name))
        throw Error("cannot read EXR '" + path + "': it has no " + name + " channel");

    Image image(static_cast<int>(width), static_cast<int>(height));
    const size_t x_stride = 3 * sizeof(float);
    const size_t y_stride = x_stride * size_t(image.width);
    Imf::FrameBuffer frame;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c)
      frame.insert(names[c],
                   Imf::Slice::Make(Imf::FLOAT, image.rgb.data() + c, window, x_stride, y_stride));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return image;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error("cannot read EXR '" + path + "': " + one_line(e.what()));
  }
}

}  // namespace dacrt
