// EnvironmentMap: the radiance of everything rays escape to, from an equirectangular
// (latitude-longitude) image, importance-sampled by pixel luminance for next-event estimation.
//
// Directions use glTF's axes (+Y up). Pixel column u ∈ [0, 1) is the azimuth φ = 2π (u − ½)
// measured from −Z (the default camera's view) towards +X, so the image's centre is straight ahead;
// row v ∈ [0, 1) is the polar angle θ = π v from +Y, the top row being the zenith. A pixel's
// radiance is constant over it (nearest lookup), which is exactly what the sampling distribution
// assumes, so sample(), radiance() and pdf() agree. The row is chosen by an alias table over rows
// (the marginal), the column by the row's own alias table (the conditional), so pdf() is the
// probability the sampling realises (util/alias_table.h), not a rounded cdf's. A constant map (a
// uniform sky, or dacrt's own stand-in for one) is sampled uniformly over the sphere instead, from
// u.x and u.y alone by inversion: its pdf is 1/4π, where the pixel grid's is 1/sin θ (crowding the
// poles), and the pattern's 2D stratification survives, which the alias tables' discrete choice
// breaks.
#pragma once

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "dacrt/util/image.h"
#include "dacrt/util/alias_table.h"

namespace dacrt {

class EnvironmentMap {
 public:
  // Throws dacrt::Error for an empty image or negative / non-finite pixels, naming `what`.
  EnvironmentMap(Image image, const std::string& what);

  glm::vec3 radiance(const glm::vec3& direction) const;

  struct Sample {
    glm::vec3 direction;
    glm::vec3 radiance;
    float pdf;  // solid angle
  };
  // u.x picks the row, u.y the column, (u.z, u.w) the point inside the pixel.
  Sample sample(const glm::vec4& u) const;
  float pdf(const glm::vec3& direction) const;

  bool black() const { return total_ <= 0.0; }
  bool constant() const { return constant_; }
  glm::vec3 average() const { return average_; }  // over the sphere (solid-angle weighted)
  const Image& image() const { return image_; }

  // The (u, v) of a direction, and back.
  static glm::vec2 to_uv(const glm::vec3& direction);
  static glm::vec3 from_uv(const glm::vec2& uv);

 private:
  int pixel_index(const glm::vec3& direction) const;

  Image image_;
  AliasTable rows_;                  // the marginal
  std::vector<AliasTable> columns_;  // per row, the conditional (empty for a black row)
  double total_ = 0.0;
  glm::vec3 average_{0.f};
  bool constant_ = false;  // every pixel the same, not black: radiance average_ everywhere
};

}  // namespace dacrt
