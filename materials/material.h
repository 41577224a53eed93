// Material: the glTF material as this version renders it, plain data that shading reads through
// scene/surface.h (the BRDF in gltf_brdf.h, the textures in texture.h).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>

#include "dacrt/materials/gltf_brdf.h"
#include "dacrt/materials/texture.h"

namespace dacrt {

// The glTF material, as far as this version renders it: the metallic-roughness BRDF (with
// KHR_materials_ior and KHR_materials_specular, and the layers and lobes of the other material
// extensions read), its textures, and an emitter. Defaults are
// glTF's. Textures multiply their factors (see scene/surface.h).
struct Material {
  std::string name;
  glm::vec3 base_color{1.f};      // baseColorFactor.rgb
  float metallic = 1.f;           // metallicFactor
  float roughness = 1.f;          // roughnessFactor (perceptual)
  float ior = 1.5f;               // KHR_materials_ior
  float specular = 1.f;           // KHR_materials_specular.specularFactor
  glm::vec3 specular_color{1.f};  // KHR_materials_specular.specularColorFactor
  float transmission = 0.f;       // KHR_materials_transmission.transmissionFactor
  // KHR_materials_volume: thicknessFactor > 0 makes a transmissive material the boundary of a
  // refractive, absorbing volume (volume(), integrators/media.h); 0 keeps it thin-walled.
  float thickness = 0.f;                    // thicknessFactor (only its sign is used)
  glm::vec3 attenuation_color{1.f};         // attenuationColor
  float attenuation_distance = INFINITY;    // attenuationDistance (∞: no absorption)
  float dispersion = 0.f;                   // KHR_materials_dispersion: 20 / Abbe number
  float clearcoat = 0.f;            // KHR_materials_clearcoat.clearcoatFactor
  float clearcoat_roughness = 0.f;  // KHR_materials_clearcoat.clearcoatRoughnessFactor
  glm::vec3 sheen_color{0.f};       // KHR_materials_sheen.sheenColorFactor
  float sheen_roughness = 0.f;      // KHR_materials_sheen.sheenRoughnessFactor
  // KHR_materials_anisotropy: anisotropyStrength, and anisotropyRotation as (cos, sin): the
  // direction of increased roughness in the (tangent, bitangent) frame (scene/surface.cpp).
  float anisotropy = 0.f;
  glm::vec2 anisotropy_rotation{1.f, 0.f};
  float iridescence = 0.f;                     // KHR_materials_iridescence.iridescenceFactor
  float iridescence_ior = 1.3f;                // iridescenceIor
  float iridescence_thickness_min = 100.f;     // iridescenceThicknessMinimum (nm)
  float iridescence_thickness_max = 400.f;     // iridescenceThicknessMaximum (nm)
  // KHR_materials_unlit: a pre-lit surface. Camera rays see its base colour (× texture × vertex
  // colour) as emitted radiance; it casts no light (it is not sampled as an emitter, and a path
  // that scattered before reaching it gets nothing from it) and reflects nothing: to every other
  // ray it is a black occluder. (`emission` holds baseColorFactor.rgb; brdf() is black.) The
  // extension's "not lit", as Blender's importer builds it (an emission seen by camera rays only).
  bool unlit = false;
  glm::vec3 emission{0.f};        // emissiveFactor × KHR_materials_emissive_strength (radiance)
  bool double_sided = false;      // emitters emit from their back face too
  float alpha = 1.f;              // baseColorFactor.a
  // alphaMode: OPAQUE ignores alpha; MASK draws where alpha >= alpha_cutoff; BLEND draws with
  // probability alpha (stochastic transparency: unbiased, no sorting).
  enum class AlphaMode : uint8_t { opaque, mask, blend };
  AlphaMode alpha_mode = AlphaMode::opaque;
  float alpha_cutoff = 0.5f;

  TextureRef base_color_texture;          // sRGB; alpha in .a
  TextureRef metallic_roughness_texture;  // linear; roughness in .g, metallic in .b
  TextureRef normal_texture;              // tangent space, scaled by normal_scale
  TextureRef emissive_texture;            // sRGB
  TextureRef transmission_texture;        // linear; transmission in .r
  TextureRef specular_texture;            // linear; specular in .a (KHR_materials_specular)
  TextureRef specular_color_texture;      // sRGB; specular colour in .rgb
  TextureRef clearcoat_texture;           // linear; clearcoat in .r (KHR_materials_clearcoat)
  TextureRef clearcoat_roughness_texture;  // linear; clearcoat roughness in .g
  TextureRef clearcoat_normal_texture;     // tangent space, scaled by clearcoat_normal_scale
  TextureRef sheen_color_texture;          // sRGB; sheen colour in .rgb (KHR_materials_sheen)
  TextureRef sheen_roughness_texture;      // linear; sheen roughness in .a
  // linear; direction in .rg (× 2 − 1, then rotated), strength in .b (KHR_materials_anisotropy)
  TextureRef anisotropy_texture;
  TextureRef iridescence_texture;          // linear; iridescence in .r (KHR_materials_iridescence)
  // linear; .g mixes the film's thickness from minimum to maximum (maximum without it)
  TextureRef iridescence_thickness_texture;
  float normal_scale = 1.f;
  float clearcoat_normal_scale = 1.f;

