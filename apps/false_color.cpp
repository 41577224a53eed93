#include "apps/false_color.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace dacrt {

namespace {

// Viridis sampled at t = i / 32 from matplotlib's 256-entry table (_cm_listed.py, CC0), rounded
// to 8 bits: linear interpolation between these stays within 2 levels of the full table.
constexpr uint8_t viridis_stops[33][3] = {
    {68, 1, 84},    {71, 13, 96},   {72, 24, 106},  {72, 35, 116},  {71, 45, 123},  {69, 54, 129},
    {66, 64, 134},  {63, 73, 137},  {59, 82, 139},  {55, 90, 141},  {51, 99, 141},  {47, 106, 142},
    {44, 114, 142}, {41, 122, 142}, {38, 129, 142}, {35, 137, 142}, {33, 144, 140}, {31, 152, 139},
    {31, 159, 136}, {33, 166, 133}, {40, 174, 128}, {49, 181, 123}, {62, 188, 116}, {76, 194, 108},
    {93, 201, 99},  {110, 206, 88}, {130, 211, 76}, {150, 216, 63}, {171, 220, 50}, {192, 223, 36},
    {213, 226, 26}, {234, 229, 26}, {253, 231, 37}};

// 3 × 5 glyphs: five rows from the top, each three bits with the left pixel the highest.
struct Glyph {
  char c;
  uint8_t rows[5];
};
constexpr Glyph glyphs[] = {{'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}},
                            {'3', {7, 1, 7, 1, 7}}, {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}},
                            {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}}, {'8', {7, 5, 7, 5, 7}},
                            {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'e', {0, 3, 7, 4, 3}},
                            {'-', {0, 0, 7, 0, 0}}, {'+', {0, 2, 7, 2, 0}}};

constexpr int kMinHeight = 32;  // room for the bar's two labels on the smallest maps

void put(Picture& p, int x, int y, const std::array<uint8_t, 3>& colour) {
  std::copy(colour.begin(), colour.end(), &p.rgb[3 * (size_t(y) * size_t(p.width) + size_t(x))]);
}

// `text` in black with its top-left corner at (x, y), each font pixel a k × k square; characters
// the font lacks are left blank.
void draw_text(Picture& p, int x, int y, const std::string& text, int k) {
  for (const char c : text) {
    const Glyph* g = std::find_if(std::begin(glyphs), std::end(glyphs),
                                  [&](const Glyph& g) { return g.c == c; });
    for (int row = 0; g != std::end(glyphs) && row < 5; ++row)
      for (int col = 0; col < 3; ++col)
        if (g->rows[row] & (4 >> col))
          for (int dy = 0; dy < k; ++dy)
            for (int dx = 0; dx < k; ++dx) put(p, x + col * k + dx, y + row * k + dy, {0, 0, 0});
    x += 4 * k;
  }
}

int text_width(const std::string& text, int k) {
  return int(text.size()) * 4 * k - k;
}

}  // namespace

std::array<uint8_t, 3> viridis(double t) {
  t = std::isnan(t) ? 0.0 : std::clamp(t, 0.0, 1.0);
  const double x = t * 32;
  const int i = std::min(int(x), 31);
  const double f = x - i;
  std::array<uint8_t, 3> c;
  for (int k = 0; k < 3; ++k)
    c[k] = uint8_t(
        std::lround(viridis_stops[i][k] + (viridis_stops[i + 1][k] - viridis_stops[i][k]) * f));
  return c;
}

Picture false_color(const std::vector<float>& values, int width, int height, double scale) {
  char top[32];
  std::snprintf(top, sizeof top, "%.3g", scale);
  const std::string top_label = top, bottom_label = "0";

  // Glyphs grow with the picture, up to 12 × 20 pixels from 512 rows.
  const int rows = std::max(height, kMinHeight), k = std::clamp(rows / 128, 1, 4);
  const int gap = 3 * k, bar_x = width + gap, bar_width = 6 * k, label_x = bar_x + bar_width + gap;
  Picture p;
  p.width = label_x + std::max(text_width(top_label, k), text_width(bottom_label, k)) + gap;
  p.height = rows;
  p.rgb.assign(size_t(3) * size_t(p.width) * size_t(p.height), 255);

  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double v = values[size_t(y) * size_t(width) + size_t(x)];
      put(p, x, y, viridis(scale > 0 ? v / scale : 0.0));
    }
  for (int y = 0; y < rows; ++y) {
    const auto colour = viridis(double(rows - 1 - y) / (rows - 1));
    for (int x = bar_x; x < bar_x + bar_width; ++x) put(p, x, y, colour);
  }
  draw_text(p, label_x, 0, top_label, k);
  draw_text(p, label_x, rows - 5 * k, bottom_label, k);
  return p;
}

}  // namespace dacrt
