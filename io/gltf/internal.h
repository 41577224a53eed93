// What the glTF loader's files share (io/gltf/*.cpp; io/gltf/gltf.cpp runs them): the file being
// loaded, its accessors read through one validated strided view, and a loader for each element
// kind. Each checks what it reads; a failure is one dacrt::Error line naming the file.
#pragma once

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <glm/gtc/quaternion.hpp>
#include <initializer_list>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "dacrt/io/gltf.h"
#include "dacrt/scene/scene.h"
#include "dacrt/util/error.h"

namespace dacrt::gltf {

// Animations (animation.cpp): plain data read once from the file, evaluated at any time.
enum class Interpolation : uint8_t { step, linear, cubic };
enum class AnimationPath : uint8_t { translation, rotation, scale, weights };
struct AnimationSampler {
  Interpolation interpolation = Interpolation::linear;
  std::vector<float> input;   // keyframe times: finite, >= 0, strictly increasing, at least one
  std::vector<float> output;  // input × (1, or 3 for CUBICSPLINE) × components floats
  size_t components = 0;      // per value: 3, 4 (x, y, z, w), or the morph target count
};
struct AnimationChannel {
  uint32_t sampler, node;
  AnimationPath path;
  size_t components;
};
struct Animation {
  std::vector<AnimationSampler> samplers;  // those no channel uses are left empty
  std::vector<AnimationChannel> channels;  // KHR_animation_pointer channels left out (warned)
};
// A node's animated values at one time; what is not animated is the node's own.
struct NodePose {
  std::optional<glm::dvec3> translation, scale;
  std::optional<glm::dquat> rotation;
  std::vector<float> weights;  // empty: not animated
};

// One JOINTS_n / WEIGHTS_n pair of a primitive (skins.cpp), read and checked for type and count.
struct SkinSet {
  int joints_accessor, weights_accessor;
  std::vector<glm::vec4> joints, weights;  // of the vertices read (Vertices::which)
};
// A primitive as its first instance read it: its corners and the vertices they use, and those
// vertices' attributes in the mesh's space as read and checked (none is ever morphed, skinned or
// placed here: every instance and pose does that to a copy).
struct KeptPrimitive {
  bool complete = false;    // every read of the first instance succeeded
  size_t vertex_count = 0;  // POSITION's elements
  size_t triangles = 0;     // as counted against memory, strips' degenerate ones included
  // The triangles' corners as the file winds them (before a mirrored instance swaps them), in
  // the numbering of `used` when `selected` (Vertices::select), else of the file.
  std::vector<std::array<uint32_t, 3>> corners;
  std::vector<uint32_t> used;
  bool selected = false;
  std::vector<glm::vec3> positions, normals;
  std::vector<std::vector<glm::vec2>> uv;  // by slot (Gltf::texcoord_sets); empty: not read
  std::vector<glm::vec4> colors, tangents;
  // Morph targets' deltas by (target, attribute): read the first time an instance or a pose
  // weighs the target (a target of weight 0 is never read).
  std::map<std::pair<size_t, std::string>, std::vector<glm::vec3>> deltas;
  std::optional<std::vector<SkinSet>> skin;  // read the first time an instance is skinned
};
// What posing reads of the file, kept from its first read for every later one (Gltf::kept): a
// GltfAnimation that poses keeps it, so that a pose evaluates the animations and rebuilds the
// world-space geometry from it through the loader's own steps, reading no accessor and checking
// none again. Later instances of a primitive in one load take it too.
struct KeptGeometry {
  std::map<std::pair<int, int>, KeptPrimitive> primitives;  // by (mesh, primitive)
  std::map<int, std::vector<glm::dmat4>> inverse_binds;     // by skin, checked
  // EXT_mesh_gpu_instancing, by node: the work its instances were counted as, and their
  // transforms.
  struct Instances {
    std::vector<uint64_t> work;
    std::vector<glm::mat4> transforms;
  };
  std::map<int, Instances> instances;
  std::optional<std::vector<Material>> materials;  // as load_materials made them
};

// The file being loaded: its path (which starts every message) and tinygltf's model of it, and
// what reading its accessors has worked out once for all their reads.
struct Gltf {
  const std::string& path;
  const tinygltf::Model& model;
  // Sparse accessors' patches, by accessor: (element, its value's bytes), by element, the last
  // of equal elements winning. Built once an accessor, however often it is read.
  mutable std::map<int, std::vector<std::pair<uint32_t, const unsigned char*>>> sparse_patches;
  mutable uint64_t sparse_entries = 0;  // in all of them, which is bounded
  // The file uses KHR_mesh_quantization: attributes may be integers (read_vec3, read_floats).
  bool quantized = false;
  // The KHR_materials_variants variant the primitives take their materials from (-1: their own).
  int variant = -1;
  // Decompressed geometry (compression.cpp), made once and kept for every load of the file (a
  // GltfAnimation's loads and poses share one Gltf):
  // EXT_meshopt_compression bufferViews, and the accessors of KHR_draco_mesh_compression primitives
  // (by index; the primitives decoded); its bytes in all, which are bounded.
  mutable std::mutex decoded_mutex;
  mutable std::map<int, std::vector<unsigned char>> decoded_views, decoded_accessors;
  mutable std::set<const tinygltf::Primitive*> decoded_primitives;
  mutable uint64_t decoded_bytes = 0;
  // What is skipped with a warning, by index: textures without a source image (materials
  // render as without them) and lights of a type KHR_lights_punctual does not define.
  mutable std::set<int> sourceless_textures, unknown_lights;
  // The animated values of each node at the time rendered (empty: the rest pose).
  std::vector<NodePose> pose;
  // What posing reads, kept across the loads of one GltfAnimation (null: nothing is kept).
  KeptGeometry* kept = nullptr;
  // The accessors read and the bufferViews and primitives decompressed so far (tests hold a
  // pose to none).
  mutable std::atomic<uint64_t> decodes{0};
  // The TEXCOORD sets materials refer to, by Scene::texcoords slot (Scene::texcoord_sets), and
  // the slot of each set: 0 and 1 are themselves, later sets numbered as they come.
  mutable std::vector<uint32_t> texcoord_sets = {0, 1};
  mutable std::map<uint32_t, uint32_t> texcoord_slots = {{0, 0}, {1, 1}};

