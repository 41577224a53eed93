// OpenEXR output: float channels (R, G, B in scene-linear Rec.709 primaries, then any named
// layers: albedo.R, N.X, Z…), with render metadata in the header. Written to a temporary name
// beside the target and renamed, so no half-written file is left.
#pragma once

#include <cstdint>
#include <functional>
#include <istream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "dacrt/util/image.h"

namespace dacrt {

struct ExrMetadata {
  int spp = 0;  // samples every pixel has
  std::string backend;
  std::string integrator;
  double render_seconds = 0.0;
  std::vector<std::pair<std::string, std::string>> extra;  // more string attributes
};

// A 32-bit unsigned integer channel (OpenEXR's UINT) read or written in place: pixel p's word is
// at base + p × stride (a film's fixed-point sums, a word of each at a time: io/film_exr.h).
struct WordChannel {
  std::string name;
  char* base = nullptr;
  size_t stride = sizeof(uint32_t);
};

void write_exr(const std::string& path, const Image& image, const ExrMetadata& metadata);
// Any channels of width × height pixels (each `values` of that size, names distinct), and any
// word channels after them.
void write_exr(const std::string& path, int width, int height, const std::vector<Channel>& channels,
               const ExrMetadata& metadata, const std::vector<WordChannel>& words = {});

// Channels made a band of rows at a time, so that no whole image of them is held beside what
// they are made from (a film of every AOV at 1080p: 141 MB of float channels). fill(y0, y1,
// floats, words) writes rows [y0, y1) of each channel: floats[c] (and words[c]) has room for
// (y1 − y0) × width values, row after row.
struct ExrRows {
  std::vector<std::string> floats, words;  // the channels' names: FLOAT, then UINT channels
  std::function<void(int y0, int y1, const std::vector<float*>& floats,
                     const std::vector<uint32_t*>& words)>
      fill;
};
void write_exr(const std::string& path, int width, int height, const ExrRows& rows,
               const ExrMetadata& metadata);

// RGB channels as float: environment maps, references, tests. The header is checked before
// OpenEXR reads it: every size it declares must fit in the file, the pixels in memory, and the
// file must be a single part of flat scanlines or tiles; anything else is one dacrt::Error.
Image read_exr(const std::string& path);
// The same from a stream (bytes in memory, for the fuzzer); `name` is the file in messages.
Image read_exr(std::istream& in, const std::string& name);

// One layer of a file as an RGB image, reading no other channel (`dacrt convert`): with `layer`
// empty the image (R, G, B; or Y alone as grey), else the layer's channels NAME.R/G/B or
// NAME.X/Y/Z, a channel named NAME, or a layer's only channel as grey (Z, samples.X); the AOV
// names normal, depth and position stand for N, Z and P. The header is checked as read_exr's.
// Error for a file without R, G and B; SettingError naming the layers there for a `layer` that
// is not one of them. With `alpha`, the image's A channel into it when the file has one (else it
// is left empty).
Image read_exr_layer(const std::string& path, const std::string& layer = "",
                     std::vector<float>* alpha = nullptr);

// Everything in a file, for tests and comparisons: every channel as float, and the header's
// string, int and double attributes as text.
struct ExrFile {
  int width = 0, height = 0;
  std::vector<Channel> channels;
  std::map<std::string, std::string> attributes;
  const Channel* find(const std::string& name) const;
};
ExrFile read_exr_file(const std::string& path);

// A file's size, its string, int and double attributes as text and its channels with their
// types ("UINT", "HALF", "FLOAT"), without reading a pixel.
struct ExrHeader {
  int width = 0, height = 0;
  std::map<std::string, std::string> attributes;
  std::map<std::string, std::string> channels;
};
ExrHeader read_exr_header(const std::string& path);
// Reads the word channels of a file of width × height pixels into place; Error naming the file
// and the channel when one is missing, is not UINT, or the size differs.
void read_exr_words(const std::string& path, int width, int height,
                    const std::vector<WordChannel>& words);

}  // namespace dacrt
