#include "dacrt/scene/camera.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <string>

#include "dacrt/util/error.h"

namespace dacrt {

Camera frame_bounds(const Box& bounds, float aspect, float yfov) {
  Camera cam;
  cam.name = "framed";
  cam.yfov = yfov;
  cam.aspect = aspect;
  // In double: in float the extent's length (a sum of squares) overflows for scenes beyond ~1e19
  // and underflows below ~1e-19, and so does lookAt's normalisation (glTF node scales of 1e30 and
  // 1e-30, tests/stress_test.cpp).
  const glm::dvec3 lo(bounds.lo), hi(bounds.hi);
  const glm::dvec3 center = bounds.empty() ? glm::dvec3(0.0) : 0.5 * lo + 0.5 * hi;
  double radius = bounds.empty() ? 1.0 : 0.5 * glm::length(hi - lo);
  if (!(radius > 0.0) || !std::isfinite(radius)) radius = 1.0;
  // Fit the bounding sphere in the narrower of the two fields of view.
  double half = 0.5 * yfov;
  if (aspect > 0.f && aspect < 1.f) half = std::atan(std::tan(half) * aspect);
  const double distance = radius / std::sin(half);
  const glm::dvec3 dir = glm::normalize(glm::dvec3(0.0, 0.25, 1.0));
  const glm::dvec3 eye = center + distance * dir;
  cam.aimed_up = glm::vec3(0.f, 1.f, 0.f);
  cam.to_world = glm::mat4(glm::inverse(glm::lookAt(eye, center, glm::dvec3(0.0, 1.0, 0.0))));
  cam.znear = 0.f;
  return cam;
}

Camera override_camera(const Camera& base, const CameraOverride& o, const glm::vec3& target) {
  const glm::vec3 position = base.position(), forward = -glm::vec3(base.to_world[2]);
  const glm::vec3 from = o.from.value_or(position);
  const glm::vec3 at = o.at ? *o.at : o.from ? target : position + forward;
  const glm::vec3 up = o.up.value_or(base.up());
  // In double: a view between points 1e20 apart has a length whose square overflows a float.
  const glm::dvec3 view = glm::dvec3(at) - glm::dvec3(from);
  if (!(glm::length(view) > 0.0))
    throw SettingError("--look-at must differ from --look-from (the camera's position)");
  if (!(glm::length(glm::dvec3(up)) > 0.0)) throw SettingError("--up must not be zero");
  if (!(glm::length(glm::cross(glm::normalize(view), glm::normalize(glm::dvec3(up)))) > 1e-6))
    throw SettingError("--up must not be parallel to the view direction");
  Camera cam = base;
  if (o.any()) cam.name = "command line";
  cam.to_world =
      glm::mat4(glm::inverse(glm::lookAt(glm::dvec3(from), glm::dvec3(at), glm::dvec3(up))));
  if (o.any()) cam.aimed_up = up;
  if (o.fov_degrees) {
    cam.orthographic = false;
    cam.yfov = glm::radians(*o.fov_degrees);
  }
  return cam;
}

glm::vec3 look_at_point(const Camera& camera, const glm::vec3& target) {
  const float d = glm::length(target - camera.position());
  return camera.position() - glm::vec3(camera.to_world[2]) * (d > 0.f ? d : 1.f);
}

CameraProjection::CameraProjection(const Camera& camera, int w, int h)
    : to_world(camera.to_world),
      width(float(w)),
      height(float(h)),
      aspect(float(w) / float(h)),
      tan_half(std::tan(0.5f * camera.yfov)),
      ymag(camera.ymag),
      znear(camera.znear),
      orthographic(camera.orthographic),
      lens_radius(camera.aperture > 0.f ? 0.5f * camera.aperture : 0.f),
      focus_distance(camera.focus_distance) {}

void CameraProjection::pinhole_rays(const float* x, const float* y, size_t n, float* dx, float* dy,
                                    float* dz, float* tmin) const {
  // glm's mat4 × vec4 is (m0·x + m1·y) + (m2·z + m3·w): with the point's z = −1 and w = 0 the
  // second sum is the same for every ray. glm::normalize is v · (1 / sqrt(dot(v, v))), the dot
  // product (x·x + y·y) + z·z, glm::length sqrt of it.
  const glm::vec4 fixed = to_world[2] * -1.f + to_world[3] * 0.f;
  const __m128 two = _mm_set1_ps(2.f), one = _mm_set1_ps(1.f);
  for (size_t k = 0; k < n; k += 4) {
    const __m128 sx =
        _mm_sub_ps(_mm_div_ps(_mm_mul_ps(two, _mm_loadu_ps(x + k)), _mm_set1_ps(width)), one);
    const __m128 sy =
        _mm_sub_ps(one, _mm_div_ps(_mm_mul_ps(two, _mm_loadu_ps(y + k)), _mm_set1_ps(height)));
    const __m128 lx = _mm_mul_ps(_mm_mul_ps(sx, _mm_set1_ps(tan_half)), _mm_set1_ps(aspect));
    const __m128 ly = _mm_mul_ps(sy, _mm_set1_ps(tan_half));
    __m128 v[3];
    for (int a = 0; a < 3; ++a)
      v[a] = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(to_world[0][a]), lx),
                                   _mm_mul_ps(_mm_set1_ps(to_world[1][a]), ly)),
                        _mm_set1_ps(fixed[a]));
    const __m128 dot = _mm_add_ps(_mm_add_ps(_mm_mul_ps(v[0], v[0]), _mm_mul_ps(v[1], v[1])),
                                  _mm_mul_ps(v[2], v[2]));
    const __m128 inv = _mm_div_ps(one, _mm_sqrt_ps(dot));
    _mm_storeu_ps(dx + k, _mm_mul_ps(v[0], inv));
    _mm_storeu_ps(dy + k, _mm_mul_ps(v[1], inv));
    _mm_storeu_ps(dz + k, _mm_mul_ps(v[2], inv));
    const __m128 local2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(lx, lx), _mm_mul_ps(ly, ly)),
                                     _mm_mul_ps(_mm_set1_ps(-1.f), _mm_set1_ps(-1.f)));
    _mm_storeu_ps(tmin + k, _mm_mul_ps(_mm_set1_ps(znear), _mm_sqrt_ps(local2)));
  }
}

