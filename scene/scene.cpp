#include "scene/scene.h"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace dacrt {

Camera frame_bounds(const Box& bounds, float aspect, float yfov) {
  Camera cam;
  cam.name = "framed";
  cam.yfov = yfov;
  cam.aspect = aspect;
  glm::vec3 center = bounds.empty() ? glm::vec3(0.f) : bounds.center();
  float radius = bounds.empty() ? 1.f : 0.5f * glm::length(bounds.extent());
  if (!(radius > 0.f)) radius = 1.f;
  // Fit the bounding sphere in the narrower of the two fields of view.
  float half = 0.5f * yfov;
  if (aspect > 0.f && aspect < 1.f) half = std::atan(std::tan(half) * aspect);
  float distance = radius / std::sin(half);
  glm::vec3 dir = glm::normalize(glm::vec3(0.f, 0.25f, 1.f));
  glm::vec3 eye = center + distance * dir;
  cam.to_world = glm::inverse(glm::lookAt(eye, center, glm::vec3(0.f, 1.f, 0.f)));
  cam.znear = 0.f;
  return cam;
}

}  // namespace dacrt