  Gltf(const std::string& path, const tinygltf::Model& model) : path(path), model(model) {
    for (const std::string& name : model.extensionsUsed)
      quantized |= name == "KHR_mesh_quantization";
  }
  [[noreturn]] void fail(const std::string& what) const { throw Error(path + ": " + what); }
  uint32_t texcoord_slot(uint32_t set) const {
    auto [it, added] = texcoord_slots.emplace(set, uint32_t(texcoord_sets.size()));
    if (added) texcoord_sets.push_back(set);
    return it->second;
  }
};

template <class Number>
std::string str(Number n) {
  return std::to_string(n);
}

// A number from the file for messages: 1e+39, 0.5 (printf's %g).
inline std::string num(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

inline bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The direction of v as a unit float vector, whatever v's magnitude (scaled to its largest
// component first, so 1e-200 and 1e200 work), or nothing when v is zero or not finite.
inline std::optional<glm::vec3> direction_of(const glm::dvec3& v) {
  const double big = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(big > 0.0) || !std::isfinite(big)) return std::nullopt;
  return glm::vec3(glm::normalize(v / big));
}

// A float the JSON gives as a double, or nothing when it overflows float (1e39 is finite in the
// file and infinite as float).
inline std::optional<float> as_float(double x) {
  const float f = float(x);
  if (!std::isfinite(f)) return std::nullopt;
  return f;
}

// Normalised n, or `fallback` when n has no usable direction (zero, NaN, inf).
inline glm::vec3 unit_or(const glm::vec3& n, const glm::vec3& fallback) {
  float len = glm::length(n);
  if (!(len > 0.f) || !std::isfinite(len)) return fallback;
  glm::vec3 u = n / len;
  return finite(u) ? u : fallback;
}

// Accessors (accessors.cpp).

struct Span {
  const unsigned char* data;
  size_t size;
  size_t stride;
};

// The bytes of bufferView `index`, checked against its buffer (or decoded, under
// EXT_meshopt_compression); `user` names who refers to it.
Span buffer_view(const Gltf& gltf, int index, const std::string& user);

// Compressed geometry (compression.cpp). The decoded bytes of bufferView `index`, which has
// EXT_meshopt_compression.
Span meshopt_view(const Gltf& gltf, int index);
// Decodes primitive `prim`'s KHR_draco_mesh_compression data (`where` names it) into its
// accessors' layouts (Gltf::decoded_accessors), which the readers below then read.
void decode_draco(const Gltf& gltf, const tinygltf::Primitive& prim, const std::string& where);
// Bytes per component of a componentType; 0 for INT (5124), DOUBLE and anything else glTF 2.0
// accessors do not allow.
size_t component_size(int type);
// Accessor `accessor`'s element count, checked against its bufferView (nothing is read).
size_t accessor_count(const Gltf& gltf, int accessor, const std::string& role);
// Which elements the readers below read: all of them (nullptr), or those listed, in that order
// (a primitive reads only the vertices its indices refer to). Each listed element must exist.
using Elements = const std::vector<uint32_t>*;
// The integer componentTypes an attribute may have besides FLOAT, as bits: those it may have when
// the accessor says normalized (read as the spec's c / max), and those it may have when it does
// not (read as the integers' values: KHR_mesh_quantization's positions and texture coordinates).
enum : uint8_t { kByte = 1, kUnsignedByte = 2, kShort = 4, kUnsignedShort = 8 };
struct IntegerTypes {
  uint8_t normalized = 0, plain = 0;
};
// POSITION and NORMAL: VEC3, FLOAT (copied out of their possibly strided view) or `integers`.
std::vector<glm::vec3> read_vec3(const Gltf& gltf, int accessor, const std::string& role,
                                 Elements which = nullptr, IntegerTypes integers = {});
// An attribute of `min_components`..`max_components` components, FLOAT or `integers`, as floats;
// components the accessor lacks are `fill`.
std::vector<glm::vec4> read_floats(const Gltf& gltf, int accessor, const std::string& role,
                                   int min_components, int max_components, IntegerTypes integers,
                                   float fill, Elements which = nullptr);
// Unit quaternions (x, y, z, w): FLOAT, or normalised BYTE or SHORT as the spec allows.
std::vector<glm::quat> read_rotations(const Gltf& gltf, int accessor, const std::string& role);
// A FLOAT MAT4 accessor's matrices as their columns, 4 a matrix.
std::vector<glm::vec4> read_matrix_columns(const Gltf& gltf, int accessor, const std::string& role);
// A primitive's indices: an unsigned SCALAR accessor, each index below `vertex_count`.
std::vector<uint32_t> read_indices(const Gltf& gltf, int accessor, const std::string& role,
                                   size_t vertex_count);

// Tangents (tangents.cpp): generated for a normal map where the file gives none, 3 per triangle
// of `corners` from the corners' shading normals `normals` (3 per triangle).
std::vector<glm::vec4> generate_tangents(const std::vector<glm::vec3>& p,
                                         const std::vector<glm::vec2>& uv,
                                         const std::vector<std::array<uint32_t, 3>>& corners,
                                         const std::vector<glm::vec3>& normals);

// Materials (materials.cpp).

// glTF's default material (a file's primitives without one use it).
Material default_material();
// The file's materials in order; what of them this version does not render as specified is
// counted in `ignored`.
std::vector<Material> load_materials(const Gltf& gltf);

// Images (images.cpp): samplers for every texture; images decoded (in parallel) for the textures
// materials use (`texture_used`, one flag a texture). Fills the scene's textures and images.
void load_textures(const Gltf& gltf, const std::vector<bool>& texture_used, Scene& scene);
// The source image of extension `name` (EXT_texture_webp, KHR_texture_basisu) of texture `t`, or
// -1 (the schema checked the index).
int extension_source(const tinygltf::Texture& t, const char* name);

// Primitives (primitives.cpp).

// A per-corner attribute (3 values per triangle) kept once some primitive has it; the triangles
// added before then get `fill`.
template <class T>
struct CornerStream {
  std::vector<T> data;
  bool on = false;
  void start(size_t triangles, const T& fill) {
    if (!on) on = true, data.assign(3 * triangles, fill);
  }
};

// What an instance of a mesh is posed with: its morph weights (one per target) and, when skinned,
// its skin's joint matrices.
struct MeshPose {
  std::vector<float> weights;
  const std::vector<glm::dmat4>* joints = nullptr;
};

// Skins (skins.cpp). The JOINTS_n / WEIGHTS_n sets of primitive `prim` (`where` names it) for
// the vertices `which` of its `vertex_count`, read and checked (in pairs, counts, types).
std::vector<SkinSet> read_skin_sets(const Gltf& gltf, const tinygltf::Primitive& prim,
                                    const std::string& where, size_t vertex_count, Elements which);
// Per-vertex skinning matrices of those vertices: the sets' weighted sum of `joints` (each
// weight checked, and each joint a weight names).
std::vector<glm::dmat4> skin_matrices(const Gltf& gltf, const std::vector<SkinSet>& sets,
                                      const std::string& where,
                                      const std::vector<glm::dmat4>& joints, Elements which);

// Meshes flattened into the scene's world-space triangles, one instance at a time, with the
// per-corner attributes some primitive has (normals, texture coordinates, colours, tangents) and
// the materials' textures marked used.
class MeshLoader {
 public:
  MeshLoader(const Gltf& gltf, Scene& scene);

