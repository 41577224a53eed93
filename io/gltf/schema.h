// The glTF 2.0 JSON schema, checked on a file's JSON before tinygltf reads it. tinygltf is lenient:
// a wrongly typed or out-of-range value silently becomes its default (a node's "mesh": 0.5 is no
// mesh, an accessor's "byteOffset": -8 is 0), so the file would render other than it says. Here
// the types, ranges, enums, array lengths, required members and index ranges that the schema and
// the Khronos glTF-Validator state are checked for every property the loader reads and the
// structure around them, with the extensions the loader reads and extensionsUsed/Required (a file
// that requires an extension the loader does not read is refused, as the spec asks).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace dacrt {

struct SchemaCheck {
  // One line each ("<path>: <JSON pointer>: <what>"), for valid content that this version does not
  // read as the file means it.
  std::vector<std::string> warnings;
  // Some integer is written with a decimal point (1.0): valid JSON and glTF, but tinygltf ignores
  // such a value, so the loader rewrites them first (io/gltf/file.cpp).
  bool whole_floats = false;
};
// Throws dacrt::Error "<path>: <JSON pointer>: <what is wrong>" for the first violation.
SchemaCheck check_gltf_schema(const std::string& path, const nlohmann::json& doc);

// Whether the loader (io/gltf/) reads extension `name` (a file may require only those).
bool gltf_extension_supported(std::string_view name);

}  // namespace dacrt
