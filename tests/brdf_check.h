// Checks shared by the BRDF tests: the χ² test of GltfBrdf::sample against a pdf (tests/chi2.h)
// and the directional albedo by importance sampling (the white furnace).
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <optional>
#include <utility>

#include "chi2.h"
#include "materials/gltf_brdf.h"
#include "util/random.h"

namespace dacrt::test {

// The BRDF's sampling of wi for a fixed wo, against another (or the same) BRDF's pdf (`sub`: see
// chi2_p_value; more where a lobe meets the horizon, where the pdf jumps to 0).
inline double brdf_chi2_p_value(const GltfBrdf& sampler, const GltfBrdf& model,
                                const glm::vec3& wo, uint64_t seed, size_t samples,
                                int sub = 16) {
  return chi2_p_value(
      [&](Pcg32& rng) -> std::optional<glm::vec3> {
        const float u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
        const auto s = sampler.sample(wo, u0, u1, u2);
        if (!s) return std::nullopt;
        return s->wi;
      },
      [&](const glm::vec3& wi) { return model.pdf(wo, wi); }, seed, samples, sub);
}

// ∫ f |cos| dωi from wo by importance sampling, per channel, with its standard error.
inline std::pair<glm::dvec3, glm::dvec3> brdf_albedo(const GltfBrdf& brdf, const glm::vec3& wo,
                                                     uint64_t seed, int n = 200000) {
  Pcg32 rng(seed);
  glm::dvec3 sum(0.0), sum2(0.0);
  for (int k = 0; k < n; ++k) {
    const auto s = brdf.sample(wo, rng.uniform(), rng.uniform(), rng.uniform());
    if (!s) continue;
    const glm::dvec3 w(s->weight);
    sum += w, sum2 += w * w;
  }
  const glm::dvec3 mean = sum / double(n);
  const glm::dvec3 error = glm::sqrt(glm::max(sum2 / double(n) - mean * mean, 0.0) / double(n));
  return {mean, error};
}

}  // namespace dacrt::test
