#include "scene/environment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/constants.hpp>
#include <string>

#include "materials/sampling.h"
#include "util/error.h"

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
  // Pixel weights: luminance × sin θ at the row's centre (the solid angle a row covers).
  std::vector<double> weight(size_t(w) * h);
  marginal_.resize(size_t(h));
  conditional_.resize(size_t(w) * h);
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
  pmf_.assign(size_t(w) * h, 0.f);
  if (total_ <= 0.0) return;
  double running = 0.0;
  for (int y = 0; y < h; ++y) {
    running += row_sum[size_t(y)];
    marginal_[size_t(y)] = float(running / total_);
    double in_row = 0.0;
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      in_row += weight[i];
      conditional_[i] = row_sum[size_t(y)] > 0.0 ? float(in_row / row_sum[size_t(y)]) : 1.f;
      pmf_[i] = float(weight[i] / total_);
    }
    conditional_[size_t(y) * w + w - 1] = 1.f;
  }
  marginal_.back() = 1.f;
}

int EnvironmentMap::pixel_index(const glm::vec3& direction) const {
  const glm::vec2 uv = to_uv(direction);
  const int x = std::clamp(int(uv.x * image_.width), 0, image_.width - 1);
  const int y = std::clamp(int(uv.y * image_.height), 0, image_.height - 1);
  return y * image_.width + x;
}

glm::vec3 EnvironmentMap::radiance(const glm::vec3& direction) const {
  const float* p = &image_.rgb[3 * size_t(pixel_index(direction))];
  return {p[0], p[1], p[2]};
}

float EnvironmentMap::pdf(const glm::vec3& direction) const {
  const float sin_theta = std::sqrt(std::max(0.f, 1.f - direction.y * direction.y));
  if (!(sin_theta > 0.f) || total_ <= 0.0) return 0.f;
  // Constant density in (u, v) over the pixel, and dω = 2π² sin θ du dv.
  return pmf_[size_t(pixel_index(direction))] * float(image_.width) * float(image_.height) /
         (2.f * glm::pi<float>() * glm::pi<float>() * sin_theta);
}

EnvironmentMap::Sample EnvironmentMap::sample(float u1, float u2) const {
  if (total_ <= 0.0) return {glm::vec3(0.f, 1.f, 0.f), glm::vec3(0.f), 0.f};
  const int w = image_.width, h = image_.height;
  // The row by the marginal, the column by the row's conditional; each uniform's remainder
  // within the chosen interval places the point inside the pixel.
  const int y = std::min(
      h - 1, int(std::upper_bound(marginal_.begin(), marginal_.end(), u1) - marginal_.begin()));
  const float r0 = y > 0 ? marginal_[size_t(y) - 1] : 0.f, r1 = marginal_[size_t(y)];
  const float fv = r1 > r0 ? std::clamp((u1 - r0) / (r1 - r0), 0.f, 1.f) : 0.5f;
  const auto row = conditional_.begin() + ptrdiff_t(y) * w;
  const int x = std::min(w - 1, int(std::upper_bound(row, row + w, u2) - row));
  const float c0 = x > 0 ? row[x - 1] : 0.f, c1 = row[x];
  const float fu = c1 > c0 ? std::clamp((u2 - c0) / (c1 - c0), 0.f, 1.f) : 0.5f;
  const glm::vec3 d = from_uv({(x + fu) / w, (y + fv) / h});
  return {d, radiance(d), pdf(d)};
}

}  // namespace dacrt
