// glTF materials: the metallic-roughness factors and textures, alpha modes, and the material
// extensions read here (KHR_materials_anisotropy, _clearcoat, _dispersion, _emissive_strength,
// _ior, _iridescence, _sheen, _specular, _transmission, _unlit, _volume) with KHR_texture_transform
// on every textureInfo. The ranges were checked by the schema (io/gltf/schema.cpp); factors are
// clamped here again for files loaded without it.
#include <algorithm>
#include <cmath>

#include "dacrt/io/gltf/internal.h"

namespace dacrt::gltf {
namespace {

// True if the material has extension `extension` with member `member`.
bool has_member(const tinygltf::Material& m, const char* extension, const char* member) {
  auto e = m.extensions.find(extension);
  return e != m.extensions.end() && e->second.IsObject() && e->second.Has(member);
}

// A textureInfo inside an extension (tinygltf leaves those as JSON values).
tinygltf::TextureInfo extension_texture(const Gltf& gltf, const tinygltf::Value& v,
                                        const std::string& what) {
  tinygltf::TextureInfo info;
  auto integer = [&](const char* name, int fallback) {
    if (!v.Has(name)) return fallback;
    const tinygltf::Value& n = v.Get(name);
    if (!n.IsNumber() || !(n.GetNumberAsDouble() >= 0.0 && n.GetNumberAsDouble() < 1e9))
      gltf.fail(what + ": " + name + " is not an index");
    return int(n.GetNumberAsDouble());
  };
  if (!v.IsObject() || !v.Has("index")) gltf.fail(what + " has no texture index");
  info.index = integer("index", -1);
  info.texCoord = integer("texCoord", 0);
  if (v.Has("extensions") && v.Get("extensions").IsObject())
    for (const std::string& key : v.Get("extensions").Keys())
      info.extensions[key] = v.Get("extensions").Get(key);
  return info;
}

// A textureInfo (with KHR_texture_transform); marks the texture used and its TEXCOORD set needed.
template <class Info>
TextureRef texture_ref(const Gltf& gltf, const Info& info, const std::string& what) {
  TextureRef ref;
  if (info.index == -1) return ref;
  if (info.index < 0 || size_t(info.index) >= gltf.model.textures.size())
    gltf.fail(what + " refers to texture " + str(info.index) + ", which does not exist (" +
              str(gltf.model.textures.size()) + " textures)");
  const tinygltf::Texture& texture = gltf.model.textures[size_t(info.index)];
  if (texture.source == -1 && extension_source(texture, "EXT_texture_webp") == -1 &&
      extension_source(texture, "KHR_texture_basisu") == -1) {
    gltf.sourceless_textures.insert(info.index);  // the spec leaves it undefined: not sampled
    return ref;
  }
  ref.texture = info.index;
  int set = info.texCoord;
  if (auto ext = info.extensions.find("KHR_texture_transform"); ext != info.extensions.end()) {
    const std::string where = what + " KHR_texture_transform";
    const tinygltf::Value& t = ext->second;
    if (!t.IsObject()) gltf.fail(where + " is not an object");
    auto pair = [&](const char* name, glm::vec2 fallback) {
      if (!t.Has(name)) return fallback;
      const tinygltf::Value& a = t.Get(name);
      if (!a.IsArray() || a.ArrayLen() != 2 || !a.Get(0).IsNumber() || !a.Get(1).IsNumber())
        gltf.fail(where + ": " + name + " is not 2 numbers");
      glm::vec2 out(a.Get(0).GetNumberAsDouble(), a.Get(1).GetNumberAsDouble());
      if (!std::isfinite(out.x) || !std::isfinite(out.y))
        gltf.fail(where + ": " + name + " is not finite");
      return out;
    };
    const glm::vec2 offset = pair("offset", glm::vec2(0.f)), scale = pair("scale", glm::vec2(1.f));
    float rotation = 0.f;
    if (t.Has("rotation")) {
      // A rotation beyond float's range would make the transform NaN.
      if (!t.Get("rotation").IsNumber() || !as_float(t.Get("rotation").GetNumberAsDouble()))
        gltf.fail(where + ": rotation is not a finite number (as float)");
      rotation = float(t.Get("rotation").GetNumberAsDouble());
    }
    if (t.Has("texCoord")) {
      if (!t.Get("texCoord").IsNumber()) gltf.fail(where + ": texCoord is not a number");
      set = int(std::clamp(t.Get("texCoord").GetNumberAsDouble(), -1.0, 1e6));
    }
    // offset · rotation · scale: u' = cos·sx·u + sin·sy·v + ox, v' = −sin·sx·u + cos·sy·v + oy
    // (the rotation turns the image clockwise on screen, as the Khronos TextureTransformTest
    // model's markers check).
    const float c = std::cos(rotation), s = std::sin(rotation);
    ref.transform = glm::mat3x2(glm::vec2(c * scale.x, -s * scale.x),
                                glm::vec2(s * scale.y, c * scale.y), offset);
  }
  if (set < 0) gltf.fail(what + ": texCoord " + str(set) + " is negative");
  ref.texcoord = gltf.texcoord_slot(uint32_t(set));
  return ref;
}

// A number member of an extension object, or `fallback` when it is absent.
double member_number(const Gltf& gltf, const tinygltf::Material& src, const std::string& what,
                        const char* extension, const char* member, double fallback) {
  if (!has_member(src, extension, member)) return fallback;
  const tinygltf::Value& value = src.extensions.at(extension).Get(member);
  if (!value.IsNumber() || !std::isfinite(value.GetNumberAsDouble()))
    gltf.fail(what + ": " + extension + "." + member + " is not a finite number");
  return value.GetNumberAsDouble();
}

// KHR_materials_volume and KHR_materials_dispersion (integrators/media.h renders them). The
// thicknessTexture is checked but not sampled: thickness is a hint for rasterisers, and only
// thicknessFactor > 0 (a volume) or 0 (thin-walled) matters to a path tracer.
void read_volume(const Gltf& gltf, const tinygltf::Material& src, const std::string& what,
                 Material& m) {
  const char* volume = "KHR_materials_volume";
  const std::string where = what + ": " + volume;
  const double thickness = member_number(gltf, src, what, volume, "thicknessFactor", 0.0);
  if (!(thickness >= 0.0)) gltf.fail(where + ".thicknessFactor is not a number >= 0");
  m.thickness = float(std::min(thickness, 1e30));
  if (has_member(src, volume, "thicknessTexture"))
    texture_ref(gltf,
                extension_texture(gltf, src.extensions.at(volume).Get("thicknessTexture"),
                                  where + ".thicknessTexture"),
                where + ".thicknessTexture");
  const double distance =
      member_number(gltf, src, what, volume, "attenuationDistance", INFINITY);
  // (A finite number here: extension_number refuses infinities, so absent is the only +∞.)
  if (!(distance > 0.0)) gltf.fail(where + ".attenuationDistance is not a number > 0");
  m.attenuation_distance = distance > 3e38 ? INFINITY : std::max(float(distance), 1e-30f);
  if (has_member(src, volume, "attenuationColor")) {
    const tinygltf::Value& c = src.extensions.at(volume).Get("attenuationColor");
    if (!c.IsArray() || c.ArrayLen() != 3)
      gltf.fail(where + ".attenuationColor is not 3 numbers");
    for (int k = 0; k < 3; ++k) {
      const double v = c.Get(k).IsNumber() ? c.Get(k).GetNumberAsDouble() : -1.0;
      if (!(v >= 0.0 && v <= 1.0)) gltf.fail(where + ".attenuationColor is not 3 numbers in [0, 1]");
      m.attenuation_color[k] = float(v);
    }
  }
  const double dispersion =
      member_number(gltf, src, what, "KHR_materials_dispersion", "dispersion", 0.0);
  if (!(dispersion >= 0.0))
    gltf.fail(what + ": KHR_materials_dispersion.dispersion is not a number >= 0");
  m.dispersion = float(std::min(dispersion, 1e6));
}

// KHR_materials_anisotropy: the strength and the rotation (as cos, sin), refused outside the
// spec's ranges rather than clamped.
void read_anisotropy(const Gltf& gltf, const tinygltf::Material& src, const std::string& what,
                     Material& m) {
  const char* anisotropy = "KHR_materials_anisotropy";
  const std::string where = what + ": " + anisotropy;
  const double strength = member_number(gltf, src, what, anisotropy, "anisotropyStrength", 0.0);
  if (!(strength >= 0.0 && strength <= 1.0))
    gltf.fail(where + ".anisotropyStrength is not a number in [0, 1]");
  m.anisotropy = float(strength);
  const double rotation = member_number(gltf, src, what, anisotropy, "anisotropyRotation", 0.0);
  if (!as_float(rotation))
    gltf.fail(where + ".anisotropyRotation is not a finite number (as float)");
  m.anisotropy_rotation = {float(std::cos(rotation)), float(std::sin(rotation))};
}

// KHR_materials_iridescence: the film's strength, IOR and thickness range (materials/iridescence.h
// renders it).
void read_iridescence(const Gltf& gltf, const tinygltf::Material& src, const std::string& what,
                      Material& m) {
  const char* film = "KHR_materials_iridescence";
  const std::string where = what + ": " + film;
  auto number = [&](const char* member, double fallback) {
    return member_number(gltf, src, what, film, member, fallback);
  };
  const double factor = number("iridescenceFactor", 0.0);
  if (!(factor >= 0.0 && factor <= 1.0))
    gltf.fail(where + ".iridescenceFactor is not a number in [0, 1]");
  m.iridescence = float(factor);
  const double ior = number("iridescenceIor", 1.3);
  if (!(ior >= 1.0)) gltf.fail(where + ".iridescenceIor is not a number >= 1");
  m.iridescence_ior = float(std::min(ior, 1e6));
  // (Beyond 10⁵ nm, 100 µm, a film is as good as infinitely thick: its colours average out.)
  const double thinnest = number("iridescenceThicknessMinimum", 100.0);
  const double thickest = number("iridescenceThicknessMaximum", 400.0);
  if (!(thinnest >= 0.0)) gltf.fail(where + ".iridescenceThicknessMinimum is not a number >= 0");
  if (!(thickest >= 0.0)) gltf.fail(where + ".iridescenceThicknessMaximum is not a number >= 0");
  m.iridescence_thickness_min = float(std::min(thinnest, 1e5));
  m.iridescence_thickness_max = float(std::min(thickest, 1e5));
}

// One material of the file (`what`, "material 3", starts its messages) with the reads its
// extensions share.
struct MaterialSource {
  const Gltf& gltf;
  const tinygltf::Material& src;
  const std::string& what;

