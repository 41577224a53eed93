// OpenEXR output through OpenEXR 3.1's C++ API: scanline, ZIP, float R/G/B, Rec.709/D65
// chromaticities and the render's metadata as header attributes. The file goes through our own
// stream (StreamOut below) so that a failed final flush is seen, which OutputFile's destructor
// would swallow.
#include "dacrt/io/exr.h"

#include <Iex.h>
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
#include <ImfThreading.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <istream>
#include <map>
#include <set>
#include <mutex>
#include <system_error>
#include <thread>

#include "dacrt/io/exr_scan.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/memory.h"
#include "dacrt/util/paths.h"

namespace dacrt {
namespace {

namespace fs = std::filesystem;

// OpenEXR compresses and decompresses the blocks of scanlines of a file on its own thread pool,
// idle unless given threads: a 1080p image with every AOV and its exact sums took 3.5 s to
// write and 5 s to read on one thread. Not for the fuzzer's reads (read_exr from a stream).
void use_threads() {
  static std::once_flag once;
  std::call_once(once, [] {
    Imf::setGlobalThreadCount(int(std::clamp(std::thread::hardware_concurrency(), 1u, 16u)));
  });
}

Error write_error(const std::string& path, const std::string& reason) {
  return Error("cannot write EXR '" + path + "': " + reason);
}

Imf::Header make_header(const std::string& path, int width, int height,
                        const std::vector<std::string>& floats,
                        const std::vector<std::string>& words, const ExrMetadata& metadata) {
  Imf::Header header(width, height, 1.f, Imath::V2f(0, 0), 1.f, Imf::INCREASING_Y,
                     Imf::ZIP_COMPRESSION);
  for (const std::vector<std::string>* names : {&floats, &words})
    for (const std::string& name : *names) {
      if (name.empty() || header.channels().findChannel(name))
        throw write_error(path, "channel name '" + name + "' is empty or repeated");
      header.channels().insert(name, Imf::Channel(names == &floats ? Imf::FLOAT : Imf::UINT));
    }
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

// OpenEXR's output stream over a std::ostream (Imf::StdOFStream takes only a std::ofstream;
// write_atomically's file is a stream on a descriptor it created).
class StreamOut : public Imf::OStream {
 public:
  StreamOut(std::ostream& stream, const std::string& name)
      : Imf::OStream(name.c_str()), s_(stream) {}
  void write(const char c[], int n) override {
    if (!s_.write(c, n)) throw std::runtime_error("writing the file failed");
  }
  uint64_t tellp() override { return uint64_t(std::streamoff(s_.tellp())); }
  void seekp(uint64_t pos) override {
    if (!s_.seekp(std::streamoff(pos))) throw std::runtime_error("seeking in the file failed");
  }

 private:
  std::ostream& s_;
};

void write_scanlines(std::ostream& stream, const std::string& path, const Imf::Header& header,
                     int width, const std::vector<Channel>& channels,
                     const std::vector<WordChannel>& words) {
  use_threads();
  StreamOut exr_stream(stream, path);
  Imf::OutputFile file(exr_stream, header);
  Imf::FrameBuffer frame;
  for (const Channel& c : channels)
    frame.insert(c.name, Imf::Slice::Make(Imf::FLOAT, c.values.data(), header.dataWindow(),
                                          sizeof(float), sizeof(float) * size_t(width)));
  for (const WordChannel& c : words)
    frame.insert(c.name, Imf::Slice::Make(Imf::UINT, c.base, header.dataWindow(), c.stride,
                                          c.stride * size_t(width)));
  file.setFrameBuffer(frame);
  file.writePixels(header.dataWindow().max.y + 1);
}

// The rows of a band at a time: 64 rows (four of ZIP's blocks of 16, so that each band
// compresses on its own threads).
void write_scanline_rows(std::ostream& stream, const std::string& path, const Imf::Header& header,
                         int width, int height, const ExrRows& rows) {
  use_threads();
  StreamOut exr_stream(stream, path);
  Imf::OutputFile file(exr_stream, header);
  constexpr int band = 64;
  const size_t most = size_t(width) * size_t(std::min(band, height));
  std::vector<std::vector<float>> floats(rows.floats.size(), std::vector<float>(most));
  std::vector<std::vector<uint32_t>> words(rows.words.size(), std::vector<uint32_t>(most));
  std::vector<float*> float_rows;
  std::vector<uint32_t*> word_rows;
  for (auto& f : floats) float_rows.push_back(f.data());
  for (auto& w : words) word_rows.push_back(w.data());
  for (int y0 = 0; y0 < height; y0 += band) {
    const int y1 = std::min(height, y0 + band);
    rows.fill(y0, y1, float_rows, word_rows);
    // Slice::Make places the window's first pixel, (0, y0), at the buffer's start.
    const Imath::Box2i window(Imath::V2i(0, y0), Imath::V2i(width - 1, y1 - 1));
    Imf::FrameBuffer frame;
    for (size_t c = 0; c < floats.size(); ++c)
      frame.insert(rows.floats[c], Imf::Slice::Make(Imf::FLOAT, floats[c].data(), window,
                                                    sizeof(float), sizeof(float) * size_t(width)));
    for (size_t c = 0; c < words.size(); ++c)
      frame.insert(rows.words[c],
                   Imf::Slice::Make(Imf::UINT, words[c].data(), window, sizeof(uint32_t),
                                    sizeof(uint32_t) * size_t(width)));
    file.setFrameBuffer(frame);
    file.writePixels(y1 - y0);
  }
}

// An Imf::IStream over a std::istream (a file, or bytes in memory for the fuzzer), reporting
// errors as Imf::StdIFStream does.
class StreamIn : public Imf::IStream {
 public:
  StreamIn(std::istream& in, const char* name) : Imf::IStream(name), in_(in) {}
  bool read(char c[], int n) override {
    if (!in_) throw Iex::InputExc("unexpected end of file");
    in_.read(c, n);
    if (in_.gcount() < n)
      throw Iex::InputExc("early end of file: read " + std::to_string(in_.gcount()) + " of " +
                          std::to_string(n) + " bytes");
    return true;
  }
  uint64_t tellg() override { return uint64_t(std::streamoff(in_.tellg())); }
  void seekg(uint64_t pos) override {
    in_.seekg(std::streamoff(pos));
    if (!in_) throw Iex::InputExc("cannot seek to byte " + std::to_string(pos));
  }
  void clear() override { in_.clear(); }

 private:
  std::istream& in_;
};

}  // namespace

void write_exr(const std::string& path, const Image& image, const ExrMetadata& metadata) {
  if (image.rgb.size() !=
      size_t(3) * size_t(std::max(0, image.width)) * size_t(std::max(0, image.height)))
    throw write_error(path, "the image has " + std::to_string(image.rgb.size()) + " values for " +
                                std::to_string(image.width) + "x" + std::to_string(image.height) +
                                " pixels");
  std::vector<Channel> channels = {{"R", {}}, {"G", {}}, {"B", {}}};
  const size_t n = image.rgb.size() / 3;
  for (int c = 0; c < 3; ++c) {
    channels[c].values.resize(n);
    for (size_t p = 0; p < n; ++p) channels[c].values[p] = image.rgb[3 * p + c];
  }
  write_exr(path, image.width, image.height, channels, metadata);
}

void write_exr(const std::string& path, int width, int height, const std::vector<Channel>& channels,
               const ExrMetadata& metadata, const std::vector<WordChannel>& words) {
  if (width <= 0 || height <= 0) throw write_error(path, "the image is empty");
  std::vector<std::string> float_names, word_names;
  for (const Channel& c : channels) {
    if (c.values.size() != size_t(width) * size_t(height))
      throw write_error(path, "channel " + c.name + " has " + std::to_string(c.values.size()) +
                                  " values for " + std::to_string(width) + "x" +
                                  std::to_string(height) + " pixels");
    float_names.push_back(c.name);
  }
  for (const WordChannel& c : words) word_names.push_back(c.name);
  const Imf::Header header = make_header(path, width, height, float_names, word_names, metadata);
  // OutputFile's destructor writes the line offsets; the stream is checked after that.
  write_atomically(path, "EXR", [&](std::ostream& stream) {
    write_scanlines(stream, path, header, width, channels, words);
  });
}

void write_exr(const std::string& path, int width, int height, const ExrRows& rows,
               const ExrMetadata& metadata) {
  if (width <= 0 || height <= 0) throw write_error(path, "the image is empty");
  const Imf::Header header = make_header(path, width, height, rows.floats, rows.words, metadata);
  write_atomically(path, "EXR", [&](std::ostream& stream) {
    write_scanline_rows(stream, path, header, width, height, rows);
  });
}

Image read_exr(const std::string& path) {
  check_input_file(path, "EXR image");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read EXR '" + path + "': " + std::strerror(errno));
  return read_exr(in, path);
}

Image read_exr(std::istream& in, const std::string& name) {
  try {
    const HeaderScan scan = scan_header(in, name);
    in.clear();
    in.seekg(0);
    StreamIn stream(in, name.c_str());
    Imf::InputFile file(stream);
    const Imath::Box2i window = file.header().dataWindow();
    const int64_t width = int64_t(window.max.x) - window.min.x + 1,
                  height = int64_t(window.max.y) - window.min.y + 1;
    if (width != scan.width || height != scan.height)  // the scan saw the same header
      throw Error("cannot read EXR '" + name + "': its header changed while it was read");
    const Imf::ChannelList& channels = file.header().channels();
    for (const char* c : {"R", "G", "B"})
      if (!channels.findChannel(c))
        throw Error("cannot read EXR '" + name + "': it has no " + c + " channel");

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
    throw Error("cannot read EXR '" + name + "': " + one_line(e.what()));
  } catch (...) {
    throw Error("cannot read EXR '" + name + "': OpenEXR failed without a message");
  }
}

const Channel* ExrFile::find(const std::string& name) const {
  for (const Channel& c : channels)
    if (c.name == name) return &c;
  return nullptr;
}

namespace {

// Opens a checked file (scan_header first) and hands OpenEXR's reader to `use`, turning every
// failure into one Error naming the file.
template <class Use>
auto with_exr(const std::string& path, Use use) {
  check_input_file(path, "EXR image");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read EXR '" + path + "': " + std::strerror(errno));
  try {
    scan_header(in, path);
    in.clear();
    in.seekg(0);
    StreamIn stream(in, path.c_str());
    use_threads();
    Imf::InputFile file(stream);
    return use(file);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error("cannot read EXR '" + path + "': " + one_line(e.what()));
  } catch (...) {
    throw Error("cannot read EXR '" + path + "': OpenEXR failed without a message");
  }
}

// The header's string, int and double attributes as text.
std::map<std::string, std::string> attributes_of(const Imf::Header& header) {
  std::map<std::string, std::string> out;
  for (auto it = header.begin(); it != header.end(); ++it) {
    const Imf::Attribute& a = it.attribute();
    if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&a))
      out[it.name()] = s->value();
    else if (const auto* n = dynamic_cast<const Imf::IntAttribute*>(&a))
      out[it.name()] = std::to_string(n->value());
    else if (const auto* d = dynamic_cast<const Imf::DoubleAttribute*>(&a))
      out[it.name()] = std::to_string(d->value());
  }
  return out;
}

}  // namespace

