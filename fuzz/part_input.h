// One fuzzing input for the reader of part files (the EXR files `dacrt render --samples A:B` writes
// with exact sums, io/film_exr.h), as the part fuzz target and the suite's fuzz test both treat
// it. The bytes are written to a file, since the part reader takes a path, and read as
// `dacrt merge` and `render --resume` read a part: the header with its exact sums' format, the
// part its attributes describe (sampleRange, match.*, match.aovs), then the exact state into a
// film of the header's size, whose image channels are made from it as merge makes them. Each step
// must succeed or throw one dacrt::Error naming the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "dacrt/film/film.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/film_exr.h"
#include "dacrt/render/part_plan.h"
#include "dacrt/util/error.h"

namespace dacrt {

struct PartFuzzOutcome {
  enum Kind { loaded, refused, too_large } kind;
  std::string error;  // the Error's message when refused
};

// The most pixels a film is made for. Merge bounds a film only by the memory available (resume
// makes it of the render's size, not the file's), which would let a forged 2^27-pixel header
// allocate gigabytes per input and stop the fuzzer at its -rss_limit_mb; the seed parts are a few
// dozen pixels.
inline constexpr int64_t part_fuzz_max_pixels = int64_t(1) << 16;

// Reads `data` as a part file at `path` (overwritten, then removed), which messages must name.
inline PartFuzzOutcome fuzz_part_input(const uint8_t* data, size_t size, const std::string& path) {
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    if (!out) return {PartFuzzOutcome::refused, "cannot write " + path};
  }
  // The file goes however this returns, so a run leaves nothing behind.
  struct Remove {
    const std::string& path;
    ~Remove() {
      std::error_code ec;
      std::filesystem::remove(path, ec);
    }
  } cleanup{path};
  try {
    const ExrHeader header = read_sums_header(path, "to merge");
    const PartHeader part = part_from_attributes(path, header.attributes);
    AovSet aovs;
    try {
      aovs = AovSet::parse(part.match.at("match.aovs"));
    } catch (const std::exception&) {  // as merge says it (apps/merge.cpp)
      throw Error(path + ": its match.aovs attribute is missing or names unknown outputs");
    }
    if (int64_t(header.width) * header.height > part_fuzz_max_pixels)
      return {PartFuzzOutcome::too_large, ""};
    Film film(header.width, header.height, aovs);
    // Resume's bounds (any count up to the part's samples) admit more files than merge's, which
    // wants every pixel to have them all; merge's check is then run on what was read.
    const uint32_t samples = part.last - part.first;
    read_film_state(path, header, film, 0, samples);
    (void)film.check_sums(samples, samples);
    (void)film.channels(true);
    return {PartFuzzOutcome::loaded, ""};
  } catch (const Error& e) {
    return {PartFuzzOutcome::refused, e.what()};
  }
}

}  // namespace dacrt
