// The check of an untrusted EXR file's header before OpenEXR reads it: every size the header
// declares must fit in the file and in memory, and the file must be one dacrt decodes (a single
// part of flat scanlines or tiles). For io/exr.cpp's readers (read_exr, the film's sums).
#pragma once

#include <cstdint>
#include <istream>
#include <string>

namespace dacrt {

// The largest image read_exr accepts (16 384 x 8 192, 1.5 GiB of float RGB).
constexpr int64_t kMaxExrPixels = int64_t(1) << 27;

// What scan_header learnt of a header it accepted.
struct HeaderScan {
  int64_t width = 0, height = 0;
};

// Reads the header of the file in `in` (named `name` in messages) and throws Error naming the
// file and the attribute unless it passes; the stream is left past the offset table.
HeaderScan scan_header(std::istream& in, const std::string& name);

}  // namespace dacrt
