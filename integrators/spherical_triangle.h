// Spherical triangles: the solid angle a triangle subtends from a point, and directions drawn
// uniformly over it (Arvo 1995, "Stratified Sampling of Spherical Triangles", SIGGRAPH). Next-event
// estimation draws them towards emitters that are large and near (integrators/light_sampling.cpp):
// sampling such a triangle by area puts most points where it is far or seen edge-on, each of them
// worth dist² / cos, while a uniform direction in its solid angle Ω is worth Ω, the same for all.
// Everything is in double: the sampling formulas subtract nearly equal cosines for small triangles,
// and the callers only use them above a solid angle of 0.5 sr (LightSampling::min_solid_angle).
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

namespace dacrt {

// The unit tangent at `from` of the great circle towards `to` (both unit); 0 if they coincide.
inline glm::dvec3 great_circle_tangent(const glm::dvec3& from, const glm::dvec3& to) {
  const glm::dvec3 t = to - glm::dot(to, from) * from;
  const double length = glm::length(t);
  return length > 0.0 ? t / length : glm::dvec3(0.0);
}

// The area of the spherical triangle with unit corners a, b, c, i.e. the solid angle of any planar
// triangle they are the directions of. From tan(Ω/2) = |a·(b×c)| / (1 + a·b + b·c + c·a) (Van
// Oosterom & Strackee 1983), which keeps its precision for small triangles, unlike the angle sum.
inline double spherical_triangle_area(const glm::dvec3& a, const glm::dvec3& b,
                                      const glm::dvec3& c) {
  const double det = std::abs(glm::dot(a, glm::cross(b, c)));
  const double den = 1.0 + glm::dot(a, b) + glm::dot(b, c) + glm::dot(c, a);
  return 2.0 * std::atan2(det, den);
}

// The solid angle triangle (p0, p1, p2) subtends from point o: 0 when o is on a corner.
inline double triangle_solid_angle(const glm::dvec3& o, const glm::dvec3& p0, const glm::dvec3& p1,
                                   const glm::dvec3& p2) {
  const glm::dvec3 a = p0 - o, b = p1 - o, c = p2 - o;
  const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
  if (!(la > 0.0 && lb > 0.0 && lc > 0.0)) return 0.0;
  return spherical_triangle_area(a / la, b / lb, c / lc);
}

// A direction uniform over the spherical triangle (a, b, c) of area `area` (> 0), from two
// uniforms. Arvo's construction: u1 sets the area u1·Ω of the sub-triangle (a, b, c') whose corner
// c' slides along the arc from a to c, solved for in closed form from the interior angle α at a and
// the arc length of a b; u2 then places the direction on the arc from b to c', uniform in the
// cosine of its angle from b, which is what makes the density the same everywhere.
inline glm::dvec3 sample_spherical_triangle(const glm::dvec3& a, const glm::dvec3& b,
                                            const glm::dvec3& c, double area, double u1,
                                            double u2) {
  const glm::dvec3 ab = great_circle_tangent(a, b), ac = great_circle_tangent(a, c);
  const double alpha = std::atan2(glm::length(glm::cross(ab, ac)), glm::dot(ab, ac));
  const double cos_ab = glm::dot(a, b);  // cosine of the arc a b
  const double s = std::sin(u1 * area - alpha), t = std::cos(u1 * area - alpha);
  const double cos_alpha = std::cos(alpha), sin_alpha = std::sin(alpha);
  const double u = t - cos_alpha, v = s + sin_alpha * cos_ab;
  const double den = (v * s + u * t) * sin_alpha;
  // The cosine of the arc a c': at u1 = 1 it is a·c, at u1 = 0 the sub-triangle is empty.
  const double q =
      den != 0.0 ? std::clamp(((v * t - u * s) * cos_alpha - v) / den, -1.0, 1.0) : 1.0;
  const glm::dvec3 c_sub = q * a + std::sqrt(std::max(0.0, 1.0 - q * q)) * ac;
  const double z = 1.0 - u2 * (1.0 - glm::dot(c_sub, b));
  return glm::normalize(z * b +
                        std::sqrt(std::max(0.0, 1.0 - z * z)) * great_circle_tangent(b, c_sub));
}

}  // namespace dacrt
