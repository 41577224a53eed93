// Bsdf: what a shading point scatters by. For most materials it is the glTF BRDF alone
// (materials/gltf_brdf.h), evaluated exactly as GltfBrdf does. A KHR_materials_volume material
// (thicknessFactor > 0, transmissive) replaces the thin-walled transmission by a refractive
// interface (materials/dielectric.h): with metallic m and transmission t (after textures),
//   f = (1 − q) · glTF BRDF(transmission 0, metallic m / (1 − q)) + q · Layers[RoughDielectric],
//   q = (1 − m) t
// which is the glTF mix of the opaque dielectric, the metal and the transmission lobe with the
// thin-walled BTDF swapped for the rough dielectric (whose own Fresnel reflection, with the
// material's specular factor and colour, iridescence and anisotropy, replaces the specular layer
// over the transmitted part). The coat and the sheen lie over both parts as over any glTF BRDF
// (materials/layers.h: f = coat + (1 − c F_c) (sheen + s f_base) is linear in f_base, so layering
// each part is layering the mix), on the front face: arriving from inside the volume, the
// interface is bare (the layers are on its outside; so is the iridescent film).
// Sampling picks the dielectric with probability q and the BRDF otherwise, then a layer or the
// interface; pdf() is the mixture's, so sample, eval and pdf agree.
#pragma once

#include <glm/glm.hpp>
#include <optional>

#include "dacrt/materials/dielectric.h"
#include "dacrt/materials/gltf_brdf.h"
#include "dacrt/materials/layers.h"

namespace dacrt {

class Bsdf {
 public:
  // The glTF BRDF alone (thin-walled transmission, as without KHR_materials_volume); implicit, so
  // that a GltfBrdf is a Bsdf wherever one is asked for.
  Bsdf(const GltfBrdf& brdf) : brdf_(brdf) {}
  // A volume material's interface, of relative IOR eta (η of the side below over the side above,
  // from the media the path is in: integrators/media.h), arriving at its front face (from
  // outside) or its back face.
  static Bsdf volume(const BrdfParams& p, float eta, bool front = true);

  glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi) const;
  float pdf(const glm::vec3& wo, const glm::vec3& wi) const;
  std::optional<GltfBrdf::Sample> sample(const glm::vec3& wo, float u_lobe, float u1,
                                         float u2) const;

  bool lambertian() const { return !dielectric_ && brdf_.lambertian(); }
  // The refractive interface, if the material is a volume's.
  const std::optional<RoughDielectric>& dielectric() const { return dielectric_; }
  // The glTF BRDF (all of the BSDF when there is no interface).
  const GltfBrdf& gltf() const { return brdf_; }

 private:
  Bsdf(const GltfBrdf& brdf, const RoughDielectric& dielectric, float q,
       const MaterialLayers& layers)
      : brdf_(brdf), dielectric_(dielectric), q_(q), layers_(layers) {}
  // The layered interface (the q part, without q).
  glm::vec3 interface_eval(const glm::vec3& wo, const glm::vec3& wi) const;
  float interface_pdf(const glm::vec3& wo, const glm::vec3& wi) const;
  std::optional<GltfBrdf::Sample> interface_sample(const glm::vec3& wo, float u_lobe, float u1,
                                                   float u2) const;

  GltfBrdf brdf_;
  std::optional<RoughDielectric> dielectric_;
  float q_ = 0.f;          // the dielectric's weight and sampling probability
  MaterialLayers layers_;  // over the dielectric (none on back faces)
};

}  // namespace dacrt