  // Mesh `mesh` (which node `node` refers to) placed by `world` (in double: see nodes.cpp).
  void add_mesh(int mesh, const glm::dmat4& world, int node, const MeshPose& pose = {});
  // Moves the per-corner attributes into the scene, once every mesh is added.
  void finish();
  // Takes the arrays of `old` (a scene an earlier run made: its geometry and per-corner
  // attributes), emptied, so that this run fills the memory they have instead of allocating its
  // own (a pose of the frames of a sequence). Before any mesh is added.
  void reuse(Scene& old);

  // Counts `units` of work (a triangle each, or an instance read) against the memory available,
  // failing with `where` (at node `node`) in the message once they could not fit.
  void add_work(uint64_t units, const std::string& where, int node);

  const std::vector<bool>& texture_used() const { return texture_used_; }
  size_t skipped_modes() const { return skipped_modes_; }
  size_t skipped_unpositioned() const { return skipped_unpositioned_; }
  // Primitives of an anisotropic material with no tangents (no TANGENT, and no uvs to make them).
  size_t untangented_anisotropic() const { return untangented_anisotropic_; }

 private:
  struct Transform;
  struct Vertices;  // a primitive's vertices as one instance reads them

  void start_normals();
  void add_primitive(int mesh, int index, const Transform& xf, bool first_instance);
  // add_primitive's steps that change the loader's state, in the order it takes them.
  void read_corners(const tinygltf::Primitive& prim, const std::string& where, const Transform& xf,
                    KeptPrimitive& kept);
  void count_triangles(size_t triangles, const std::string& where, int node);
  void read_normals(Vertices& v);
  void read_texcoords(Vertices& v, size_t before);
  void read_colors(Vertices& v, size_t before);
  void add_triangles(const Vertices& v, const std::vector<std::array<uint32_t, 3>>& corners,
                     uint32_t material, size_t before);
  void use_textures(const Material& m);
  uint32_t material_for(int index, const std::string& where);
  int variant_material(const tinygltf::Primitive& prim) const;

