// Camera: how the image plane maps to rays. glTF's cameras (perspective or orthographic), the
// camera made when a file has none, and one given on the command line as a LookAt.
#pragma once

#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "dacrt/tracer/geometry.h"

namespace dacrt {

// A camera in glTF's convention: it looks down its local -Z with +Y up. Perspective (a pinhole)
// or orthographic.
struct Camera {
  std::string name;
  glm::mat4 to_world{1.f};  // camera-to-world, rigid (scale removed)
  float yfov = 0.7f;        // perspective: vertical field of view, radians
  float aspect = 0.f;       // width / height; 0 when the file does not say
  float znear = 0.f;
  bool orthographic = false;
  float ymag = 1.f;  // orthographic: half the view's height (its width follows the aspect)
  // The up direction it was aimed with, as LookAt's up (+Y for the camera framing a scene, the
  // --up of an override); unset for a file's camera: its image's up.
  std::optional<glm::vec3> aimed_up;
  // A thin lens (a render's --aperture or --fstop; glTF cameras are pinholes): rays start on a
  // disk of this diameter around the position, across the view axis, and pass through the point
  // the pinhole ray meets at depth focus_distance along the view axis, so the plane at that depth
  // is sharp. 0: a pinhole (focus_distance unused).
  float aperture = 0.f;
  float focus_distance = 1.f;

  glm::vec3 position() const { return glm::vec3(to_world[3]); }
  glm::vec3 up() const { return aimed_up.value_or(glm::vec3(to_world[1])); }
};

// A camera that looks at the whole box from the +Z side (glTF's front), slightly above, with the
// given vertical field of view; used when a file has no camera.
Camera frame_bounds(const Box& bounds, float aspect, float yfov = 0.7f);

// A camera given on the command line as pbrt's LookAt (F3D's --camera-* options are alike): any
// of its parts overrides `base`, the camera it starts from.
struct CameraOverride {
  std::optional<glm::vec3> from, at, up;  // eye, a point it looks at, the up direction
  std::optional<float> fov_degrees;       // vertical field of view (makes it perspective)
  bool any() const { return from || at || up || fov_degrees; }
};

// `base` with the override applied. Unset parts keep base's: its position, its direction (when
// only `from` is new, the camera looks at `target`, the scene's centre), its up (up(): +Y for a
// framed camera, so a new view is not tilted by the framing's downward look), its yfov.
// Throws SettingError (naming the flags) when from and at coincide or up is parallel to the view.
Camera override_camera(const Camera& base, const CameraOverride& o, const glm::vec3& target);

// A point the camera looks at, for printing it as a LookAt: on its viewing axis, as far as
// `target` is from it (1 when that is 0).
glm::vec3 look_at_point(const Camera& camera, const glm::vec3& target);

// The camera as render flags, ready to copy: "--look-from X,Y,Z --look-at X,Y,Z --up X,Y,Z
// --fov DEGREES" (no --fov for an orthographic camera), then "--aperture D --focus-distance F"
// for a thin lens. The look-at point is on the view axis, as
// far as `target` (the scene's centre).
std::string camera_flags(const Camera& camera, const glm::vec3& target);

// The lens as a render asks for it (--aperture or --fstop; --focus-distance or --focus-on), made
// into the camera's aperture and focus_distance by lens_camera.
struct LensRequest {
  std::optional<float> aperture;        // diameter, in scene units (glTF: metres); 0: a pinhole
  std::optional<float> fstop;           // or as an f-number (see lens_camera)
  std::optional<float> focus_distance;  // depth of the plane in focus, along the view axis
  std::optional<glm::vec3> focus_on;    // or a point whose depth is
  bool any() const { return aperture || fstop || focus_distance || focus_on; }
};

// The focal length of a 36 × 24 mm sensor (full frame, its long side along the image's longer
// side) that gives `camera` its vertical field of view for an image of this shape (width /
// height), in metres: (24 or 36 mm) / 2 / tan(yfov / 2).
float full_frame_focal_length(const Camera& camera, float aspect);

// `camera` with the lens `lens` asks for, on an image of this aspect (width / height). The
// aperture: --aperture, or the full-frame focal length over --fstop (a perspective camera only).
// The focus: --focus-distance, the depth of --focus-on, else `default_focus` (the caller's
// choice). Throws SettingError naming the flag for --fstop on an orthographic camera, a
// focus point not in front of the camera, or an aperture that is not finite. `notes` gets one
// line for what is not used (a focus without an aperture).
Camera lens_camera(const Camera& camera, const LensRequest& lens, float aspect,
                   float default_focus, std::vector<std::string>& notes);

// A point on the unit disk from two uniforms, area-preserving (Shirley and Chiu 1997, "A
// low distortion map between disk and square"): the lens sample.
glm::vec2 sample_disk(float u1, float u2);

// The largest image side, whether given (--width, --height) or derived from a camera's aspect.
inline constexpr int max_image_side = 1 << 15;

// The image size for a camera of this aspect ratio (width / height; <= 0: none) and the sides
// given (0: not given). Both given are kept; one given keeps the camera's aspect (or makes a
// square); none gives `longer` pixels on the longer side. Throws Error("<camera>'s aspectRatio
// 1e-07 with --width 8 gives a height of 79999999 pixels, more than 32768 …") when the derived side
// is over max_image_side.
glm::ivec2 image_size(float aspect, int width, int height, int longer, const std::string& camera);

// The camera ray through image point (x, y) (pixels, from the top-left corner) of a width ×
// height image, unit direction. Returns where along it the camera's near plane (znear) lies: the
// ray's tmin, so nothing nearer than znear is seen.
float camera_ray(const Camera& camera, int width, int height, float x, float y, glm::vec3& origin,
                 glm::vec3& direction);

// The thin-lens camera ray through image point (x, y) from the lens point that the numbers
// (lens_u, lens_v) in [0, 1)² pick (sample_disk). A pinhole camera's is camera_ray's.
float camera_ray(const Camera& camera, int width, int height, float x, float y, float lens_u,
                 float lens_v, glm::vec3& origin, glm::vec3& direction);

// What camera_ray takes of a camera and an image size, made once for a batch of rays (the field
// of view's tangent is worth hoisting: a call per camera sample was 4 % of a textured render). The
// rays are the same bit for bit.
struct CameraProjection {
  glm::mat4 to_world;
  float width, height, aspect, tan_half, ymag, znear;
  bool orthographic;
  float lens_radius, focus_distance;  // 0: a pinhole

