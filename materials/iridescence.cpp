// KHR_materials_iridescence's thin-film Fresnel (see iridescence.h).
#include "dacrt/materials/iridescence.h"

#include <algorithm>
#include <cmath>

#include "dacrt/materials/dielectric.h"

namespace dacrt {
namespace {

// The CIE 1931 matching functions' response, normalised to an equal-energy spectrum and taken to
// linear Rec. 709, to cos(2π · opd / λ): Belcour & Barla's Gaussian fit, Fourier-transformed.
// Each channel is divided by what an equal-energy spectrum gives (see iridescence.h).
glm::vec3 sensitivity(float opd_nm) {
  const float phase = 2.f * 3.14159265f * opd_nm * 1e-9f, p2 = phase * phase;
  // val · √(2π var) / 1.0685e-7, pos, var of each Gaussian (x̄ has two).
  const glm::vec3 xyz(0.84659f * std::cos(1.6810e6f * phase) * std::exp(-4.3278e9f * p2) +
                          0.15387f * std::cos(2.2399e6f * phase) * std::exp(-4.5282e9f * p2),
                      1.00022f * std::cos(1.7953e6f * phase) * std::exp(-9.3046e9f * p2),
                      1.00112f * std::cos(2.2084e6f * phase) * std::exp(-6.6121e9f * p2));
  // XYZ to linear Rec. 709 (rows), each divided by its row's sum.
  return {(3.2404542f * xyz.x - 1.5371385f * xyz.y - 0.4985314f * xyz.z) / 1.2047843f,
          (-0.9692660f * xyz.x + 1.8760108f * xyz.y + 0.0415560f * xyz.z) / 0.9483008f,
          (0.0556434f * xyz.x - 0.2040259f * xyz.y + 1.0572252f * xyz.z) / 0.9088427f};
}

}  // namespace

glm::vec3 thin_film_fresnel(float cos_theta1, float outside_ior, float film_ior, float thickness_nm,
                            const glm::vec3& base_f0) {
  const float cos1 = std::clamp(cos_theta1, 0.f, 1.f);
  // Beyond 10⁵ nm the spectral terms are 0 to float precision; the clamp keeps the phase finite.
  const float d = std::clamp(thickness_nm, 0.f, 1e5f);
  const float n1 = std::max(outside_ior, 1.f);
  // The film fades into the outside medium as it vanishes.
  const float t = std::clamp(d / 0.03f, 0.f, 1.f), fade = t * t * (3.f - 2.f * t);
  const float n2 = n1 + (std::clamp(film_ior, 1.f, 1e6f) - n1) * fade;
  // The first interface, and the angle inside the film (Snell).
  const float r12 = fresnel_dielectric(cos1, n2 / n1), t121 = 1.f - r12;
  const float sin2_sq = (n1 / n2) * (n1 / n2) * (1.f - cos1 * cos1);
  if (sin2_sq >= 1.f) return glm::vec3(1.f);  // total internal reflection
  const float cos2 = std::sqrt(1.f - sin2_sq);
  const float opd = 2.f * n2 * d * cos2;
  const glm::vec3 s1 = sensitivity(opd), s2 = sensitivity(2.f * opd);
  // Phase shifts are 0 or π: reflecting off a lower IOR shifts by π. Their sum φ21 + φ23 enters
  // the m-th term as cos(m (δ + φ)) = cos(m δ) · (−1)^(m k), with k the number of π shifts.
  const int k21 = n2 < n1 ? 0 : 1;  // φ21 = π − φ12
  glm::vec3 f;
  for (int c = 0; c < 3; ++c) {
    // The base's IOR from its F0, as if it were a dielectric seen from the air.
    const float root = std::sqrt(std::clamp(base_f0[c], 0.f, 0.9999f));
    const float n3 = (1.f + root) / (1.f - root);
    const float r23 = fresnel_dielectric(cos2, n3 / n2);
    const int k = k21 + (n3 < n2 ? 1 : 0);
    // The Airy sum as a Fourier series: the constant term, then the first two harmonics.
    const float r123 = std::min(r12 * r23, 0.9999f), amplitude = std::sqrt(r123);
    const float rs = t121 * t121 * r23 / (1.f - r123);
    const float c1 = (rs - t121) * amplitude, c2 = c1 * amplitude;
    const float sign1 = k % 2 ? -1.f : 1.f;  // (−1)^k; (−1)^(2k) = 1
    f[c] = r12 + rs + 2.f * (c1 * sign1 * s1[c] + c2 * s2[c]);
  }
  return glm::clamp(f, 0.f, 1.f);
}

}  // namespace dacrt