  const Gltf& gltf_;
  Scene& scene_;
  const uint64_t available_memory_;
  std::vector<glm::vec3> normals_;  // per corner; kept once any primitive has NORMAL
  bool keep_normals_ = false;
  std::vector<CornerStream<glm::vec2>> texcoords_;  // by slot (Gltf::texcoord_sets)
  std::vector<uint32_t> kept_texcoords_;            // the slots whose stream is on
  CornerStream<glm::vec4> colors_, tangents_;
  std::vector<bool> texture_used_;  // by a material some primitive uses
  int default_material_ = -1;
  std::vector<bool> mesh_seen_;
  size_t skipped_modes_ = 0, skipped_unpositioned_ = 0, untangented_anisotropic_ = 0;
  uint64_t work_ = 0;  // triangles asked for, every instance and primitive counted
  size_t degenerate_ = 0;  // triangles of zero area left out
};

// The file's animations, checked; one error line names the element ("animations[0].samplers[1]
// .input").
std::vector<Animation> read_animations(const Gltf& gltf);
// Sampler `s`'s value at time t into out[0..components): held at the ends, STEP, LINEAR (slerp
// when `rotation`) or CUBICSPLINE; rotations come out as unit quaternions (x, y, z, w).
void sample(const AnimationSampler& s, double t, bool rotation, float* out);
// Every channel of every animation at time t, for `nodes` nodes (a target that several animate
// takes the last one's value).
std::vector<NodePose> pose_at(const std::vector<Animation>& animations, size_t nodes, double t);
// The last keyframe time of any channel (0 without any).
double animation_end(const std::vector<Animation>& animations);
// The animations GltfOptions::animation `choice` names, as indices into the file's (in order);
// a SettingError naming the file's animations when it names none.
std::vector<size_t> choose_animations(const Gltf& gltf, const std::string& choice);
// Each of `animations` (the file's, read) summed up for `dacrt info`: name, end, whether it is one
// of `chosen`, and which others animate one of its targets (a node's translation, rotation, scale
// or morph weights) too.
std::vector<AnimationSummary> summarize_animations(const Gltf& gltf,
                                                   const std::vector<Animation>& animations,
                                                   const std::vector<size_t>& chosen);
// A one-line note, when the choice was the default and other animations than the one that plays
// exist (or all play and some share targets): which plays, which do not, which share its targets,
// and the option that chooses; empty otherwise.
std::string animation_note(const Gltf& gltf, const std::vector<AnimationSummary>& summaries,
                           const std::string& choice);

// Skins (skins.cpp): the joint matrices of skin `skin` (world(joint) × inverse bind matrix, one per
// joint) from the nodes' world transforms `world`, checked (joints exist, the inverse bind
// matrices are FLOAT MAT4, enough of them, finite).
std::vector<glm::dmat4> joint_matrices(const Gltf& gltf, int skin,
                                       const std::vector<glm::dmat4>& world);
// Every skin of the file checked so (those no node uses too).
void check_skins(const Gltf& gltf);

// Nodes (nodes.cpp): the node tree of scene `scene` walked from its roots, each node's meshes
// given to `meshes`, its camera and light added to `out`. World transforms are composed in
// double: a chain of scales that over- or underflows float (1e20 · 1e20, 1e-25 · 1e-25) keeps its
// rotation, which cameras and lights need, and its product where it comes back into range.
void load_nodes(const Gltf& gltf, int scene, MeshLoader& meshes, Scene& out);

// Cameras (cameras.cpp): camera `index` as node `node` places it by `world`.
Camera load_camera(const Gltf& gltf, int index, const glm::dmat4& world, int node);

// Lights (lights.cpp): the KHR_lights_punctual light of node `index` (placed by `world`), if it
// has one.
std::optional<PunctualLight> load_light(const Gltf& gltf, const tinygltf::Node& node,
                                        const glm::dmat4& world, int index);

}  // namespace dacrt::gltf
