// The glTF JSON read before tinygltf parses it (io/gltf/file.cpp): members looked up without
// throwing, indices checked against their arrays, and the images a render can show, so that
// only those are read.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace dacrt::gltf_json {

// Member `key` of `object` as an index below `limit` (any number >= 0 truncated, as the loader
// reads it), or nothing.
std::optional<size_t> index_at(const nlohmann::json& object, const char* key, size_t limit);

// Whether a URI is a data URI (its bytes in the string), not a file's name.
bool is_data_uri(const nlohmann::json& uri);

// Member `key` of `j`, or null when `j` is not an object or has no such member.
const nlohmann::json& member(const nlohmann::json& j, const char* key);

// The length of array member `key` of `doc` (0 when it is missing or not an array).
size_t array_size(const nlohmann::json& doc, const char* key);

// The images the render of scene `scene` (-1: the default) can show: those of the textures in
// the material slots the loader samples (Material::sampled_textures) of the materials of the
// triangle primitives (those `variant` maps them to, if it names a KHR_materials_variants
// variant) of the meshes of the nodes under the scene's roots. A superset of what the
// loader decodes (which leaves out primitives a failure skips, and materials whose emission
// rounds to 0 as float).
std::vector<bool> used_images(const nlohmann::json& doc, int scene, const std::string& variant);

}  // namespace dacrt::gltf_json
