#include "dacrt/scene/environment.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <glm/gtc/constants.hpp>
#include <string>

#include "dacrt/materials/sampling.h"
#include "dacrt/util/error.h"
#include "dacrt/util/memory.h"

namespace dacrt {

glm::vec2 EnvironmentMap::to_uv(const glm::vec3& d) {
  const float phi = std::atan2(d.x, -d.z);
  const float theta = std::acos(std::clamp(d.y, -1.f, 1.f));
  return {phi * glm::one_over_two_pi<float>() + 0.5f, theta * glm::one_over_pi<float>()};
}

glm::vec3 EnvironmentMap::from_uv(const glm::vec2& uv) {
  const float phi = glm::two_pi<float>() * (uv.x - 0.5f), theta = glm::pi<float>() * uv.y;
  const float s = std::sin(theta);
  return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
}

namespace {

// Radiance above this is refused: a path carrying it, divided by the pdfs of a few bounces,
// would overflow float (3.4e38) and be dropped from the film, silently darkening the image.
constexpr float kMaxRadiance = 1e18f;

// What is wrong with the first bad channel of c, for messages: "has G = -1 (negative)".
std::string bad_radiance(const glm::vec3& c) {
  for (int k = 0; k < 3; ++k) {
    const float v = c[k];
    const char* why = std::isnan(v)      ? "not a number"
                      : std::isinf(v)    ? "infinite"
                      : v < 0.f          ? "negative"
                      : v > kMaxRadiance ? "above 1e18, the brightest radiance accepted"
                                         : nullptr;
    if (!why) continue;
    char value[32];
    std::snprintf(value, sizeof value, "%g", double(v));
    return std::string("has ") + "RGB"[k] + " = " + value + " (" + why + ")";
  }
  return "is valid";
}

}  // namespace

EnvironmentMap::EnvironmentMap(Image image, const std::string& what) : image_(std::move(image)) {
  const int w = image_.width, h = image_.height;
  if (w <= 0 || h <= 0) throw Error(what + ": the environment image is empty");
  // The weights and the alias tables the map keeps (a double and three uint32_t a pixel), bounded
  // before any of them is allocated: a map read_exr accepts may still not fit beside its image.
  const uint64_t tables = uint64_t(w) * uint64_t(h) * (sizeof(double) + 3 * sizeof(uint32_t));
  if (const uint64_t available = available_memory(); tables > available)
    throw Error(what + ": the environment map's sampling tables need " + format_bytes(tables) +
                ", more than the " + format_bytes(available) + " of memory available");
  // Pixel weights: luminance × sin θ at the row's centre (the solid angle a row covers).
  std::vector<double> weight(size_t(w) * h);
  std::vector<double> row_sum(size_t(h), 0.0);
  glm::dvec3 integral(0.0);
  for (int y = 0; y < h; ++y) {
    const double theta0 = glm::pi<double>() * y / h, theta1 = glm::pi<double>() * (y + 1) / h;
    const double sin_mid = std::sin(0.5 * (theta0 + theta1));
    const double solid_angle = glm::two_pi<double>() / w * (std::cos(theta0) - std::cos(theta1));
    for (int x = 0; x < w; ++x) {
      const glm::vec3 c(image_.pixel(x, y)[0], image_.pixel(x, y)[1], image_.pixel(x, y)[2]);
      if (!(c.x >= 0.f && c.y >= 0.f && c.z >= 0.f && c.x <= kMaxRadiance && c.y <= kMaxRadiance &&
            c.z <= kMaxRadiance))
        throw Error(what + ": environment pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                    ") " + bad_radiance(c));
      weight[size_t(y) * w + x] = double(luminance(c)) * sin_mid;
      row_sum[size_t(y)] += weight[size_t(y) * w + x];
      integral += glm::dvec3(c) * solid_angle;
    }
  }
  average_ = glm::vec3(integral / (4.0 * glm::pi<double>()));
  for (double r : row_sum) total_ += r;
  if (total_ <= 0.0) return;
  const float* first = image_.pixel(0, 0);
  constant_ = true;
  for (size_t i = 0; i < image_.rgb.size() && constant_; i += 3)
    constant_ = image_.rgb[i] == first[0] && image_.rgb[i + 1] == first[1] &&
                image_.rgb[i + 2] == first[2];
  if (constant_) average_ = glm::vec3(first[0], first[1], first[2]);
  rows_ = AliasTable(row_sum);
  columns_.reserve(size_t(h));
  for (int y = 0; y < h; ++y)
    columns_.emplace_back(std::vector<double>(weight.begin() + ptrdiff_t(y) * w,
                                              weight.begin() + ptrdiff_t(y + 1) * w));
}

int EnvironmentMap::pixel_index(const glm::vec3& direction) const {
  const glm::vec2 uv = to_uv(direction);
  const int x = std::clamp(int(uv.x * image_.width), 0, image_.width - 1);
  const int y = std::clamp(int(uv.y * image_.height), 0, image_.height - 1);
  return y * image_.width + x;
}

glm::vec3 EnvironmentMap::radiance(const glm::vec3& direction) const {
  if (constant_) return average_;
  const float* p = &image_.rgb[3 * size_t(pixel_index(direction))];
  return {p[0], p[1], p[2]};
}

float EnvironmentMap::pdf(const glm::vec3& direction) const {
  if (constant_) return glm::one_over_pi<float>() * 0.25f;
  const float sin_theta = std::sqrt(std::max(0.f, 1.f - direction.y * direction.y));
  if (!(sin_theta > 0.f) || total_ <= 0.0) return 0.f;
  // Constant density in (u, v) over the pixel, and dω = 2π² sin θ du dv. The pixel's probability
  // is a product of two multiples of 2⁻²⁴: exact in double.
  const int i = pixel_index(direction), x = i % image_.width, y = i / image_.width;
  const AliasTable& row = columns_[size_t(y)];
  if (row.empty()) return 0.f;
  const double pmf = rows_.pmf(size_t(y)) * row.pmf(size_t(x));
  return float(pmf * image_.width * image_.height /
               (2.0 * glm::pi<double>() * glm::pi<double>() * double(sin_theta)));
}

EnvironmentMap::Sample EnvironmentMap::sample(const glm::vec4& u) const {
  if (total_ <= 0.0) return {glm::vec3(0.f, 1.f, 0.f), glm::vec3(0.f), 0.f};
  if (constant_) {
    const float y = 1.f - 2.f * u.x, r = std::sqrt(std::max(0.f, 1.f - y * y));
    const float phi = glm::two_pi<float>() * u.y;
    return {{r * std::sin(phi), y, -r * std::cos(phi)}, average_, pdf({})};
  }
  const int w = image_.width, h = image_.height;
  const uint32_t y = rows_.sample(u.x), x = columns_[y].sample(u.y);
  const glm::vec3 d = from_uv({(float(x) + u.z) / float(w), (float(y) + u.w) / float(h)});
  return {d, radiance(d), pdf(d)};
}

}  // namespace dacrt
