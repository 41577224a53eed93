// Scene: what a glTF file becomes. Immutable once loaded: world-space triangles (Geometry), their
// shading data, a material table, cameras and lights. Elements refer to each other by index. What
// one render adds (a moved camera, an image size, more lights, an environment) is its Shot
// (scene/shot.h). The one change after loading is animation's: GltfAnimation::pose (io/gltf.h)
// replaces the geometry, its per-corner attributes, the cameras and the lights with new arrays
// for another time, made from what the load kept (the file is not decoded again); materials,
// textures and images stay as loaded.
#pragma once

#include <array>
#include <glm/glm.hpp>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "dacrt/materials/material.h"
#include "dacrt/materials/texture.h"
#include "dacrt/scene/camera.h"
#include "dacrt/tracer/geometry.h"
#include "dacrt/util/file_hash.h"

namespace dacrt {

// A KHR_lights_punctual light, placed by its node. Intensities are taken as renderer units, like
// emissive factors: `intensity` (colour × intensity) is radiant intensity for point and spot lights
// (irradiance I / d² at distance d) and irradiance for directional lights.
struct PunctualLight {
  enum class Type : uint8_t { point, spot, directional };
  Type type = Type::point;
  std::string name;
  glm::vec3 intensity{1.f};
  float range = 0.f;  // beyond it nothing; 0 = unlimited
  glm::vec3 position{0.f};
  glm::vec3 direction{0.f, 0.f, -1.f};             // where it shines: the node's -Z
  float cos_inner = 1.f, cos_outer = 0.70710678f;  // spot cone (defaults 0 and π/4)

  // What reaches a point `to` away from the light (|to| = distance), before the cosine there:
  // I / d² with the spec's recommended range window and spot falloff.
  glm::vec3 irradiance_towards(const glm::vec3& to) const;
};

struct Scene {
  std::string path;  // the file it came from, for messages
  // The other files it was read from (external buffers and images), which no output may replace,
  // with how much of each the loader read (what the render's fingerprint covers).
  std::vector<FileRead> files;
  Geometry geometry;  // world space; geometry.material indexes `materials`
  // Per-corner shading normals, 3 per triangle (corner-major: tri*3 + corner), world space and
  // normalised. Empty when no primitive had NORMAL; primitives without it get geometric normals.
  std::vector<glm::vec3> normals;
  // More per-corner attributes, each empty when nothing needs it: TEXCOORD_n (kept only if a
  // material samples set n), COLOR_0 as linear RGBA (1 where a primitive has none), and
  // tangents (xyz, w = bitangent sign; world space, from TANGENT or generated; kept only when a
  // material has a normal map; zero where none could be made).
  // texcoords[k] is TEXCOORD_n for n = texcoord_sets[k] (TextureRef::texcoord is k): 0 and 1 are
  // always TEXCOORD_0 and _1, the later sets a material samples follow in order, so that their
  // count is bounded by the file's texture references, never by the numbers they give.
  std::vector<std::vector<glm::vec2>> texcoords = std::vector<std::vector<glm::vec2>>(2);
  std::vector<uint32_t> texcoord_sets = {0, 1};
  std::vector<glm::vec4> colors;
  std::vector<glm::vec4> tangents;
  // One per glTF image and texture; images that no material uses are left undecoded (empty).
  std::vector<TextureImage> images;
  std::vector<Texture> textures;
  std::vector<Material> materials;    // never empty: the glTF default material is appended if used
  std::vector<Camera> cameras;        // never empty after loading: see `cameras_from_file`
  std::vector<PunctualLight> lights;  // KHR_lights_punctual, one per node that has one
  size_t cameras_from_file = 0;       // if 0, cameras[0] was made to frame the scene's bounds
  // KHR_materials_variants: the file's variant names, and the one rendered (empty: none).
  std::vector<std::string> variants;
  std::string variant;

  // What the file uses that this version does not render as specified (the loader warns once):
  // textures a material samples whose KHR_texture_basisu
  // (KTX2) image gives way to their fallback source (no KTX2 decoder), counted per texture;
  // extensions the file uses that are not read at all (by name: the kinds of element that carry
  // them and how many; none when only listed in extensionsUsed). Occlusion textures are left
  // unread on purpose (a path tracer computes occlusion): counted for `dacrt info`, not warned.
  struct Ignored {
    size_t ktx2_textures = 0;
    std::map<std::string, std::map<std::string, size_t>> extensions;
    size_t occlusion_textures = 0;
    // Textures without a source image (the spec leaves them undefined: rendered without them)
    // and lights of a type KHR_lights_punctual does not define (skipped).
    size_t sourceless_textures = 0, unknown_lights = 0;
    // Primitives whose morph targets move TEXCOORD_n or COLOR_n (only POSITION, NORMAL and
    // TANGENT are morphed: those attributes keep their base values).
    size_t unmorphed_primitives = 0;
    // Primitives of an anisotropic material with no tangents (no TANGENT, and no uvs to make
    // them): their anisotropy follows an arbitrary direction.
    size_t untangented_anisotropic = 0;
    bool any() const {
      return ktx2_textures || sourceless_textures || unknown_lights || unmorphed_primitives ||
             untangented_anisotropic || !extensions.empty();
    }
    // "KHR_materials_sheen (2 materials), EXT_foo (listed in extensionsUsed)", or "".
    std::string unread_extensions() const;
  } ignored;

  // Counts from the file, for `dacrt info`. Triangles of zero area (corners that coincide or lie
  // on one line) are dropped by the loader, counted here: no ray can hit them, but every ray
  // through their point would be tested against them all.
  size_t degenerate_triangles = 0;
  size_t mesh_count = 0;
  size_t primitive_count = 0;
  size_t node_count = 0;

  Box bounds() const { return geometry.bounds(); }
  // What views are framed on (the camera made for a file without one, a --look-from without
  // --look-at): the rest pose's bounds when the loader posed the scene, so that every frame of
  // a sequence gets one view; else (empty) the geometry's.
  Box view_bounds{};
  Box framing_bounds() const { return view_bounds.empty() ? bounds() : view_bounds; }

  // The shading work this scene does not need, in words, for `dacrt info` and the render's
  // statistics: texture lookups and uv interpolation (no textured material), vertex colours,
  // alpha tests (every material opaque), transmission (no transmissive material). Shadow rays are
  // the integrator's call (an environment map needs them too).
  std::vector<std::string> unused_work() const;
};

// A scene's materials counted by kind, for `dacrt info` and the Python module's Scene.info.
struct MaterialCounts {
  size_t emissive_triangles = 0, emissive = 0, textured = 0, masked = 0, blended = 0,
         transmissive = 0;
};
MaterialCounts count_materials(const Scene& scene);

}  // namespace dacrt
