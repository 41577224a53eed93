// glTF 2.0 loading (.gltf and .glb) into a Scene. Throws dacrt::Error with a one-line message
// naming the file and the element at fault for anything malformed.
#pragma once

#include <string>

#include "scene/scene.h"

namespace dacrt {

struct GltfOptions {
  int scene = -1;  // which scene of the file; -1 = the file's default scene (or scene 0)
  // KHR_materials_variants: the variant whose materials the primitives take; empty: their own.
  // A name the file does not have is a SettingError naming those it has.
  std::string variant{};
};

Scene load_gltf(const std::string& path, const GltfOptions& options = {});
// The same from a file's bytes in memory (the fuzzer's entry point); `path` names them in
// messages and is where external buffers are looked for.
Scene load_gltf_memory(const std::string& path, const unsigned char* data, size_t size,
                       const GltfOptions& options = {});

}  // namespace dacrt
