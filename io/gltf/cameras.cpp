// glTF cameras: perspective and orthographic, placed by their node with its scale and shear
// removed (in double, so that a scale of 1e20 or 1e-25, which float cannot square, still gives
// the rotation).
#include "dacrt/io/gltf/internal.h"

namespace dacrt::gltf {

Camera load_camera(const Gltf& gltf, int index, const glm::dmat4& world, int node) {
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
    // As float, the view's half height and its aspect ratio (0 would mean "unknown") must stay
    // finite and non-zero.
    cam.orthographic = true;
    cam.ymag = float(ymag);
    cam.aspect = float(xmag / ymag);
    if (!(cam.ymag > 0.f) || !std::isfinite(cam.ymag) || !(cam.aspect > 0.f) ||
        !std::isfinite(cam.aspect))
      gltf.fail(what + ": orthographic xmag " + num(xmag) + " and ymag " + num(ymag) +
                " are beyond float's range");
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

  // Remove scale (and shear) with Gram-Schmidt, keeping the viewing axis (-Z) and then +Y, in
  // double and each axis scaled to its largest component first.
  const std::string placed = "node " + str(node) + " gives " + what;
  const std::optional<glm::vec3> z_axis = direction_of(glm::dvec3(world[2]));
  if (!z_axis) gltf.fail(placed + " a zero scale along its viewing axis (Z): it has no direction");
  const glm::dvec3 z(*z_axis);
  const std::optional<glm::vec3> y_axis = direction_of(glm::dvec3(world[1]));
  if (!y_axis) gltf.fail(placed + " a zero scale along its Y axis: it has no up direction");
  const glm::dvec3 y_off = glm::dvec3(*y_axis) - glm::dot(glm::dvec3(*y_axis), z) * z;
  if (!(glm::length(y_off) > 1e-6))
    gltf.fail(placed +
              " a Y axis along its viewing axis (a degenerate shear): it has no up "
              "direction");
  const glm::vec3 y = glm::vec3(glm::normalize(y_off)), zf(z);
  const glm::vec3 position(world[3]);
  if (!finite(position))
    gltf.fail(placed + " a position beyond float's range (" + num(world[3].x) + ", " +
              num(world[3].y) + ", " + num(world[3].z) + ")");
  cam.to_world = glm::mat4(glm::vec4(glm::cross(y, zf), 0.f), glm::vec4(y, 0.f), glm::vec4(zf, 0.f),
                           glm::vec4(position, 1.f));
  return cam;
}

}  // namespace dacrt::gltf
