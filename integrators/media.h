// Media: the volumes (KHR_materials_volume) a path is inside, and what they do to it.
//
// A volume material (Material::volume(): thicknessFactor > 0 and transmissive) is the boundary of
// a closed mesh whose front faces look out. Each path keeps a small stack of the volumes it is
// in (MediumStack, at most MediumStack::depth = 4 deep): a refraction through a front face pushes
// the material, one through a back face removes its topmost entry. From the stack:
// - the IOR on either side of an interface: arriving at a front face of m, the relative IOR is
//   η(m) / η(top of the stack) (1 when the stack is empty: the camera is outside every volume);
//   arriving at a back face of m, it is η(top once m is removed) / η(m). So an ice cube in water
//   refracts by 1.31 / 1.33 and leaves into water, not air. Overlapping volumes (two meshes whose
//   interiors intersect) get no priorities: the IOR beyond a back face is whatever is on top once
//   m is removed.
// - absorption: Beer–Lambert, σ_a = −ln(attenuationColor) / attenuationDistance per channel, over
//   the length a ray travels inside the medium on top of the stack (not the thicknessFactor,
//   which the spec makes a hint for rasterisers: a path tracer measures the real distance).
//   attenuationDistance's default, +∞, absorbs nothing.
// Overflow: a fifth nested volume is not pushed. Its refractions stay right (the IOR of its own
// surfaces is known from the material), and leaving it finds nothing to remove; only its
// absorption is lost, inside it the path is attenuated by the enclosing medium instead.
// Paths start outside every volume (a camera inside one sees no absorption until it crosses a
// boundary).
//
// KHR_materials_dispersion: a path that meets a dispersive volume material (dispersion > 0)
// before following a channel picks one of R, G, B uniformly and continues as that channel alone
// (its throughput ×3 there, 0 in the others); every IOR it meets is then the channel's, at
// channel_wavelength (materials/dielectric.h). An RGB approximation of the spectral effect.
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "dacrt/materials/dielectric.h"
#include "dacrt/materials/material.h"

namespace dacrt {

struct MediumStack {
  static constexpr int depth = 4;
  uint32_t material[depth];
  uint8_t size = 0;
  int8_t channel = -1;  // the colour channel the path follows (dispersion), or −1: all three
  int top() const { return size ? int(material[size - 1]) : -1; }
};

// One volume material, as a medium.
struct Medium {
  glm::vec3 sigma_a{0.f};  // absorption coefficient, per unit length (world units)
  float ior = 1.5f;        // KHR_materials_ior (0, "infinite", as 1e6)
  float dispersion = 0.f;  // KHR_materials_dispersion: 20 / Abbe number
  bool absorbs = false;
};

// The medium of a volume material m, or nothing if m is not a volume's.
std::optional<Medium> medium_of(const Material& m);

// Beer–Lambert transmittance exp(−σ_a d), per channel (a channel of σ_a 0 stays 1, also for
// d = ∞; d = 0 gives 1 whatever σ_a).
inline glm::vec3 beer_lambert(const glm::vec3& sigma_a, float distance) {
  glm::vec3 t(1.f);
  for (int c = 0; c < 3; ++c)
    if (sigma_a[c] > 0.f && distance > 0.f) t[c] = std::exp(-sigma_a[c] * distance);
  return t;
}

class Media {
 public:
  explicit Media(const std::vector<Material>& materials);

  bool any() const { return any_; }          // some material is a volume
  bool absorbing() const { return absorbs_; }  // ... and one of them absorbs
  const std::optional<Medium>& medium(uint32_t material) const { return media_[material]; }

  // The IOR of volume material m for the path's channel (−1: the material's own).
  float ior(uint32_t m, int channel) const;
  // The IOR of the medium on top of the stack (1 outside every volume).
  float ior(const MediumStack& s) const { return s.size ? ior(uint32_t(s.top()), s.channel) : 1.f; }
  // The relative IOR η_beyond / η_arrival at a hit of volume material m, arriving at its front
  // face (front) or its back face.
  float eta(const MediumStack& s, uint32_t m, bool front) const;
  // The transmittance along a segment of length `distance` in the medium on top of the stack.
  glm::vec3 transmittance(const MediumStack& s, float distance) const {
    const int m = s.top();
    return m >= 0 && media_[m]->absorbs ? beer_lambert(media_[m]->sigma_a, distance)
                                        : glm::vec3(1.f);
  }

  // The stack after a refraction through a face of volume material m.
  static void cross(MediumStack& s, uint32_t m, bool front);

 private:
  std::vector<std::optional<Medium>> media_;  // by material
  bool any_ = false, absorbs_ = false;
};

}  // namespace dacrt
