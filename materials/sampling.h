// Sampling building blocks: orthonormal frames, cosine-weighted hemisphere directions, uniform
// points on triangles, and the power heuristic for multiple importance sampling.
#pragma once

#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

namespace dacrt {

// An orthonormal basis around a unit normal (Duff et al., "Building an Orthonormal Basis,
// Revisited", JCGT 2017): branch-free and continuous except at one pole.
struct Frame {
  glm::vec3 s, t, n;
  explicit Frame(const glm::vec3& normal) : n(normal) {
    float sign = std::copysign(1.f, n.z);
    float a = -1.f / (sign + n.z), b = n.x * n.y * a;
    s = glm::vec3(1.f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = glm::vec3(b, sign + n.y * n.y * a, -n.y);
  }
  glm::vec3 to_world(const glm::vec3& v) const { return v.x * s + v.y * t + v.z * n; }
  glm::vec3 to_local(const glm::vec3& v) const {
    return {glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)};
  }
};

// cos x and sin x for |x| ≤ π/4, by their Taylor polynomials to x⁸ and x⁹ (the first terms left
// out are below 2.6e-8 there, under half a float ulp of 1): no range reduction, no branches.
inline glm::vec2 cos_sin_quarter(float x) {
  const float x2 = x * x;
  const float c = 1.f + x2 * (-1.f / 2 + x2 * (1.f / 24 + x2 * (-1.f / 720 + x2 * (1.f / 40320))));
  const float s =
      x * (1.f + x2 * (-1.f / 6 + x2 * (1.f / 120 + x2 * (-1.f / 5040 + x2 * (1.f / 362880)))));
  return {c, s};
}

// Cosine-weighted direction around +z from two uniforms (concentric disk mapping, Shirley-Chiu).
// Branch-free: the square's point (a, b) is on the disk at radius r = the larger of |a|, |b| (with
// its sign) and angle φ, and both of the mapping's cases take cos and sin of an angle ψ in
// [−π/4, π/4]: φ = ψ = π/4 · b/a, or φ = π/2 − ψ with ψ = π/4 · a/b (cos φ = sin ψ, sin φ = cos ψ).
inline glm::vec3 sample_cosine_hemisphere(float u1, float u2) {
  const float a = 2.f * u1 - 1.f, b = 2.f * u2 - 1.f;
  const bool a_major = std::abs(a) > std::abs(b);
  const float r = a_major ? a : b, minor = a_major ? b : a;
  const glm::vec2 cs = cos_sin_quarter(glm::quarter_pi<float>() * (minor / (r != 0.f ? r : 1.f)));
  const float x = r * (a_major ? cs.x : cs.y), y = r * (a_major ? cs.y : cs.x);
  return {x, y, std::sqrt(std::max(0.f, 1.f - x * x - y * y))};
}

inline float cosine_hemisphere_pdf(float cos_theta) {
  return cos_theta > 0.f ? cos_theta * glm::one_over_pi<float>() : 0.f;
}

// Barycentric weights (of corners 1 and 2) of a uniform point on a triangle.
inline glm::vec2 sample_triangle(float u1, float u2) {
  float s = std::sqrt(u1);
  return {s * (1.f - u2), s * u2};
}

// The weight a² / (a² + b²) of strategy a against b, written as 1 / (1 + (b/a)²) so that squares
// cannot overflow: a huge or infinite pdf gives a weight of 0 or 1 (pbrt-v4 guards the same case),
// never inf/inf = NaN, which the film would drop. Two infinite pdfs share the sample (½ each); a
// strategy whose pdf is 0 (or NaN) gets 0.
inline float power_heuristic(float pdf_a, float pdf_b) {
  if (!(pdf_a > 0.f)) return 0.f;
  const float r = pdf_b > 0.f ? pdf_b / pdf_a : 0.f;
  if (std::isnan(r)) return 0.5f;  // ∞ / ∞
  return 1.f / (1.f + r * r);
}

inline float luminance(const glm::vec3& c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;  // Rec.709
}

}  // namespace dacrt
