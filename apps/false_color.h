// False colour for `dacrt diff --preview`: a map of non-negative values (per-pixel errors) through
// viridis, the perceptually uniform colormap of van der Walt and Smith (matplotlib's default since
// 2.0), with a colour bar beside it whose ends are labelled with their values in a tiny built-in
// bitmap font (no font library: digits, '.', 'e', '-', '+' are all a number needs).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace dacrt {

// Viridis at t in [0, 1] (clamped; NaN is 0) as 8-bit sRGB: t = 0 is its first colour
// (68, 1, 84), t = 1 its last (253, 231, 37).
std::array<uint8_t, 3> viridis(double t);

// An 8-bit RGB picture, rows from the top.
struct Picture {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // 3 * width * height
};

// `values` (width × height, row-major from the top-left, each ≥ 0) in false colour at the
// top-left of the picture: 0 is viridis's first colour, `scale` and above its last, linear in
// between (scale 0: everything the first colour). On its right, on white, a bar from the last
// colour at its top row to the first at its bottom row, as tall as the picture (the picture is at
// least 32 pixels tall), labelled with `scale` at its top and 0 at its bottom.
Picture false_color(const std::vector<float>& values, int width, int height, double scale);

}  // namespace dacrt