ExrFile read_exr_file(const std::string& path) {
  return with_exr(path, [&](Imf::InputFile& file) {
    const Imf::Header& header = file.header();
    const Imath::Box2i window = header.dataWindow();
    const int64_t width = int64_t(window.max.x) - window.min.x + 1,
                  height = int64_t(window.max.y) - window.min.y + 1;
    int64_t count = 0;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) ++count;
    if (width < 1 || height < 1 || width > kMaxExrPixels || height > kMaxExrPixels ||
        width * height > kMaxExrPixels / std::max<int64_t>(count, 1))
      throw Error("cannot read EXR '" + path + "': " + std::to_string(width) + " x " +
                  std::to_string(height) + " pixels in " + std::to_string(count) +
                  " channels is empty or more than the 2^27 values accepted");
    ExrFile out;
    out.width = int(width), out.height = int(height);
    Imf::FrameBuffer frame;
    out.channels.reserve(size_t(count));
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      out.channels.push_back({it.name(), std::vector<float>(size_t(width * height))});
      frame.insert(it.name(), Imf::Slice::Make(Imf::FLOAT, out.channels.back().values.data(),
                                               window, sizeof(float), sizeof(float) * width));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    out.attributes = attributes_of(header);
    return out;
  });
}

namespace {

// The channels of `layer` (read_exr_layer): three, or one read as grey.
std::vector<std::string> layer_channels(const std::string& path, const Imf::ChannelList& list,
                                        const std::string& layer) {
  const std::string name = layer == "normal" ? "N" : layer == "depth" ? "Z"
                           : layer == "position" ? "P" : layer;
  const std::string prefix = name.empty() ? "" : name + ".";
  static const char* const sets[2][3] = {{"R", "G", "B"}, {"X", "Y", "Z"}};
  for (const auto& set : sets) {
    std::vector<std::string> found;
    for (const char* c : set)
      if (list.findChannel(prefix + c)) found.push_back(prefix + c);
    if (found.size() == 3) return found;
    if (name.empty()) break;  // the image is R, G, B (or Y), never X, Y, Z
  }
  if (name.empty()) {
    if (list.findChannel("Y")) return {"Y"};
    throw Error("cannot read EXR '" + path + "': it has no R, G and B channels");
  }
  if (list.findChannel(name)) return {name};
  std::vector<std::string> in_layer;
  std::set<std::string> layers;
  for (auto it = list.begin(); it != list.end(); ++it) {
    const std::string channel = it.name();
    if (channel.starts_with(prefix)) in_layer.push_back(channel);
    const size_t dot = channel.rfind('.');
    layers.insert(dot == std::string::npos ? channel : channel.substr(0, dot));
  }
  if (in_layer.size() == 1) return in_layer;
  std::string names;
  for (const std::string& l : layers)
    if (l != "R" && l != "G" && l != "B" && !l.starts_with("exact"))
      names += (names.empty() ? "'" : ", '") + l + "'";
  throw SettingError(path + " has no layer '" + layer + "'" +
                     (names.empty() ? std::string(" (it has none but the image)")
                                    : " (its layers: " + names + ")"));
}

}  // namespace