float CameraProjection::ray(float x, float y, float lens_u, float lens_v, glm::vec3& origin,
                            glm::vec3& direction) const {
  if (!thin_lens()) return ray(x, y, origin, direction);
  const float sx = 2.f * x / width - 1.f, sy = 1.f - 2.f * y / height;
  // In the camera's frame: the point in focus, and where the ray leaves the lens (its plane is
  // z = 0, through the position, or the orthographic view's plane).
  glm::vec3 focus, start(lens_radius * sample_disk(lens_u, lens_v), 0.f);
  if (orthographic) {
    const glm::vec3 on_plane(sx * ymag * aspect, sy * ymag, 0.f);
    focus = on_plane + glm::vec3(0.f, 0.f, -focus_distance);
    start += on_plane;
  } else {
    // The pinhole ray's point at depth 1, scaled to the focus plane's depth (not its distance
    // along the ray: the plane in focus is flat).
    focus = glm::vec3(sx * tan_half * aspect, sy * tan_half, -1.f) * focus_distance;
  }
  const glm::vec3 local = focus - start;
  origin = glm::vec3(to_world * glm::vec4(start, 1.f));
  direction = glm::normalize(glm::vec3(to_world * glm::vec4(local, 0.f)));
  // The near plane at depth znear: the ray goes |local| for a depth of focus_distance.
  return znear * glm::length(local) / focus_distance;
}

glm::vec2 sample_disk(float u1, float u2) {
  const float a = 2.f * u1 - 1.f, b = 2.f * u2 - 1.f;
  if (a == 0.f && b == 0.f) return glm::vec2(0.f);
  const float quarter = 0.25f * float(M_PI);
  if (std::abs(a) > std::abs(b)) {
    const float phi = quarter * (b / a);
    return a * glm::vec2(std::cos(phi), std::sin(phi));
  }
  const float phi = 2.f * quarter - quarter * (a / b);
  return b * glm::vec2(std::cos(phi), std::sin(phi));
}

float full_frame_focal_length(const Camera& camera, float aspect) {
  const float sensor_height = aspect >= 1.f ? 0.024f : 0.036f;  // the image's vertical side
  return 0.5f * sensor_height / std::tan(0.5f * camera.yfov);
}

