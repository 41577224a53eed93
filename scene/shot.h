// Shot: what one render of a scene sees besides its geometry and materials: the camera as the
// user placed it, the image size, the lights (the file's and the user's), and what rays that leave
// the scene see. A Scene never changes after loading; a render's choices of camera, size and
// lighting are resolved once into a Shot (render/render_job.h, make_shot), which the
// integrators read.
#pragma once

#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include "dacrt/scene/camera.h"
#include "dacrt/scene/environment.h"
#include "dacrt/scene/scene.h"

namespace dacrt {

struct Shot {
  Camera camera;
  int camera_index = 0;  // the scene's camera it started from
  int width = 0, height = 0;
  std::vector<PunctualLight> lights;  // the scene's, then those the settings add
  // What rays that leave the scene see: a uniform radiance, or an equirectangular map (which
  // next-event estimation samples) instead when environment_map is set.
  glm::vec3 environment{0.f};
  std::shared_ptr<const EnvironmentMap> environment_map;
  // What the user should be told about the choices made (a scene without emitters lit by a
  // uniform environment, a camera made to frame the scene), one line each, naming the scene.
  std::vector<std::string> notes;

  uint64_t pixels() const { return uint64_t(width) * uint64_t(height); }
};

}  // namespace dacrt