Image read_exr_layer(const std::string& path, const std::string& layer,
                     std::vector<float>* alpha) {
  return with_exr(path, [&](Imf::InputFile& file) {
    const Imf::Header& header = file.header();
    const std::vector<std::string> names = layer_channels(path, header.channels(), layer);
    const Imath::Box2i window = header.dataWindow();
    const int64_t width = int64_t(window.max.x) - window.min.x + 1,
                  height = int64_t(window.max.y) - window.min.y + 1;
    if (width < 1 || height < 1 || width > kMaxExrPixels || height > kMaxExrPixels ||
        width * height > kMaxExrPixels / 3)
      throw Error("cannot read EXR '" + path + "': " + std::to_string(width) + " x " +
                  std::to_string(height) + " pixels is empty or more than the 2^27 values "
                  "accepted");
    Image image{int(width), int(height)};
    const size_t x_stride = 3 * sizeof(float), y_stride = x_stride * size_t(width);
    Imf::FrameBuffer frame;
    for (size_t c = 0; c < names.size(); ++c)
      frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, image.rgb.data() + c, window, x_stride,
                                              y_stride));
    if (alpha) alpha->clear();
    if (alpha && layer.empty() && header.channels().findChannel("A")) {
      alpha->resize(size_t(width * height));
      frame.insert("A", Imf::Slice::Make(Imf::FLOAT, alpha->data(), window, sizeof(float),
                                         sizeof(float) * size_t(width)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    if (names.size() == 1)
      for (size_t p = 0; p < image.rgb.size(); p += 3)
        image.rgb[p + 1] = image.rgb[p + 2] = image.rgb[p];
    return image;
  });
}

ExrHeader read_exr_header(const std::string& path) {
  return with_exr(path, [&](Imf::InputFile& file) {
    const Imf::Header& header = file.header();
    const Imath::Box2i window = header.dataWindow();
    ExrHeader out;
    out.width = window.max.x - window.min.x + 1, out.height = window.max.y - window.min.y + 1;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      const Imf::PixelType type = it.channel().type;
      out.channels[it.name()] = type == Imf::UINT ? "UINT" : type == Imf::HALF ? "HALF" : "FLOAT";
    }
    out.attributes = attributes_of(header);
    return out;
  });
}

void read_exr_words(const std::string& path, int width, int height,
                    const std::vector<WordChannel>& words) {
  with_exr(path, [&](Imf::InputFile& file) {
    const Imath::Box2i window = file.header().dataWindow();
    if (window.max.x - window.min.x + 1 != width || window.max.y - window.min.y + 1 != height)
      throw Error("cannot read EXR '" + path + "': it is not " + std::to_string(width) + " x " +
                  std::to_string(height) + " pixels");
    Imf::FrameBuffer frame;
    for (const WordChannel& c : words) {
      const Imf::Channel* channel = file.header().channels().findChannel(c.name);
      if (!channel || channel->type != Imf::UINT)
        throw Error("cannot read EXR '" + path + "': it has no 32-bit integer channel " + c.name);
      // Slice::Make places the data window's first pixel at `base`.
      frame.insert(c.name, Imf::Slice::Make(Imf::UINT, c.base, window, c.stride,
                                            c.stride * size_t(width)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return 0;
  });
}

}  // namespace dacrt
