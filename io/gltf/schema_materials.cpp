// The glTF schema check of images, samplers, textures and materials (with the material
// extensions the loader reads); the Checker is in io/gltf/schema_checker.h.
#include <string>

#include "dacrt/io/gltf/schema_checker.h"

namespace dacrt::gltf::schema {

void Checker::image(const json& i, const Pointer& at) {
  const json* uri = has(i, at, "uri");
  const json* view = has(i, at, "bufferView");
  if (uri) this->uri(*uri, at / "uri");
  if (view) index(*view, at / "bufferView", "bufferViews");
  if (uri && view) fail(at, "has both a uri and a bufferView (it must have one)");
  if (!uri && !view) fail(at, "has neither a uri nor a bufferView (it must have one)");
  const json* mime = has(i, at, "mimeType");
  if (view && !mime) fail(at / "mimeType", "is missing (it is required with a bufferView)");
  if (mime) {
    string(*mime, at / "mimeType");
    // KTX2 images are never decoded: the loader says so for each texture that has one.
    if (*mime != "image/png" && *mime != "image/jpeg" && *mime != "image/webp" &&
        *mime != "image/ktx2")
      warn(at / "mimeType", describe(*mime) +
                                " is not image/png, image/jpeg or image/webp, the types this "
                                "version decodes");
  }
}

void Checker::sampler(const json& s, const Pointer& at) {
  if (const json* v = has(s, at, "magFilter")) enum_int(*v, at / "magFilter", {9728, 9729});
  if (const json* v = has(s, at, "minFilter"))
    enum_int(*v, at / "minFilter", {9728, 9729, 9984, 9985, 9986, 9987});
  for (const char* key : {"wrapS", "wrapT"})
    if (const json* v = has(s, at, key)) enum_int(*v, at / key, {33071, 33648, 10497});
}

void Checker::texture(const json& t, const Pointer& at) {
  index_member(t, at, "sampler", "samplers");
  index_member(t, at, "source", "images");
  // Another image for the texture (the validator allows an empty object, with no source).
  for (const char* name : {"EXT_texture_webp", "KHR_texture_basisu"})
    if (const json* x = extension(t, at, name))
      index_member(*x, at / "extensions" / name, "source", "images");
}

void Checker::material(const json& m, const Pointer& at) {
  if (const json* pbr = has(m, at, "pbrMetallicRoughness")) {
    const Pointer p = at / "pbrMetallicRoughness";
    property(*pbr, p);
    numbers_member(*pbr, p, "baseColorFactor", 4, kUnit);
    number_member(*pbr, p, "metallicFactor", kUnit);
    number_member(*pbr, p, "roughnessFactor", kUnit);
    texture_info(*pbr, p, "baseColorTexture");
    texture_info(*pbr, p, "metallicRoughnessTexture");
  }
  if (const json* t = texture_info(m, at, "normalTexture"))
    number_member(*t, at / "normalTexture", "scale", kAnyNumber);
  if (const json* t = texture_info(m, at, "occlusionTexture"))
    number_member(*t, at / "occlusionTexture", "strength", kUnit);
  texture_info(m, at, "emissiveTexture");
  numbers_member(m, at, "emissiveFactor", 3, kUnit);
  if (const json* v = has(m, at, "alphaMode"))
    enum_string(*v, at / "alphaMode", {"OPAQUE", "MASK", "BLEND"});
  number_member(m, at, "alphaCutoff", kNonNegative);
  if (const json* v = has(m, at, "doubleSided")) boolean(*v, at / "doubleSided");

  auto ext = [&](const char* name, auto&& check) {
    if (const json* x = extension(m, at, name)) check(*x, at / "extensions" / name);
  };
  ext("KHR_materials_clearcoat", [&](const json& x, const Pointer& p) {
    number_member(x, p, "clearcoatFactor", kUnit);
    texture_info(x, p, "clearcoatTexture");
    number_member(x, p, "clearcoatRoughnessFactor", kUnit);
    texture_info(x, p, "clearcoatRoughnessTexture");
    if (const json* t = texture_info(x, p, "clearcoatNormalTexture"))
      number_member(*t, p / "clearcoatNormalTexture", "scale", kAnyNumber);
  });
  ext("KHR_materials_sheen", [&](const json& x, const Pointer& p) {
    numbers_member(x, p, "sheenColorFactor", 3, kUnit);
    texture_info(x, p, "sheenColorTexture");
    number_member(x, p, "sheenRoughnessFactor", kUnit);
    texture_info(x, p, "sheenRoughnessTexture");
  });
  ext("KHR_materials_anisotropy", [&](const json& x, const Pointer& p) {
    number_member(x, p, "anisotropyStrength", kUnit);
    number_member(x, p, "anisotropyRotation", kAnyNumber);
    texture_info(x, p, "anisotropyTexture");
  });
  ext("KHR_materials_iridescence", [&](const json& x, const Pointer& p) {
    number_member(x, p, "iridescenceFactor", kUnit);
    texture_info(x, p, "iridescenceTexture");
    if (const json* v = has(x, p, "iridescenceIor"))
      if (const double ior = number(*v, p / "iridescenceIor", kAnyNumber); !(ior >= 1.0))
        fail(p / "iridescenceIor", describe(*v) + " is not a number >= 1");
    number_member(x, p, "iridescenceThicknessMinimum", kNonNegative);
    number_member(x, p, "iridescenceThicknessMaximum", kNonNegative);
    texture_info(x, p, "iridescenceThicknessTexture");
  });
  ext("KHR_materials_unlit", [&](const json&, const Pointer&) {});  // an object, no members
  ext("KHR_materials_emissive_strength", [&](const json& x, const Pointer& p) {
    number_member(x, p, "emissiveStrength", kNonNegative);
  });
  ext("KHR_materials_ior", [&](const json& x, const Pointer& p) {
    if (const json* v = has(x, p, "ior"))
      if (const double ior = number(*v, p / "ior", kAnyNumber); !(ior >= 1.0 || ior == 0.0))
        fail(p / "ior", describe(*v) + " is not a number >= 1 or 0");
  });
  ext("KHR_materials_specular", [&](const json& x, const Pointer& p) {
    number_member(x, p, "specularFactor", kUnit);
    texture_info(x, p, "specularTexture");
    numbers_member(x, p, "specularColorFactor", 3, kNonNegative);
    texture_info(x, p, "specularColorTexture");
  });
  ext("KHR_materials_transmission", [&](const json& x, const Pointer& p) {
    number_member(x, p, "transmissionFactor", kUnit);
    texture_info(x, p, "transmissionTexture");
  });
  ext("KHR_materials_volume", [&](const json& x, const Pointer& p) {
    number_member(x, p, "thicknessFactor", kNonNegative);
    texture_info(x, p, "thicknessTexture");
    number_member(x, p, "attenuationDistance", kPositive);
    numbers_member(x, p, "attenuationColor", 3, kUnit);
  });
  ext("KHR_materials_dispersion",
      [&](const json& x, const Pointer& p) { number_member(x, p, "dispersion", kNonNegative); });
}

}  // namespace dacrt::gltf::schema
