// The GGX (Trowbridge-Reitz) microfacet pieces the glTF BRDF and the clearcoat share (defined in
// gltf_brdf.cpp), exposed for the tests.
#pragma once

#include <glm/glm.hpp>

namespace dacrt {

float ggx_d(float cos_h, float alpha);
float ggx_lambda(float cos_theta, float alpha);  // Smith Λ
// Height-correlated visibility G₂ / (4 cos_o cos_i).
float ggx_visibility(float cos_o, float cos_i, float alpha);
// A visible normal for wo (upper hemisphere), Heitz 2018; with two α, of the anisotropic
// distribution with α_x along x and α_y along y (materials/anisotropy.h).
glm::vec3 sample_ggx_visible_normal(const glm::vec3& wo, float alpha_x, float alpha_y, float u1,
                                    float u2);
inline glm::vec3 sample_ggx_visible_normal(const glm::vec3& wo, float alpha, float u1, float u2) {
  return sample_ggx_visible_normal(wo, alpha, alpha, u1, u2);
}

}  // namespace dacrt