  bool sheen() const { return sheen_color != glm::vec3(0.f); }
  // An anisotropic specular lobe (which needs a tangent frame: scene/surface.cpp).
  bool anisotropic() const { return anisotropy > 0.f && !unlit; }
  // The textures shading reads (null entries for the rest): an emissive texture only when the
  // emissive factor is not black, the transmission, specular, clearcoat, sheen, anisotropy and
  // iridescence ones only when their factors are not 0 (an unlit material reads its base colour
  // only).
  std::array<const TextureRef*, 15> sampled_textures() const {
    auto when = [](bool used, const TextureRef& t) { return used ? &t : nullptr; };
    const bool lit = !unlit;
    return {&base_color_texture,
            when(lit, metallic_roughness_texture),
            when(lit, normal_texture),
            when(lit && emissive(), emissive_texture),
            when(lit && transmission > 0.f, transmission_texture),
            when(lit && specular > 0.f, specular_texture),
            when(lit && specular > 0.f, specular_color_texture),
            when(lit && clearcoat > 0.f, clearcoat_texture),
            when(lit && clearcoat > 0.f, clearcoat_roughness_texture),
            when(lit && clearcoat > 0.f, clearcoat_normal_texture),
            when(lit && sheen(), sheen_color_texture),
            when(lit && sheen(), sheen_roughness_texture),
            when(anisotropic(), anisotropy_texture),
            when(lit && iridescence > 0.f, iridescence_texture),
            when(lit && iridescence > 0.f, iridescence_thickness_texture)};
  }
  bool textured() const {
    for (const TextureRef* t : sampled_textures())
      if (t && *t) return true;
    return false;
  }

  // A volume's boundary: thick and transmissive somewhere (a volume without transmission has no
  // effect, as KHR_materials_volume says: no light enters it). Decided from the factors and the
  // range their textures can give (metallic × a texel may be below a metallicFactor of 1); the
  // path tracer enters it only where the textured values transmit.
  bool volume() const {
    return thickness > 0.f && transmission > 0.f && (metallic < 1.f || metallic_roughness_texture);
  }
  bool emissive() const { return emission.x > 0.f || emission.y > 0.f || emission.z > 0.f; }
  // Casts light: emissive and not unlit (an unlit surface's colour is seen, not shone).
  bool emitter() const { return emissive() && !unlit; }
  // An emitter's radiance is `emission` at every point and towards every direction: no emissive
  // texture, and no clearcoat darkening it by angle (scene/surface.h: emission_at).
  bool uniform_emission() const { return !emissive_texture && !(clearcoat > 0.f); }
  // (One object returned on every path, so that it is built in place: this runs at every hit.)
  BrdfParams brdf() const {
    BrdfParams p;
    if (unlit) {  // black Lambert
      p.base_color = glm::vec3(0.f), p.metallic = 0.f, p.specular = 0.f;
      p.specular_color = glm::vec3(0.f);
      return p;
    }
    p.base_color = base_color, p.metallic = metallic, p.roughness = roughness, p.ior = ior;
    p.specular = specular, p.specular_color = specular_color, p.transmission = transmission;
    p.clearcoat = clearcoat, p.clearcoat_roughness = clearcoat_roughness;
    p.sheen_color = sheen_color, p.sheen_roughness = sheen_roughness;
    p.anisotropy = anisotropy;  // (the direction in the shading frame: scene/surface.cpp)
    p.iridescence = iridescence, p.iridescence_ior = iridescence_ior;
    p.iridescence_thickness = iridescence_thickness_max;  // (surface_at applies the texture)
    return p;
  }
  // A Lambertian surface: no metal, no specular layer.
  static Material lambert(const glm::vec3& color) {
    Material m;
    m.base_color = color;
    m.metallic = 0.f;
    m.specular = 0.f;
    return m;
  }
};

}  // namespace dacrt
