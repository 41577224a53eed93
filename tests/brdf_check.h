// Checks shared by the BRDF tests: the χ² test of GltfBrdf::sample against a pdf (tests/chi2.h)
// and the directional albedo by importance sampling (the white furnace).
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <optional>
#include <utility>

#include "chi2.h"
#include "dacrt/materials/gltf_brdf.h"
#include "dacrt/materials/sampling.h"
#include "dacrt/util/random.h"

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

// `n` samples from wo: each one's pdf is pdf(wo, wi) and its weight eval · |cos θi| / pdf.
// Returns how many went below the surface (transmission).
inline size_t check_sample_weights(const GltfBrdf& brdf, const glm::vec3& wo, Pcg32& rng,
                                   int n = 2000) {
  size_t below = 0;
  for (int k = 0; k < n; ++k) {
    const auto s = brdf.sample(wo, rng.uniform(), rng.uniform(), rng.uniform());
    if (!s) continue;
    below += s->wi.z < 0.f;
    CHECK(s->pdf == doctest::Approx(brdf.pdf(wo, s->wi)).epsilon(1e-5));
    const glm::vec3 expected = brdf.eval(wo, s->wi) * std::abs(s->wi.z) / s->pdf;
    for (int ch = 0; ch < 3; ++ch)
      CHECK(s->weight[ch] == doctest::Approx(expected[ch]).epsilon(1e-5));
  }
  return below;
}

// Reciprocity f(a, b) = f(b, a) on `pairs` cosine-distributed pairs of directions above the surface
// (pairs with a cosine at or below `min_cos` skipped), and nothing below it: for BRDFs without
// transmission.
inline void check_reciprocal_reflection(const GltfBrdf& brdf, Pcg32& rng, float min_cos,
                                        int pairs = 500) {
  for (int k = 0; k < pairs; ++k) {
    const glm::vec3 a = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
    const glm::vec3 b = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
    if (!(a.z > min_cos && b.z > min_cos)) continue;
    const glm::vec3 fab = brdf.eval(a, b), fba = brdf.eval(b, a);
    for (int ch = 0; ch < 3; ++ch) CHECK(fab[ch] == doctest::Approx(fba[ch]).epsilon(1e-4));
    const glm::vec3 below(b.x, b.y, -b.z);
    CHECK(brdf.eval(a, below) == glm::vec3(0.f));
    CHECK(brdf.pdf(a, below) == 0.f);
  }
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
