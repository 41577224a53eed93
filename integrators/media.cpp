// The volumes a path is inside (see media.h).
#include "dacrt/integrators/media.h"

#include <algorithm>

namespace dacrt {

std::optional<Medium> medium_of(const Material& m) {
  if (!m.volume()) return std::nullopt;
  Medium out;
  out.ior = m.ior == 0.f ? 1e6f : m.ior;
  out.dispersion = m.dispersion;
  if (m.attenuation_distance < INFINITY)
    for (int c = 0; c < 3; ++c)
      out.sigma_a[c] = -std::log(std::clamp(m.attenuation_color[c], 0.f, 1.f)) /
                       m.attenuation_distance;  // colour 0: σ_a = ∞, nothing gets through
  out.absorbs = out.sigma_a != glm::vec3(0.f);
  return out;
}

Media::Media(const std::vector<Material>& materials) {
  for (const Material& m : materials) {
    media_.push_back(medium_of(m));
    any_ |= media_.back().has_value();
    absorbs_ |= media_.back() && media_.back()->absorbs;
  }
}

float Media::ior(uint32_t m, int channel) const {
  const Medium& medium = *media_[m];
  return channel < 0 ? medium.ior
                     : dispersive_ior(medium.ior, medium.dispersion, channel_wavelength[channel]);
}

float Media::eta(const MediumStack& s, uint32_t m, bool front) const {
  if (front) return ior(m, s.channel) / ior(s);
  MediumStack after = s;
  cross(after, m, false);
  return ior(after) / ior(m, s.channel);
}

void Media::cross(MediumStack& s, uint32_t m, bool front) {
  if (front) {
    if (s.size < MediumStack::depth) s.material[s.size++] = m;  // else: overflow (media.h)
    return;
  }
  for (int k = int(s.size) - 1; k >= 0; --k)
    if (s.material[k] == m) {
      for (int j = k; j + 1 < int(s.size); ++j) s.material[j] = s.material[j + 1];
      --s.size;
      return;
    }
}

}  // namespace dacrt
