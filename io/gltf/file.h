// Reading a glTF file into tinygltf's model: .gltf or .glb (told apart by the GLB magic), with
// the checks tinygltf lacks (GLB chunk lengths, JSON nesting depth, the glTF schema's types and
// ranges (io/gltf/schema.h), FIFOs posing as buffers) and images ignored (a no-op loader: this
// version renders no textures). Throws dacrt::Error with one line naming the file.
#pragma once

#include <tiny_gltf.h>

#include <string>
#include <vector>

namespace dacrt {

// `files`, when given, receives the paths of the external files read (buffers, images).
tinygltf::Model read_gltf_model(const std::string& path, std::vector<std::string>* files = nullptr);
// The same from bytes already in memory; `path` names them in messages, and external buffers are
// looked up beside it.
tinygltf::Model parse_gltf_model(const std::string& path, const unsigned char* data, size_t size,
                                 std::vector<std::string>* files = nullptr);

}  // namespace dacrt
