// The Charlie sheen lobe and its albedo table (see sheen.h).
#include "dacrt/materials/sheen.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

namespace dacrt {

float sheen_alpha(float roughness) {
  const float r = std::clamp(roughness, 0.f, 1.f);
  return std::max(sheen_min_alpha, r * r);
}

float sheen_d(float cos_h, float alpha) {
  const float inv = 1.f / alpha;
  const float sin2 = std::max(0.f, 1.f - cos_h * cos_h);
  return (2.f + inv) * std::pow(sin2, 0.5f * inv) * (0.5f * glm::one_over_pi<float>());
}

namespace {

// Estevez & Kulla's fit of the Charlie lobe's shadowing exponent: its five coefficients
// interpolated in (1 − α)² between their values at α = 1 and α = 0.
float charlie_l(float x, float alpha) {
  const float t = (1.f - alpha) * (1.f - alpha);
  const float a = glm::mix(21.5473f, 25.3245f, t), b = glm::mix(3.82987f, 3.32435f, t);
  const float c = glm::mix(0.19823f, 0.16801f, t), d = glm::mix(-1.97760f, -1.27393f, t);
  const float e = glm::mix(-4.32054f, -4.85967f, t);
  return a / (1.f + b * std::pow(x, c)) + d * x + e;
}

}  // namespace

float sheen_lambda(float cos_theta, float alpha) {
  const float x = std::clamp(std::abs(cos_theta), 0.f, 1.f);
  return x < 0.5f ? std::exp(charlie_l(x, alpha))
                  : std::exp(2.f * charlie_l(0.5f, alpha) - charlie_l(1.f - x, alpha));
}

float sheen_visibility(float cos_o, float cos_i, float alpha) {
  return 1.f /
         ((1.f + sheen_lambda(cos_o, alpha) + sheen_lambda(cos_i, alpha)) * (4.f * cos_o * cos_i));
}

// Midpoint rule over the hemisphere in (cos θi, φ), φ over [0, π] twice (the lobe is symmetric
// about wo's plane of incidence), summed in double: 128 × 64 points (tests/brdf_layers_test.cpp
// compares the table with the lobe's albedo by importance sampling).
float sheen_albedo_integral(float cos_o, float roughness) {
  const float alpha = sheen_alpha(roughness);
  // (V grows as 1 / cos θo at grazing: μ = 0 is taken as 1e-4, where the table's first node
  // stands for what rays that graze the surface see.)
  const float co = std::clamp(cos_o, 1e-4f, 1.f);
  const glm::vec3 wo(std::sqrt(std::max(0.f, 1.f - co * co)), 0.f, co);
  constexpr int n_t = 128, n_phi = 64;
  double sum = 0.0;
  for (int i = 0; i < n_t; ++i) {
    const float ci = (float(i) + 0.5f) / n_t, si = std::sqrt(1.f - ci * ci);
    const double v = sheen_visibility(co, ci, alpha);
    double ring = 0.0;
    for (int j = 0; j < n_phi; ++j) {
      const float phi = glm::pi<float>() * (float(j) + 0.5f) / n_phi;
      const glm::vec3 wi(si * std::cos(phi), si * std::sin(phi), ci);
      const glm::vec3 h = glm::normalize(wo + wi);
      ring += double(sheen_d(h.z, alpha)) * v;
    }
    sum += ring * ci;
  }
  // dω = d(cos θ) dφ; the φ half counted twice.
  return float(sum * (1.0 / n_t) * (glm::pi<double>() / n_phi) * 2.0);
}

namespace {

// Nodes at √μ = 0, 1/31, ..., 1 (dense at grazing angles, where E changes fast) and at α from
// sheen_min_alpha to 1 evenly in log α (E changes with the exponent 1/α).
constexpr int table_size = 32;
const float log_min_alpha = std::log(sheen_min_alpha);

float node_roughness(int r) {  // the roughness whose α is node r's
  return std::sqrt(std::exp(log_min_alpha * (1.f - float(r) / (table_size - 1))));
}

struct AlbedoTable {
  std::array<float, table_size * table_size> e;  // [roughness][cos θo]
  AlbedoTable() {
    for (int r = 0; r < table_size; ++r)
      for (int m = 0; m < table_size; ++m)
        e[r * table_size + m] = sheen_albedo_integral(
            float(m * m) / float((table_size - 1) * (table_size - 1)), node_roughness(r));
  }
};

}  // namespace

float sheen_albedo(float cos_o, float roughness) {
  static const AlbedoTable table;  // built on first use (thread-safe)
  const float x = std::sqrt(std::clamp(cos_o, 0.f, 1.f)) * (table_size - 1);
  const float y = (1.f - std::log(sheen_alpha(roughness)) / log_min_alpha) * (table_size - 1);
  const int x0 = std::min(int(x), table_size - 2), y0 = std::min(int(y), table_size - 2);
  const float fx = x - float(x0), fy = y - float(y0);
  auto at = [&](int r, int m) { return table.e[r * table_size + m]; };
  const float lo = at(y0, x0) + (at(y0, x0 + 1) - at(y0, x0)) * fx;
  const float hi = at(y0 + 1, x0) + (at(y0 + 1, x0 + 1) - at(y0 + 1, x0)) * fx;
  return lo + (hi - lo) * fy;
}

}  // namespace dacrt