  // A number member of an extension object, or `fallback` when it is absent.
  double number(const char* extension, const char* member, double fallback) const {
    return member_number(gltf, src, what, extension, member, fallback);
  }
  // Factors the spec bounds to [0, 1] are clamped; what is not a number is an error.
  float unit(double value, const char* name) const {
    if (!std::isfinite(value)) gltf.fail(what + ": " + name + " is not a finite number");
    return std::clamp(float(value), 0.f, 1.f);
  }
  // A textureInfo member of an extension object (none when absent).
  TextureRef texture(const char* extension, const char* member) const {
    if (!has_member(src, extension, member)) return TextureRef{};
    const std::string where = what + " " + extension + "." + member;
    return texture_ref(
        gltf, extension_texture(gltf, src.extensions.at(extension).Get(member), where), where);
  }
  // Three numbers in [0, 1] of an extension object, or `fallback`.
  glm::vec3 color(const char* extension, const char* member, glm::vec3 fallback) const {
    if (!has_member(src, extension, member)) return fallback;
    const tinygltf::Value& c = src.extensions.at(extension).Get(member);
    const std::string where = what + ": " + extension + "." + member;
    if (!c.IsArray() || c.ArrayLen() != 3) gltf.fail(where + " is not 3 numbers");
    glm::vec3 out;
    for (int k = 0; k < 3; ++k) {
      if (!c.Get(k).IsNumber() || !std::isfinite(c.Get(k).GetNumberAsDouble()))
        gltf.fail(where + " is not 3 finite numbers");
      out[k] = std::clamp(float(c.Get(k).GetNumberAsDouble()), 0.f, 1.f);
    }
    return out;
  }
};

// The core factors: alpha mode and cutoff, base colour, emission (with
// KHR_materials_emissive_strength), metallic and roughness.
void read_factors(const MaterialSource& in, Material& m) {
  const auto& [gltf, src, what] = in;
  if (src.alphaMode == "MASK")
    m.alpha_mode = Material::AlphaMode::mask;
  else if (src.alphaMode == "BLEND")
    m.alpha_mode = Material::AlphaMode::blend;
  else if (src.alphaMode != "OPAQUE" && !src.alphaMode.empty())
    gltf.fail(what + ": alphaMode \"" + src.alphaMode + "\" is not OPAQUE, MASK or BLEND");
  if (!(src.alphaCutoff >= 0.0) || !std::isfinite(src.alphaCutoff))
    gltf.fail(what + ": alphaCutoff is not a finite number >= 0");
  m.alpha_cutoff = float(src.alphaCutoff);
  const auto& base = src.pbrMetallicRoughness.baseColorFactor;
  const auto& emissive = src.emissiveFactor;
  if (base.size() != 4)
    gltf.fail(what + ": baseColorFactor has " + str(base.size()) + " numbers, not 4");
  if (emissive.size() != 3)
    gltf.fail(what + ": emissiveFactor has " + str(emissive.size()) + " numbers, not 3");
  // The spec bounds the factors to [0, 1]; clamping keeps the albedo energy-conserving.
  m.base_color = glm::clamp(glm::vec3(base[0], base[1], base[2]), 0.f, 1.f);
  if (!std::isfinite(base[3])) gltf.fail(what + ": baseColorFactor is not finite");
  m.alpha = std::clamp(float(base[3]), 0.f, 1.f);
  glm::vec3 emission = glm::clamp(glm::vec3(emissive[0], emissive[1], emissive[2]), 0.f, 1.f);
  const double strength = in.number("KHR_materials_emissive_strength", "emissiveStrength", 1.0);
  if (!(strength >= 0.0) || !std::isfinite(float(strength)))
    gltf.fail(what +
              ": KHR_materials_emissive_strength.emissiveStrength is not a finite number >= 0");
  m.emission = emission * float(strength);
  if (!finite(m.base_color) || !finite(m.emission))
    gltf.fail(what + ": a colour factor is not finite");
  m.metallic = in.unit(src.pbrMetallicRoughness.metallicFactor, "metallicFactor");
  m.roughness = in.unit(src.pbrMetallicRoughness.roughnessFactor, "roughnessFactor");
}

// KHR_materials_ior, and KHR_materials_specular's and KHR_materials_transmission's factors and
// textures (the specular colour factor: read_specular_color).
void read_ior_specular_transmission(const MaterialSource& in, Material& m) {
  const auto& [gltf, src, what] = in;
  // KHR_materials_ior: 1 or more, or exactly 0 (Fresnel 1, for converted spec-gloss files).
  const double ior = in.number("KHR_materials_ior", "ior", 1.5);
  if (!(ior >= 1.0 || ior == 0.0))
    gltf.fail(what + ": KHR_materials_ior.ior is " + std::to_string(ior) + ", not 0 or >= 1");
  m.ior = float(std::min(ior, 1e6));  // beyond, F0 is 1 to float precision
  m.specular = in.unit(in.number("KHR_materials_specular", "specularFactor", 1.0),
                       "KHR_materials_specular.specularFactor");
  m.transmission = in.unit(in.number("KHR_materials_transmission", "transmissionFactor", 0.0),
                           "KHR_materials_transmission.transmissionFactor");
  m.transmission_texture = in.texture("KHR_materials_transmission", "transmissionTexture");
  m.specular_texture = in.texture("KHR_materials_specular", "specularTexture");
  m.specular_color_texture = in.texture("KHR_materials_specular", "specularColorTexture");
}

// KHR_materials_clearcoat
void read_clearcoat(const MaterialSource& in, Material& m) {
  const auto& [gltf, src, what] = in;
  m.clearcoat = in.unit(in.number("KHR_materials_clearcoat", "clearcoatFactor", 0.0),
                        "KHR_materials_clearcoat.clearcoatFactor");
  m.clearcoat_roughness =
      in.unit(in.number("KHR_materials_clearcoat", "clearcoatRoughnessFactor", 0.0),
              "KHR_materials_clearcoat.clearcoatRoughnessFactor");
  m.clearcoat_texture = in.texture("KHR_materials_clearcoat", "clearcoatTexture");
  m.clearcoat_roughness_texture =
      in.texture("KHR_materials_clearcoat", "clearcoatRoughnessTexture");
  m.clearcoat_normal_texture = in.texture("KHR_materials_clearcoat", "clearcoatNormalTexture");
  if (m.clearcoat_normal_texture) {
    const tinygltf::Value& t =
        src.extensions.at("KHR_materials_clearcoat").Get("clearcoatNormalTexture");
    if (t.Has("scale")) {
      const tinygltf::Value& s = t.Get("scale");
      if (!s.IsNumber() || !as_float(s.GetNumberAsDouble()))
        gltf.fail(what +
                  ": KHR_materials_clearcoat.clearcoatNormalTexture.scale is not a "
                  "number in float's range");
      m.clearcoat_normal_scale = float(s.GetNumberAsDouble());
    }
  }
}

// KHR_materials_sheen
void read_sheen(const MaterialSource& in, Material& m) {
  m.sheen_color = in.color("KHR_materials_sheen", "sheenColorFactor", glm::vec3(0.f));
  m.sheen_roughness = in.unit(in.number("KHR_materials_sheen", "sheenRoughnessFactor", 0.0),
                              "KHR_materials_sheen.sheenRoughnessFactor");
  m.sheen_color_texture = in.texture("KHR_materials_sheen", "sheenColorTexture");
  m.sheen_roughness_texture = in.texture("KHR_materials_sheen", "sheenRoughnessTexture");
}

// KHR_materials_specular's specularColorFactor.
void read_specular_color(const MaterialSource& in, Material& m) {
  const auto& [gltf, src, what] = in;
  if (has_member(src, "KHR_materials_specular", "specularColorFactor")) {
    const tinygltf::Value& c =
        src.extensions.at("KHR_materials_specular").Get("specularColorFactor");
    if (!c.IsArray() || c.ArrayLen() != 3)
      gltf.fail(what + ": KHR_materials_specular.specularColorFactor is not 3 numbers");
    for (int k = 0; k < 3; ++k) {
      // Infinite as float, the specular layer would make every sample of the surface NaN.
      if (!c.Get(k).IsNumber() || !as_float(c.Get(k).GetNumberAsDouble()) ||
          c.Get(k).GetNumberAsDouble() < 0.0)
        gltf.fail(what +
                  ": KHR_materials_specular.specularColorFactor is not 3 numbers in [0, 3.4e38] "
                  "(float)");
      m.specular_color[k] = float(c.Get(k).GetNumberAsDouble());
    }
  }
}

}  // namespace

Material default_material() {
  Material m;
  m.name = "default";
  return m;
}

std::vector<Material> load_materials(const Gltf& gltf) {
  std::vector<Material> materials;
  for (size_t i = 0; i < gltf.model.materials.size(); ++i) {
    const tinygltf::Material& src = gltf.model.materials[i];
    std::string what = "material " + str(i);
    const MaterialSource in{gltf, src, what};
    Material m;
    m.name = src.name;
    m.double_sided = src.doubleSided;
    read_factors(in, m);
    read_ior_specular_transmission(in, m);
    read_clearcoat(in, m);
    read_sheen(in, m);
    read_volume(gltf, src, what, m);
    read_anisotropy(gltf, src, what, m);
    m.anisotropy_texture = in.texture("KHR_materials_anisotropy", "anisotropyTexture");
    read_iridescence(gltf, src, what, m);
    m.iridescence_texture = in.texture("KHR_materials_iridescence", "iridescenceTexture");
    m.iridescence_thickness_texture =
        in.texture("KHR_materials_iridescence", "iridescenceThicknessTexture");
    read_specular_color(in, m);
    const auto& pbr = src.pbrMetallicRoughness;
    m.base_color_texture = texture_ref(gltf, pbr.baseColorTexture, what + " baseColorTexture");
    m.metallic_roughness_texture =
        texture_ref(gltf, pbr.metallicRoughnessTexture, what + " metallicRoughnessTexture");
    m.emissive_texture = texture_ref(gltf, src.emissiveTexture, what + " emissiveTexture");
    m.normal_texture = texture_ref(gltf, src.normalTexture, what + " normalTexture");
    if (!as_float(src.normalTexture.scale))
      gltf.fail(what + ": normalTexture.scale " + num(src.normalTexture.scale) +
                " is beyond float's range");
    m.normal_scale = float(src.normalTexture.scale);
    // KHR_materials_unlit: the base colour, emitted; no reflection (see Material::unlit).
    if (src.extensions.count("KHR_materials_unlit")) {
      m.unlit = true;
      m.emission = m.base_color;
      m.emissive_texture = m.base_color_texture;
    }
    materials.push_back(m);
  }
  return materials;
}

}  // namespace dacrt::gltf
