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

float sheen_visibility(float cos_o, float cos_i) {
  return 1.f / (4.f * (cos_i + cos_o - cos_i * cos_o));
}

// Midpoint rule over the hemisphere in (cos θi, φ), φ over [0, π] twice (the lobe is symmetric
// about wo's plane of incidence), summed in double: 128 × 64 points (tests/brdf_layers_test.cpp
// compares the table with the lobe's albedo by importance sampling).
float sheen_albedo_integral(float cos_o, float roughness) {
  const float alpha = sheen_alpha(roughness);
  const float co = std::clamp(cos_o, 0.f, 1.f);
  const glm::vec3 wo(std::sqrt(std::max(0.f, 1.f - co * co)), 0.f, co);
  constexpr int n_t = 128, n_phi = 64;
  double sum = 0.0;
  for (int i = 0; i < n_t; ++i) {
    const float ci = (float(i) + 0.5f) / n_t, si = std::sqrt(1.f - ci * ci);
    double ring = 0.0;
    for (int j = 0; j < n_phi; ++j) {
      const float phi = glm::pi<float>() * (float(j) + 0.5f) / n_phi;
      const glm::vec3 wi(si * std::cos(phi), si * std::sin(phi), ci);
      const glm::vec3 h = glm::normalize(wo + wi);
      ring += double(sheen_d(h.z, alpha)) * sheen_visibility(co, ci);
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
