// The glTF JSON read before tinygltf parses it (see file_json.h).
#include "dacrt/io/gltf/file_json.h"

#include <set>

namespace dacrt::gltf_json {

// Member `key` of `object` as an index below `limit` (any number >= 0 truncated, as the loader
// reads it), or nothing.
std::optional<size_t> index_at(const nlohmann::json& object, const char* key, size_t limit) {
  if (!object.is_object()) return std::nullopt;
  auto it = object.find(key);
  if (it == object.end() || !it->is_number()) return std::nullopt;
  const double d = it->get<double>();
  if (!(d >= 0.0 && d < double(limit))) return std::nullopt;
  return size_t(d);
}

// Whether a URI is a data URI (its bytes in the string), not a file's name.
bool is_data_uri(const nlohmann::json& uri) {
  return uri.is_string() && uri.get_ref<const std::string&>().starts_with("data:");
}

const nlohmann::json& member(const nlohmann::json& j, const char* key) {
  static const nlohmann::json none;
  if (!j.is_object()) return none;
  auto it = j.find(key);
  return it == j.end() ? none : *it;
}

size_t array_size(const nlohmann::json& doc, const char* key) {
  const nlohmann::json& a = member(doc, key);
  return a.is_array() ? a.size() : 0;
}

// The images the render of scene `scene` (-1: the default) can show: those of the textures in
// the material slots the loader samples (Material::sampled_textures) of the materials of the
// triangle primitives (those `variant` maps them to, if it names a KHR_materials_variants
// variant) of the meshes of the nodes under the scene's roots. A superset of what the
// loader decodes (which leaves out primitives a failure skips, and materials whose emission
// rounds to 0 as float).
std::vector<bool> used_images(const nlohmann::json& doc, int scene, const std::string& variant) {
  const size_t nodes = array_size(doc, "nodes"), meshes = array_size(doc, "meshes"),
               materials = array_size(doc, "materials"), textures = array_size(doc, "textures"),
               images = array_size(doc, "images");
  std::vector<bool> mesh_used(meshes), material_used(materials), texture_used(textures),
      image_used(images), node_seen(nodes);
  if (scene == -1) scene = int(index_at(doc, "scene", SIZE_MAX).value_or(0));
  const nlohmann::json& scenes = member(doc, "scenes");
  std::vector<size_t> stack;
  auto push_all = [&](const nlohmann::json& list) {
    if (!list.is_array()) return;
    for (const nlohmann::json& n : list)
      if (n.is_number() && n.get<double>() >= 0.0 && n.get<double>() < double(nodes) &&
          !node_seen[size_t(n.get<double>())])
        node_seen[size_t(n.get<double>())] = true, stack.push_back(size_t(n.get<double>()));
  };
  if (scenes.is_array() && scene >= 0 && size_t(scene) < scenes.size())
    push_all(member(scenes[size_t(scene)], "nodes"));
  while (!stack.empty()) {
    const nlohmann::json& node = doc["nodes"][stack.back()];
    stack.pop_back();
    if (auto m = index_at(node, "mesh", meshes)) mesh_used[*m] = true;
    push_all(member(node, "children"));
  }
  // The KHR_materials_variants variant named `variant`, by index (none: the primitives' own
  // materials).
  std::optional<size_t> chosen;
  const nlohmann::json& variants =
      member(member(member(doc, "extensions"), "KHR_materials_variants"), "variants");
  if (!variant.empty() && variants.is_array())
    for (size_t v = 0; v < variants.size() && !chosen; ++v)
      if (const nlohmann::json& name = member(variants[v], "name");
          name.is_string() && name.get_ref<const std::string&>() == variant)
        chosen = v;
  for (size_t m = 0; m < meshes; ++m) {
    const nlohmann::json& primitives = member(doc["meshes"][m], "primitives");
    if (mesh_used[m] && primitives.is_array())
      for (const nlohmann::json& p : primitives) {
        // Points, lines and primitives without POSITION are skipped.
        const bool drawn = index_at(p, "mode", 7).value_or(4) >= 4 &&
                           member(member(p, "attributes"), "POSITION").is_number();
        std::optional<size_t> material = index_at(p, "material", materials);
        // KHR_materials_variants: the material the chosen variant maps the primitive to, as
        // io/gltf/primitives.cpp's variant_material picks it.
        bool mapped = false;
        const nlohmann::json& mappings =
            member(member(member(p, "extensions"), "KHR_materials_variants"), "mappings");
        if (chosen && mappings.is_array())
          for (const nlohmann::json& mapping : mappings) {
            const nlohmann::json& variants = member(mapping, "variants");
            if (mapped || !variants.is_array()) continue;
            for (const nlohmann::json& v : variants)
              if (v.is_number() && v.get<double>() == double(*chosen)) mapped = true;
            if (mapped) material = index_at(mapping, "material", materials);
          }
        if (drawn && material) material_used[*material] = true;
      }
  }
  for (size_t i = 0; i < materials; ++i) {
    if (!material_used[i]) continue;
    const nlohmann::json& m = doc["materials"][i];
    const nlohmann::json& pbr = member(m, "pbrMetallicRoughness");
    const nlohmann::json& extensions = member(m, "extensions");
    const nlohmann::json& transmission = member(extensions, "KHR_materials_transmission");
    const nlohmann::json& specular = member(extensions, "KHR_materials_specular");
    const nlohmann::json& clearcoat = member(extensions, "KHR_materials_clearcoat");
    const nlohmann::json& sheen = member(extensions, "KHR_materials_sheen");
    const nlohmann::json& anisotropy = member(extensions, "KHR_materials_anisotropy");
    const nlohmann::json& film = member(extensions, "KHR_materials_iridescence");
    // The emissive, transmission, specular, clearcoat, sheen, anisotropy and iridescence textures
    // are sampled only where their factors are not 0 (Material::sampled_textures), an unlit
    // material's base colour only.
    auto positive = [](const nlohmann::json& f, double fallback) {
      if (f.is_array()) {
        bool any = false;
        for (const nlohmann::json& c : f) any |= c.is_number() && c.get<double>() > 0.0;
        return any;
      }
      return f.is_number() ? f.get<double>() > 0.0 : fallback > 0.0;
    };
    const bool lit = !extensions.is_object() || !extensions.contains("KHR_materials_unlit");
    const bool emissive = positive(member(m, "emissiveFactor"), 0.0);
    const bool transmits = positive(member(transmission, "transmissionFactor"), 0.0);
    const bool speculars = positive(member(specular, "specularFactor"), 1.0);
    const bool coated = positive(member(clearcoat, "clearcoatFactor"), 0.0);
    const bool sheens = positive(member(sheen, "sheenColorFactor"), 0.0);
    const bool anisotropic = positive(member(anisotropy, "anisotropyStrength"), 0.0);
    const bool iridescent = positive(member(film, "iridescenceFactor"), 0.0);
    auto when = [&](bool used, const nlohmann::json& o, const char* key) {
      return used && lit ? &member(o, key) : nullptr;
    };
    for (const nlohmann::json* slot :
         {&member(pbr, "baseColorTexture"), when(true, pbr, "metallicRoughnessTexture"),
          when(true, m, "normalTexture"), when(emissive, m, "emissiveTexture"),
          when(transmits, transmission, "transmissionTexture"),
          when(speculars, specular, "specularTexture"),
          when(speculars, specular, "specularColorTexture"),
          when(coated, clearcoat, "clearcoatTexture"),
          when(coated, clearcoat, "clearcoatRoughnessTexture"),
          when(coated, clearcoat, "clearcoatNormalTexture"),
          when(sheens, sheen, "sheenColorTexture"), when(sheens, sheen, "sheenRoughnessTexture"),
          when(anisotropic, anisotropy, "anisotropyTexture"),
          when(iridescent, film, "iridescenceTexture"),
          when(iridescent, film, "iridescenceThicknessTexture")})
      if (auto texture = slot ? index_at(*slot, "index", textures) : std::nullopt)
        texture_used[*texture] = true;
  }
  // A texture's image: its EXT_texture_webp source, else its own source (which is also the
  // fallback of a KHR_texture_basisu image), as io/gltf/images.cpp's load_textures chooses.
  for (size_t t = 0; t < textures; ++t) {
    if (!texture_used[t]) continue;
    const nlohmann::json& texture = doc["textures"][t];
    auto source =
        index_at(member(member(texture, "extensions"), "EXT_texture_webp"), "source", images);
    if (!source) source = index_at(texture, "source", images);
    if (source) image_used[*source] = true;
  }
  return image_used;
}

}  // namespace dacrt::gltf_json
