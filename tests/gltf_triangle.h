// The one triangle the glTF loader tests start from: its positions, and a file of it ready to be
// broken by a test.
#pragma once

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <vector>

#include "gltf_writer.h"

namespace dacrt::test {

inline const std::vector<glm::vec3> kTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

// Positions of a one-triangle file with `extra` primitive members, ready to be broken by a test.
inline GltfWriter triangle_file(nlohmann::json extra = nlohmann::json::object()) {
  GltfWriter w;
  w.add_triangles(kTriangle, extra);
  return w;
}

}  // namespace dacrt::test
