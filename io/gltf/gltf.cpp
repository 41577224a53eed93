// glTF 2.0 loading: tinygltf parses the file (Debian ships it compiled in libtinygltf.so, so no
// TINYGLTF_IMPLEMENTATION here), then the chosen scene's node tree is flattened into world-space
// triangles, a material table and cameras. Everything read from the file is validated first, so a
// malformed file gives one dacrt::Error line and never a crash or an out-of-bounds read.
//
// Supported: .gltf (external .bin or data URIs) and .glb; TRS and matrix nodes; triangle lists,
// indexed (u8/u16/u32) or not; sparse accessors and accessors without a bufferView (zeros);
// geometry as the optimisers publish it: KHR_mesh_quantization, EXT_meshopt_compression and
// KHR_draco_mesh_compression (compression.cpp);
// NORMAL, TANGENT, TEXCOORD_0/1 and COLOR_0 (float or normalised integers); the metallic-roughness
// factors with KHR_materials_ior and KHR_materials_specular, emissiveFactor ×
// KHR_materials_emissive_strength, doubleSided; baseColor, metallic-roughness, normal and
// emissive textures with KHR_texture_transform and samplers, from PNG, JPEG or WebP
// (EXT_texture_webp) images (embedded, in a bufferView, or external files), KHR_texture_basisu
// textures from their fallback image; tangents generated where a normal map needs them and the
// file has none; perspective and orthographic cameras; animations (animation.cpp), skins
// (skins.cpp) and morph targets, at GltfOptions::time or at rest.
// Triangle lists, strips and fans. Skipped with one warning line each: point and line primitives,
// primitives without POSITION (the spec says to skip them).
// Ignored: occlusion textures (a path tracer computes occlusion), images no material uses (never
// decoded), KHR_animation_pointer channels, and extensions that are only "used" (the spec says
// the asset renders without them).
// Rejected: files that *require* an extension not read here, and textures whose only image is
// KTX2 (KHR_texture_basisu).
// Normals that are NaN, infinite or zero are replaced by the triangle's geometric normal: they are
// only shading hints. A non-finite position is an error, since the triangle has no place.
//
// This file is the entry point (io/gltf.h): it reads the model (file.cpp, with schema.cpp's
// checks) and builds the scene in order: materials.cpp, then nodes.cpp (which places
// primitives.cpp's meshes, cameras.cpp's cameras and lights.cpp's lights), then images.cpp for
// the textures the placed meshes use. accessors.cpp and tangents.cpp serve them (internal.h).
#include "dacrt/io/gltf.h"

#include <mutex>
#include <new>

#include "dacrt/io/gltf/file.h"
#include "dacrt/io/gltf/internal.h"
#include "dacrt/io/gltf/schema.h"
#include "dacrt/util/text.h"