  CameraProjection(const Camera& camera, int width, int height);
  float ray(float x, float y, glm::vec3& origin, glm::vec3& direction) const {
    if (orthographic) {
      const glm::vec3 local((2.f * x / width - 1.f) * ymag * aspect,
                            (1.f - 2.f * y / height) * ymag, 0.f);
      origin = glm::vec3(to_world * glm::vec4(local, 1.f));
      direction = -glm::vec3(to_world[2]);
      return znear;
    }
    glm::vec3 local((2.f * x / width - 1.f) * tan_half * aspect, (1.f - 2.f * y / height) * tan_half,
                    -1.f);
    origin = glm::vec3(to_world[3]);
    direction = glm::normalize(glm::vec3(to_world * glm::vec4(local, 0.f)));
    // The near plane is at depth znear: `local` (depth 1) scaled by znear, |local| · znear away.
    return znear * glm::length(local);
  }
  // The perspective pinhole rays (not orthographic, no lens) through the image points (x[k],
  // y[k]) for k < n, n a multiple of 4: each unit direction (dx, dy, dz) and tmin, four rays at a
  // time with ray()'s operations in ray()'s order (the same bits); the origin is to_world[3].
  void pinhole_rays(const float* x, const float* y, size_t n, float* dx, float* dy, float* dz,
                    float* tmin) const;
  bool pinhole() const { return !orthographic && !thin_lens(); }
  // Whether rays need a lens sample (the four-number ray).
  bool thin_lens() const { return lens_radius > 0.f; }
  // The ray from the lens point (lens_u, lens_v) picks (after pbrt-v4's PerspectiveCamera): it
  // passes through the point the pinhole ray (or, orthographic, the parallel ray) meets on the
  // plane in focus, at depth focus_distance. With no lens (lens_radius 0) the pinhole ray.
  float ray(float x, float y, float lens_u, float lens_v, glm::vec3& origin,
            glm::vec3& direction) const;
};

}  // namespace dacrt