Camera lens_camera(const Camera& camera, const LensRequest& lens, float aspect,
                   float default_focus, std::vector<std::string>& notes) {
  Camera cam = camera;
  const glm::vec3 forward = -glm::vec3(camera.to_world[2]);
  float aperture = lens.aperture.value_or(0.f);
  if (lens.fstop) {
    if (camera.orthographic)
      throw SettingError("--fstop needs a field of view: the camera is orthographic (give "
                         "--aperture, the lens's diameter, or --fov)");
    aperture = full_frame_focal_length(camera, aspect) / *lens.fstop;
  }
  if (!std::isfinite(aperture) || aperture < 0.f)
    throw SettingError("the aperture is not a finite size (--fstop or --aperture)");
  float focus = default_focus;
  if (lens.focus_distance) focus = *lens.focus_distance;
  if (lens.focus_on) {
    // Its depth, in double: a point 1e20 away must not overflow the difference's square.
    const double depth = glm::dot(glm::dvec3(*lens.focus_on) - glm::dvec3(camera.position()),
                                  glm::dvec3(forward));
    if (!(depth > 0.0) || !std::isfinite(float(depth))) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "--focus-on %g,%g,%g is not in front of the camera (its depth along the view "
                    "is %g)",
                    double(lens.focus_on->x), double(lens.focus_on->y), double(lens.focus_on->z),
                    depth);
      throw SettingError(text);
    }
    focus = float(depth);
  }
  if (!(aperture > 0.f)) {
    if (lens.focus_distance || lens.focus_on)
      notes.push_back(std::string(lens.focus_on ? "--focus-on" : "--focus-distance") +
                      " has no effect without --aperture or --fstop (a pinhole is sharp at "
                      "every depth)");
    return cam;
  }
  if (!(focus > 0.f) || !std::isfinite(focus))
    throw SettingError("the focus distance is not a positive finite depth");
  cam.aperture = aperture;
  cam.focus_distance = focus;
  return cam;
}

float camera_ray(const Camera& camera, int width, int height, float x, float y, glm::vec3& origin,
                 glm::vec3& direction) {
  return CameraProjection(camera, width, height).ray(x, y, origin, direction);
}

float camera_ray(const Camera& camera, int width, int height, float x, float y, float lens_u,
                 float lens_v, glm::vec3& origin, glm::vec3& direction) {
  return CameraProjection(camera, width, height).ray(x, y, lens_u, lens_v, origin, direction);
}

std::string camera_flags(const Camera& cam, const glm::vec3& target) {
  const glm::vec3 p = cam.position() + 0.f;  // + 0: no "-0" printed
  const glm::vec3 at = look_at_point(cam, target) + 0.f;
  const glm::vec3 up = cam.up() + 0.f;
  char text[320];
  std::snprintf(text, sizeof text,
                "--look-from %.7g,%.7g,%.7g --look-at %.7g,%.7g,%.7g --up %.7g,%.7g,%.7g", p.x, p.y,
                p.z, at.x, at.y, at.z, up.x, up.y, up.z);
  std::string out = text;
  if (!cam.orthographic) {
    std::snprintf(text, sizeof text, " --fov %.7g", cam.yfov * 180.0 / M_PI);
    out += text;
  }
  if (cam.aperture > 0.f) {
    std::snprintf(text, sizeof text, " --aperture %.7g --focus-distance %.7g",
                  double(cam.aperture), double(cam.focus_distance));
    out += text;
  }
  return out;
}

glm::ivec2 image_size(float aspect, int width, int height, int longer, const std::string& camera) {
  if (width > 0 && height > 0) return {width, height};
  if (!(aspect > 0.f)) {
    const int side = width > 0 ? width : height > 0 ? height : longer;
    return {side, side};
  }
  auto derived = [&](double size, const char* side, const char* flag, int given) {
    if (!(size <= double(max_image_side))) {
      char ratio[32];
      std::snprintf(ratio, sizeof ratio, "%g", double(aspect));
      throw Error(camera + "'s aspectRatio " + ratio + " with " + flag + " " +
                  std::to_string(given) + " gives a " + side + " of " +
                  (size < 1e15 ? std::to_string(std::llround(size)) : std::to_string(size)) +
                  " pixels, more than " + std::to_string(max_image_side) +
                  " (give --width and --height)");
    }
    return std::max(1, int(std::lround(size)));
  };
  if (width > 0) return {width, derived(width / double(aspect), "height", "--width", width)};
  if (height > 0) return {derived(height * double(aspect), "width", "--height", height), height};
  // The longer side is `longer`: the other cannot exceed it.
  if (aspect >= 1.f) return {longer, std::max(1, int(std::lround(longer / double(aspect))))};
  return {std::max(1, int(std::lround(longer * double(aspect)))), longer};
}

}  // namespace dacrt