namespace dacrt {
namespace gltf {
namespace {

// KHR_texture_basisu is not read, but its textures' fallbacks are, and counted apart
// (ktx2_textures).
constexpr std::string_view kBasisu = "KHR_texture_basisu";
// Extensions that carry metadata only (authorship, licences): nothing in them is rendered, so
// nothing is left out by not reading them.
constexpr std::string_view kMetadata[] = {"KHR_xmp_json_ld", "KHR_xmp"};
bool metadata(const std::string& name) {
  for (std::string_view m : kMetadata)
    if (name == m) return true;
  return false;
}

// The extensions the file uses that the loader does not read, by the kind of element carrying
// them (a material, a node, the file...), and the materials with an occlusion texture.
void note_unread(const Gltf& gltf, Scene::Ignored& ignored) {
  const tinygltf::Model& m = gltf.model;
  auto note = [&](const tinygltf::ExtensionMap& extensions, const char* kind) {
    for (const auto& [name, value] : extensions)
      if (!gltf_extension_supported(name) && name != kBasisu && !metadata(name))
        ++ignored.extensions[name][kind];
  };
  auto each = [&](const auto& elements, const char* kind) {
    for (const auto& e : elements) note(e.extensions, kind);
  };
  note(m.extensions, "file");
  each(m.materials, "material");
  each(m.textures, "texture");
  each(m.images, "image");
  each(m.samplers, "sampler");
  each(m.nodes, "node");
  each(m.meshes, "mesh");
  for (const tinygltf::Mesh& mesh : m.meshes) each(mesh.primitives, "primitive");
  each(m.cameras, "camera");
  each(m.scenes, "scene");
  each(m.accessors, "accessor");
  each(m.bufferViews, "bufferView");
  each(m.buffers, "buffer");
  each(m.animations, "animation");
  each(m.skins, "skin");
  for (const std::string& name : m.extensionsUsed)
    if (!gltf_extension_supported(name) && name != kBasisu && !metadata(name))
      ignored.extensions[name];  // at least listed
  for (const tinygltf::Material& material : m.materials)
    ignored.occlusion_textures += material.occlusionTexture.index >= 0;
  for (const tinygltf::Mesh& mesh : m.meshes)
    for (const tinygltf::Primitive& primitive : mesh.primitives) {
      bool unmorphed = false;
      for (const auto& target : primitive.targets)
        for (const auto& [attribute, accessor] : target)
          unmorphed |= attribute != "POSITION" && attribute != "NORMAL" && attribute != "TANGENT";
      ignored.unmorphed_primitives += unmorphed;
    }
}

// The file's KHR_materials_variants names (checked by the schema: an array of named objects).
std::vector<std::string> variant_names(const Gltf& gltf) {
  std::vector<std::string> names;
  auto x = gltf.model.extensions.find("KHR_materials_variants");
  if (x == gltf.model.extensions.end() || !x->second.Has("variants")) return names;
  const tinygltf::Value& variants = x->second.Get("variants");
  for (size_t i = 0; i < variants.ArrayLen(); ++i)
    names.push_back(variants.Get(int(i)).Get("name").Get<std::string>());
  return names;
}

// The scene at options.time. `geometry_only`: what a frame re-makes (triangles, their attributes,
// cameras and lights), without decoding the textures, noting what is not read or warning again.
// `gltf` may have served earlier runs: what they decoded and kept (Gltf::kept) is not read again.
// `reuse`: a scene whose arrays the new one fills (MeshLoader::reuse), or null.
Scene run(Gltf& gltf, const GltfOptions& options, const std::vector<Animation>& animations,
          bool geometry_only = false, Scene* reuse = nullptr) {
  gltf.pose = options.time ? pose_at(animations, gltf.model.nodes.size(), *options.time)
                           : std::vector<NodePose>{};
  int scene = options.scene;
  Scene out;
  out.variants = variant_names(gltf);
  if (!options.variant.empty()) {
    auto it = std::find(out.variants.begin(), out.variants.end(), options.variant);
    if (it == out.variants.end()) {
      std::string known;
      for (const std::string& v : out.variants) known += (known.empty() ? "" : ", ") + v;
      throw SettingError(gltf.path + ": --variant \"" + one_line(options.variant.substr(0, 100)) +
                         "\" is not a material variant of the file (" +
                         (known.empty() ? std::string("it has none") : "it has: " + known) + ")");
    }
    gltf.variant = int(it - out.variants.begin());
    out.variant = options.variant;
  }
  MeshLoader meshes(gltf, out);
  if (reuse) meshes.reuse(*reuse);
  out.path = gltf.path;
  // Required extensions, types, ranges and indices were checked against the schema
  // (io/gltf/schema.cpp) before tinygltf parsed the file.

  bool by_default = scene == -1;
  if (by_default) scene = gltf.model.defaultScene == -1 ? 0 : gltf.model.defaultScene;
  size_t count = gltf.model.scenes.size();
  // A file without scenes (a library of meshes) gives an empty scene, unless one was asked for.
  if ((scene < 0 || size_t(scene) >= count) && !(count == 0 && by_default && scene == 0))
    gltf.fail(std::string(by_default ? "default " : "") + "scene " + str(scene) +
              " does not exist (" + str(count) + " scenes)");
  if (gltf.kept && gltf.kept->materials) {
    out.materials = *gltf.kept->materials;
  } else {
    out.materials = load_materials(gltf);
    if (gltf.kept) gltf.kept->materials = out.materials;
  }
  if (!geometry_only) check_skins(gltf);
  if (!geometry_only) note_unread(gltf, out.ignored);
  if (count > 0) load_nodes(gltf, scene, meshes, out);
  if (!geometry_only) load_textures(gltf, meshes.texture_used(), out);

  meshes.finish();
  if (out.materials.empty()) out.materials.push_back(default_material());
  out.cameras_from_file = out.cameras.size();
  // A pose's camera-less scene takes the camera framing the rest pose (GltfAnimation::Impl::
  // load): its own bounds are not needed.
  const bool rest_framed = geometry_only && options.time && !animations.empty();
  if (out.cameras.empty())
    out.cameras.push_back(rest_framed ? Camera{} : frame_bounds(out.bounds(), 0.f));
  if (geometry_only) return out;

  auto warn = [&](size_t n, const char* what) {
    if (n > 0) print_message("warning: " + gltf.path + ": skipped " + str(n) + " " + what);
  };
  warn(meshes.skipped_modes(), "point and line primitives");
  warn(meshes.skipped_unpositioned(), "primitives without POSITION");
  out.ignored.untangented_anisotropic = meshes.untangented_anisotropic();
  if (const size_t n = out.ignored.untangented_anisotropic)
    print_message("warning: " + gltf.path + ": " + str(n) +
                  " primitives of anisotropic materials have no TANGENT and no TEXCOORD to make "
                  "tangents from: their anisotropy follows an arbitrary direction");
  out.ignored.sourceless_textures = gltf.sourceless_textures.size();
  out.ignored.unknown_lights = gltf.unknown_lights.size();
  const Scene::Ignored& i = out.ignored;
  if (i.any()) {
    std::string what;
    auto add = [&](size_t n, const char* name) {
      if (n) what += (what.empty() ? "" : ", ") + str(n) + " " + name;
    };
    add(i.ktx2_textures,
        "KHR_texture_basisu textures (rendered from their fallback images: no KTX2 decoder)");
    add(i.sourceless_textures, "textures without a source image (materials rendered without them)");
    add(i.unknown_lights, "lights of a type KHR_lights_punctual does not define (skipped)");
    add(i.unmorphed_primitives,
        "primitives whose morph targets move TEXCOORD or COLOR attributes (kept at their base "
        "values)");
    if (!what.empty())
      print_message("warning: " + gltf.path +
                    ": not rendered as specified in this version: " + what);
    if (const std::string unread = i.unread_extensions(); !unread.empty())
      print_message("warning: " + gltf.path +
                    ": extensions not read in this version (rendered without them): " + unread);
  }
  return out;
}

}  // namespace
}  // namespace gltf

namespace {

// Runs `body`, turning every failure into one Error line naming `path`.
template <typename Body>
auto guarded(const std::string& path, Body body) {
  try {
    return body();
  } catch (const Error&) {  // SettingError too
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(path + ": out of memory while loading");
  } catch (const std::exception& e) {
    throw Error(path + ": cannot be loaded: " + one_line(e.what()));
  }
}

}  // namespace

struct GltfAnimation::Impl {
  std::string path;
  GltfOptions options;
  std::vector<FileRead> files;
  tinygltf::Model model;
  // The file as every load reads it, once: its sparse patches, decompressed bufferViews and
  // primitives, and (when the loads keep it) what posing reads (`kept`). Loads take turns on it.
  std::optional<gltf::Gltf> gltf;
  std::optional<gltf::KeptGeometry> kept;
  std::mutex running;
  std::vector<gltf::Animation> animations;  // those that play (GltfOptions::animation)
  std::vector<AnimationSummary> summaries;  // every animation of the file
  std::string choice;                       // "none", "all" or the index that plays
  std::string note;                         // animation_note's
  // The rest pose's bounds, and the camera made for a file without one, framing them (made once
  // they are needed).
  mutable std::once_flag rest_made;
  mutable Box rest_bounds;
  mutable Camera rest_camera;

