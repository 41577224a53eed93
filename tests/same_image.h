// Comparing dacrt's EXR outputs in tests: the image channels bit for bit, and whether a file
// keeps its exact sums (io/film_exr.h).
#pragma once

#include <doctest/doctest.h>

#include <cstring>
#include <map>
#include <string>

#include "dacrt/io/exr.h"

namespace dacrt::test {

// The render option that gives the 17 channels below.
inline const std::string every_aov = "--aov albedo,normal,depth,position,variance,samples";

// Every image channel (not the exact sums) of two files the same, bit for bit: `channels` of them
// (17 with every AOV: R G B, albedo (3), N (3), Z, P (3), variance (3), samples).
inline void check_same_image(const std::string& a, const std::string& b, size_t channels = 17) {
  const ExrFile x = read_exr_file(a), y = read_exr_file(b);
  std::map<std::string, const Channel*> image;
  for (const Channel& c : y.channels)
    if (c.name.rfind("exact.", 0) != 0) image[c.name] = &c;
  size_t compared = 0;
  for (const Channel& c : x.channels) {
    if (c.name.rfind("exact.", 0) == 0) continue;
    INFO(a << " and " << b << ", channel " << c.name);
    REQUIRE(image.count(c.name));
    CHECK(std::memcmp(c.values.data(), image[c.name]->values.data(),
                      c.values.size() * sizeof(float)) == 0);
    ++compared;
  }
  CHECK(compared == image.size());
  CHECK(compared == channels);
}

inline bool has_sums(const std::string& file) {
  return read_exr_header(file).channels.count("exact.sums.0.w0") == 1;
}

}  // namespace dacrt::test
