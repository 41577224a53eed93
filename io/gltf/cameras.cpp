// glTF cameras: perspective and orthographic, placed by their node with its scale and shear
// removed.
#include "io/gltf/internal.h"

namespace dacrt::gltf {

Camera load_camera(const Gltf& gltf, int index, const glm::mat4& world, int node) {
  if (index < 0 || size_t(index) >= gltf.model.cameras.size())
    gltf.fail("node " + str(node) + " refers to camera " + str(index) + ", which does not exist");
  const tinygltf::Camera& src = gltf.model.cameras[size_t(index)];
  std::string what = "camera " + str(index);
  Camera cam;
  cam.name = src.name;
  if (src.type == "orthographic") {
    // xmag and ymag are half the view's width and height; the spec forbids zero.
    const double xmag = std::abs(src.orthographic.xmag), ymag = std::abs(src.orthographic.ymag);
    if (!(xmag > 0.0 && ymag > 0.0) || !std::isfinite(xmag / ymag) || !std::isfinite(ymag))
      gltf.fail(what + ": orthographic xmag and ymag must be finite and non-zero");
    cam.orthographic = true;
    cam.ymag = float(ymag);
    cam.aspect = float(xmag / ymag);
    cam.znear = float(src.orthographic.znear);
  } else if (src.type == "perspective") {
    cam.yfov = float(src.perspective.yfov);
    cam.aspect = float(src.perspective.aspectRatio);
    cam.znear = float(src.perspective.znear);
  } else {
    gltf.fail(what + ": type \"" + src.type + "\" is neither perspective nor orthographic");
  }
  if (!cam.orthographic && !(cam.yfov > 0.f && cam.yfov < 3.14159f))
    gltf.fail(what + ": yfov " + str(cam.yfov) + " is not in (0, pi)");
  if (!(cam.aspect >= 0.f) || !std::isfinite(cam.aspect))
    gltf.fail(what + ": aspectRatio is not a finite number >= 0");
  if (!(cam.znear >= 0.f) || !std::isfinite(cam.znear))
    gltf.fail(what + ": znear is not a finite number >= 0");

  // Remove scale (and shear) with Gram-Schmidt, keeping the viewing axis (-Z) and then +Y.
  glm::vec3 z = unit_or(glm::vec3(world[2]), glm::vec3(0.f));
  glm::vec3 y = unit_or(glm::vec3(world[1]) - glm::dot(glm::vec3(world[1]), z) * z, glm::vec3(0.f));
  if (z == glm::vec3(0.f) || y == glm::vec3(0.f))
    gltf.fail("node " + str(node) + " gives " + what + " a degenerate transform (zero scale)");
  cam.to_world = glm::mat4(glm::vec4(glm::cross(y, z), 0.f), glm::vec4(y, 0.f), glm::vec4(z, 0.f),
                           glm::vec4(glm::vec3(world[3]), 1.f));
  return cam;
}

}  // namespace dacrt::gltf