  // `keep`: what posing reads is kept for later loads and poses (a GltfAnimation that poses).
  template <typename Read>
  Impl(const std::string& path, const GltfOptions& options, bool keep, Read read)
      : path(path), options(options) {
    guarded(path, [&] {
      model = read(files);
      gltf.emplace(this->path, model);
      if (keep) gltf->kept = &kept.emplace();
      std::vector<gltf::Animation> all = gltf::read_animations(*gltf);
      const std::vector<size_t> chosen = gltf::choose_animations(*gltf, options.animation);
      summaries = gltf::summarize_animations(*gltf, all, chosen);
      note = gltf::animation_note(*gltf, summaries, options.animation);
      choice = all.empty()                  ? "none"
               : options.animation == "all" ? "all"
                                            : std::to_string(chosen[0]);
      for (size_t a : chosen) animations.push_back(std::move(all[a]));
      return 0;
    });
  }
  Scene load(const GltfOptions& at, bool geometry_only, Scene* reuse = nullptr) {
    return guarded(path, [&] {
      const std::lock_guard<std::mutex> lock(running);
      Scene scene = gltf::run(*gltf, at, animations, geometry_only, reuse);
      scene.files = files;
      if (at.time && !geometry_only && !note.empty()) print_message(note);
      // Posed, the scene is framed as at rest (the camera made for a file without one, a
      // --look-from without --look-at): every time, every frame of a sequence the same view
      // (framing each pose's bounds would shake the view as they change).
      if (at.time && !animations.empty()) {
        std::call_once(rest_made, [&] {
          GltfOptions rest = at;
          rest.time.reset();
          const Scene still = gltf::run(*gltf, rest, animations, true);
          rest_bounds = still.bounds();
          rest_camera = still.cameras.at(0);
        });
        scene.view_bounds = rest_bounds;
        if (scene.cameras_from_file == 0) scene.cameras.at(0) = rest_camera;
      }
      return scene;
    });
  }
};

GltfAnimation::GltfAnimation(const std::string& path, const GltfOptions& options, bool poses)
    : impl_(std::make_unique<Impl>(path, options, poses, [&](std::vector<FileRead>& files) {
        return read_gltf_model(path, options.scene, &files, options.variant);
      })) {}

GltfAnimation::~GltfAnimation() = default;

Scene GltfAnimation::load() const {
  return impl_->load(impl_->options, false);
}

void GltfAnimation::pose(double time, Scene& scene) const {
  GltfOptions at = impl_->options;
  at.time = time;
  // The new arrays fill the old ones' memory (no page is allocated and touched anew).
  Scene posed = impl_->load(at, true, &scene);
  scene.geometry = std::move(posed.geometry);
  scene.degenerate_triangles = posed.degenerate_triangles;  // a pose can collapse triangles
  scene.normals = std::move(posed.normals);
  scene.texcoords = std::move(posed.texcoords);
  scene.colors = std::move(posed.colors);
  scene.tangents = std::move(posed.tangents);
  scene.cameras = std::move(posed.cameras);
  scene.cameras_from_file = posed.cameras_from_file;
  scene.view_bounds = posed.view_bounds;
  scene.lights = std::move(posed.lights);
}

double GltfAnimation::end() const {
  return gltf::animation_end(impl_->animations);
}

size_t GltfAnimation::animation_count() const {
  return impl_->summaries.size();
}

const std::vector<AnimationSummary>& GltfAnimation::animations() const {
  return impl_->summaries;
}

std::string GltfAnimation::animation_choice() const {
  return impl_->choice;
}

uint64_t GltfAnimation::decodes() const {
  return impl_->gltf->decodes;
}

Scene load_gltf(const std::string& path, const GltfOptions& options) {
  return GltfAnimation(path, options, false).load();
}

Scene load_gltf_memory(const std::string& path, const unsigned char* data, size_t size,
                       const GltfOptions& options) {
  GltfAnimation::Impl file(path, options, false, [&](std::vector<FileRead>& files) {
    return parse_gltf_model(path, data, size, options.scene, &files, options.variant);
  });
  Scene scene = file.load(options, false);
  return scene;
}

}  // namespace dacrt
