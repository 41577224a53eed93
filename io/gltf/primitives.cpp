// glTF meshes and primitives: triangle lists, strips and fans flattened into world-space
// triangles, each with its material and the per-corner shading normals, texture coordinates,
// colours and tangents (from the file or generated) that some primitive of the scene has.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <limits>

#include "dacrt/io/gltf/internal.h"
#include "dacrt/util/memory.h"

namespace dacrt::gltf {
namespace {

// What a triangle takes at least once loaded and traced: its corners and material (40 bytes),
// shading normals (36), the loader's corner indices while it is built (12), the kernel's triangle
// record (20).
constexpr uint64_t kBytesPerTriangle = 40 + 36 + 12 + 20;
// Hits report the triangle as a uint32_t with ~0u meaning "miss".
constexpr size_t kMaxTriangles = std::numeric_limits<uint32_t>::max() - 1;

glm::vec3 geometric_normal(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  return unit_or(glm::cross(b - a, c - a), glm::vec3(0.f, 0.f, 1.f));
}

}  // namespace

// The part of a node's world transform that positions, normals, tangents and winding need.
struct MeshLoader::Transform {
  glm::dmat4 world;   // positions are transformed in double, then rounded to float
  glm::mat3 normal;   // inverse-transpose of world's 3x3, up to a positive factor
  glm::mat3 tangent;  // world's 3x3, up to a positive factor
  bool flips;         // negative determinant: mirrored, so the winding must be swapped back
  int node;
  const MeshPose* pose;
};

namespace {

// m over its largest entry, as float: the same directions, whatever m's scale (1e-25 squares to
// 0 in float, 1e20 to infinity).
glm::mat3 direction_matrix(const glm::dmat3& m) {
  double big = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) big = std::max(big, std::abs(m[c][r]));
  return big > 0.0 && std::isfinite(big) ? glm::mat3(m / big) : glm::mat3(0.f);
}

}  // namespace

MeshLoader::MeshLoader(const Gltf& gltf, Scene& scene)
    : gltf_(gltf),
      scene_(scene),
      available_memory_(available_memory()),
      texture_used_(gltf.model.textures.size(), false),
      mesh_seen_(gltf.model.meshes.size(), false) {}

void MeshLoader::add_mesh(int mesh, const glm::dmat4& world, int node, const MeshPose& pose) {
  if (mesh < 0 || size_t(mesh) >= gltf_.model.meshes.size())
    gltf_.fail("node " + str(node) + " refers to mesh " + str(mesh) + ", which does not exist");
  bool first_instance = !mesh_seen_[size_t(mesh)];
  mesh_seen_[size_t(mesh)] = true;
  scene_.mesh_count += first_instance;

  const glm::dmat3 linear(world);
  // The cofactor matrix is det × inverse-transpose: always finite, even for a zero scale.
  const glm::dmat3 cofactor(glm::cross(linear[1], linear[2]), glm::cross(linear[2], linear[0]),
                            glm::cross(linear[0], linear[1]));
  // The determinant's sign, from the columns scaled to their largest entries (which keeps it).
  glm::dmat3 unit = linear;
  for (int c = 0; c < 3; ++c) {
    const double big = std::max({std::abs(unit[c].x), std::abs(unit[c].y), std::abs(unit[c].z)});
    if (big > 0.0) unit[c] /= big;
  }
  const bool flips = glm::determinant(unit) < 0.0;
  Transform xf{world, direction_matrix(flips ? -cofactor : cofactor), direction_matrix(linear),
               flips, node, &pose};
  for (size_t p = 0; p < gltf_.model.meshes[size_t(mesh)].primitives.size(); ++p)
    add_primitive(mesh, int(p), xf, first_instance);
}

void MeshLoader::finish() {
  scene_.degenerate_triangles = degenerate_;
  if (keep_normals_) scene_.normals = std::move(normals_);
  scene_.texcoord_sets = gltf_.texcoord_sets;
  scene_.texcoords.assign(std::max<size_t>(2, texcoords_.size()), {});
  for (size_t slot = 0; slot < texcoords_.size(); ++slot)
    scene_.texcoords[slot] = std::move(texcoords_[slot].data);
  scene_.colors = std::move(colors_.data);
  scene_.tangents = std::move(tangents_.data);
}

void MeshLoader::reuse(Scene& old) {
  auto emptied = [](auto& v) {
    auto out = std::move(v);
    out.clear();  // the capacity stays
    return out;
  };
  Geometry& g = scene_.geometry;
  g.corners = emptied(old.geometry.corners);
  g.material = emptied(old.geometry.material);
  normals_ = emptied(old.normals);
  texcoords_.resize(std::max(texcoords_.size(), old.texcoords.size()));
  for (size_t slot = 0; slot < old.texcoords.size(); ++slot)
    texcoords_[slot].data = emptied(old.texcoords[slot]);
  colors_.data = emptied(old.colors);
  tangents_.data = emptied(old.tangents);
}

// The material's textures are needed once a primitive uses it (only those are decoded).
void MeshLoader::use_textures(const Material& m) {
  for (const TextureRef* ref : m.sampled_textures())
    if (ref && *ref) texture_used_[size_t(ref->texture)] = true;
}

// The primitive's material, or with a KHR_materials_variants variant chosen, the one its mapping
// for that variant names (checked by the schema: mappings of a material and variant indices).
int MeshLoader::variant_material(const tinygltf::Primitive& prim) const {
  if (gltf_.variant < 0) return prim.material;
  auto x = prim.extensions.find("KHR_materials_variants");
  if (x == prim.extensions.end() || !x->second.Has("mappings")) return prim.material;
  const tinygltf::Value& mappings = x->second.Get("mappings");
  for (size_t k = 0; k < mappings.ArrayLen(); ++k) {
    const tinygltf::Value& mapping = mappings.Get(int(k));
    const tinygltf::Value& variants = mapping.Get("variants");
    for (size_t v = 0; v < variants.ArrayLen(); ++v)
      if (variants.Get(int(v)).GetNumberAsInt() == gltf_.variant)
        return mapping.Get("material").GetNumberAsInt();
  }
  return prim.material;
}

uint32_t MeshLoader::material_for(int index, const std::string& where) {
  if (index == -1) {  // the glTF default material, appended once, only if used
    if (default_material_ < 0) {
      default_material_ = int(scene_.materials.size());
      scene_.materials.push_back(default_material());
    }
    return uint32_t(default_material_);
  }
  if (index < 0 || size_t(index) >= gltf_.model.materials.size())
    gltf_.fail(where + " refers to material " + str(index) + ", which does not exist (" +
               str(gltf_.model.materials.size()) + " materials)");
  return uint32_t(index);
}

// Once one primitive has NORMAL, every triangle needs 3 normals: earlier ones get geometric
// normals.
void MeshLoader::start_normals() {
  keep_normals_ = true;
  const Geometry& g = scene_.geometry;
  normals_.reserve(3 * g.size());
  for (size_t t = 0; t < g.size(); ++t)
    normals_.insert(normals_.end(), 3,
                    geometric_normal(g.vertex(t, 0), g.vertex(t, 1), g.vertex(t, 2)));
}

void MeshLoader::add_work(uint64_t units, const std::string& where, int node) {
  work_ = units > UINT64_MAX - work_ ? UINT64_MAX : work_ + units;
  if (work_ > available_memory_ / kBytesPerTriangle)
    gltf_.fail(where + " brings the scene to " + str(work_) + " triangles (at node " + str(node) +
               "; every instance of every primitive counted as one more, degenerate ones too), "
               "which need about " +
               format_bytes(work_ > UINT64_MAX / kBytesPerTriangle ? UINT64_MAX
                                                                   : work_ * kBytesPerTriangle) +
               ", more than the " + format_bytes(available_memory_) + " of memory available");
}

// One instance of a primitive as its vertices are read: where they come from, which of the
// accessors' elements are read and how, and the attributes read (per vertex, in world space;
// empty when the primitive lacks them or nothing needs them). The file is read only by the
// primitive's first instance (`read`), into its KeptPrimitive; the later instances and poses
// copy from there.
struct MeshLoader::Vertices {
  Vertices(const Gltf& gltf, const tinygltf::Primitive& prim, const std::string& where,
           const Transform& xf, const Material& mat, KeptPrimitive& kept, bool read);
  Vertices(const Vertices&) = delete;  // `which` may point into `kept`
  Vertices& operator=(const Vertices&) = delete;

  // Vertex i's number in the file.
  size_t vertex(size_t i) const { return which ? size_t((*which)[i]) : i; }
  // A kept attribute for this instance to change: a copy when the record outlives the load, else
  // the record's own (it goes with this instance).
  template <class T>
  T take(T& kept_values) const {
    return gltf.kept ? kept_values : std::move(kept_values);
  }
  // Fails unless accessor `accessor` (`role` in messages) has as many elements as POSITION.
  void same_count(int accessor, const std::string& role) const;
  // Morph targets: each target's `attribute` deltas times its weight, added to `values`.
  void morph(const char* attribute, std::vector<glm::vec3>& values, IntegerTypes types) const;
  // A direction's matrix for vertex i: the skin's (with the instance's) or the node's.
  glm::mat3 normal_matrix(size_t i) const;
  glm::mat3 tangent_matrix(size_t i) const;

  // The steps of add_primitive that read the file only, in the order it takes them.
  void select(std::vector<std::array<uint32_t, 3>>& corners);
  void read_positions(int accessor);
  void read_tangents();

  const Gltf& gltf;
  const tinygltf::Primitive& prim;
  const std::string& where;  // "mesh m primitive p"
  const Transform& xf;
  const Material& mat;
  KeptPrimitive& kept;
  const bool read;  // the first instance: the file is read into `kept`
  size_t count;     // POSITION's elements
  // The elements read: all (`which` is null), or those kept.used (select()).
  Elements which = nullptr;
  // The integer types KHR_mesh_quantization allows, by attribute.
  IntegerTypes position_types, direction_types, texcoord_types;
  // Whether the material needs tangents, and the TEXCOORD slot they are generated from.
  bool anisotropic, wants_tangents;
  uint32_t tangent_set;

  std::vector<glm::dmat4> skin;  // per vertex, when skinned
  std::vector<glm::vec3> points, normals;
  std::vector<std::vector<glm::vec2>> uv;  // by slot (Gltf::texcoord_sets)
  std::vector<glm::vec4> colors, tangents;
};

MeshLoader::Vertices::Vertices(const Gltf& gltf, const tinygltf::Primitive& prim,
                               const std::string& where, const Transform& xf, const Material& mat,
                               KeptPrimitive& kept, bool read)
    : gltf(gltf),
      prim(prim),
      where(where),
      xf(xf),
      mat(mat),
      kept(kept),
      read(read),
      count(kept.vertex_count) {
  // KHR_mesh_quantization lets attributes be integers: positions and texture coordinates of any
  // 8- or 16-bit type, normalized or not, normals and tangents of the signed ones, normalized (the
  // node's transform scales them back).
  const bool quantized = gltf.quantized;
  constexpr uint8_t small = kByte | kUnsignedByte | kShort | kUnsignedShort;
  position_types = quantized ? IntegerTypes{small, small} : IntegerTypes{};
  direction_types = {uint8_t(quantized ? kByte | kShort : 0), 0};
  texcoord_types = {uint8_t(kUnsignedByte | kUnsignedShort | (quantized ? kByte | kShort : 0)),
                    uint8_t(quantized ? small : 0)};
  // Tangents, for normal-mapped and anisotropic materials: from the file, else generated from a
  // uv set (add_triangles). The spec says to ignore TANGENT when NORMAL is absent (the normals are
  // then flat). A clearcoat normal map needs them too. They are generated from the base normal
  // map's TEXCOORD set, else the clearcoat normal map's, else the anisotropy texture's, else
  // TEXCOORD_0.
  const bool coat_map = mat.clearcoat > 0.f && mat.clearcoat_normal_texture;
  const TextureRef& normal_map =
      mat.normal_texture || !coat_map ? mat.normal_texture : mat.clearcoat_normal_texture;
  anisotropic = mat.anisotropic();
  wants_tangents = normal_map || anisotropic;
  tangent_set = normal_map               ? normal_map.texcoord
                : mat.anisotropy_texture ? mat.anisotropy_texture.texcoord
                                         : 0u;
}

void MeshLoader::Vertices::same_count(int accessor, const std::string& role) const {
  const size_t n = accessor_count(gltf, accessor, role);
  if (n != count)
    gltf.fail("accessor " + str(accessor) + " (" + role + ") has " + str(n) +
              " elements but POSITION has " + str(count));
}

void MeshLoader::Vertices::morph(const char* attribute, std::vector<glm::vec3>& values,
                                 IntegerTypes types) const {
  const std::vector<float>& weights = xf.pose->weights;
  for (size_t k = 0; k < prim.targets.size(); ++k) {
    auto a = prim.targets[k].find(attribute);
    if (a == prim.targets[k].end()) continue;
    const std::string role = std::string(attribute) + " of " + where + " target " + str(k);
    if (read) same_count(a->second, role);
    if (weights[k] == 0.f) continue;  // nothing to add: not read
    auto known = kept.deltas.find({k, attribute});
    if (known == kept.deltas.end())
      known = kept.deltas
                  .emplace(std::pair{k, attribute}, read_vec3(gltf, a->second, role, which, types))
                  .first;
    const std::vector<glm::vec3>& deltas = known->second;
    for (size_t i = 0; i < values.size(); ++i) {
      values[i] += weights[k] * deltas[i];
      if (!finite(values[i]))
        gltf.fail("accessor " + str(a->second) + " (" + role + ") morphs vertex " + str(vertex(i)) +
                  " to a non-finite value");
    }
  }
}

glm::mat3 MeshLoader::Vertices::normal_matrix(size_t i) const {
  if (skin.empty()) return xf.normal;
  const glm::dmat3 m = glm::dmat3(xf.world) * glm::dmat3(skin[i]);
  return direction_matrix(
      glm::dmat3(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1])));
}

glm::mat3 MeshLoader::Vertices::tangent_matrix(size_t i) const {
  return skin.empty() ? xf.tangent : direction_matrix(glm::dmat3(xf.world) * glm::dmat3(skin[i]));
}

// The vertices read: all of them when the corners use about as many, else only those the
// corners use (renumbered in order), so that a handful of indices into a million vertices
// costs a handful. Chosen by the first instance (for kept.corners), then kept.
void MeshLoader::Vertices::select(std::vector<std::array<uint32_t, 3>>& corners) {
  if (read && count > 2 * 3 * corners.size()) {
    std::vector<uint32_t>& used = kept.used;
    used.reserve(3 * corners.size());
    for (const auto& c : corners) used.insert(used.end(), c.begin(), c.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    for (auto& c : corners)
      for (uint32_t& k : c)
        k = uint32_t(std::lower_bound(used.begin(), used.end(), k) - used.begin());
    kept.selected = true;
  }
  if (kept.selected) which = &kept.used;
}

// The positions (accessor `accessor`), morphed, skinned and placed by the instance's transform.
void MeshLoader::Vertices::read_positions(int accessor) {
  if (read) {
    kept.positions = read_vec3(gltf, accessor, "POSITION of " + where, which, position_types);
    for (size_t i = 0; i < kept.positions.size(); ++i)
      if (!finite(kept.positions[i]))
        gltf.fail("accessor " + str(accessor) + " (POSITION of " + where + ") vertex " +
                  str(vertex(i)) + " is not finite");
  }
  points = take(kept.positions);
  // Morph targets: one weight each, from the node (morph()).
  const std::vector<float>& weights = xf.pose->weights;
  if (prim.targets.size() != weights.size())
    gltf.fail(where + " has " + str(prim.targets.size()) + " morph targets but its node gives " +
              str(weights.size()) + " weights");
  morph("POSITION", points, position_types);
  // Skinning: each vertex by its own matrix (the joints', weighted); else the node's transform.
  if (xf.pose->joints) {
    if (!kept.skin) kept.skin = read_skin_sets(gltf, prim, where, count, which);
    skin = skin_matrices(gltf, *kept.skin, where, *xf.pose->joints, which);
  }
  for (size_t i = 0; i < points.size(); ++i) {
    points[i] =
        glm::vec3((skin.empty() ? xf.world : xf.world * skin[i]) * glm::dvec4(points[i], 1.0));
    if (!finite(points[i]))
      gltf.fail("node " + str(xf.node) + " puts vertex " + str(vertex(i)) + " of " + where +
                " at a non-finite position");
  }
}

// The file's tangents, when the material wants them and the primitive has normals.
void MeshLoader::Vertices::read_tangents() {
  if (auto attribute = prim.attributes.find("TANGENT");
      wants_tangents && !normals.empty() && attribute != prim.attributes.end()) {
    if (read) {
      const std::string role = "TANGENT of " + where;
      same_count(attribute->second, role);
      kept.tangents = read_floats(gltf, attribute->second, role, 4, 4, direction_types, 0.f, which);
    }
    tangents = take(kept.tangents);
    std::vector<glm::vec3> xyz(tangents.size());
    for (size_t i = 0; i < tangents.size(); ++i) xyz[i] = glm::vec3(tangents[i]);
    morph("TANGENT", xyz, direction_types);
    for (size_t i = 0; i < tangents.size(); ++i) {
      glm::vec4& t = tangents[i];
      // A mirroring transform turns the bitangent cross(n, t) around: flip its sign back.
      t = glm::vec4(tangent_matrix(i) * xyz[i], (t.w < 0.f) != xf.flips ? -1.f : 1.f);
      if (!finite(glm::vec3(t))) t = glm::vec4(0.f);
    }
  }
}

// The primitive's triangles, as one instance adds them: its mode and POSITION are checked, its
// material chosen, its corners and then its vertices' attributes read, and the triangles added
// with the per-corner attributes some primitive of the scene has.
void MeshLoader::add_primitive(int mesh, int index, const Transform& xf, bool first_instance) {
  const tinygltf::Primitive& prim = gltf_.model.meshes[size_t(mesh)].primitives[size_t(index)];
  std::string where = "mesh " + str(mesh) + " primitive " + str(index);
  const int mode = prim.mode;
  add_work(1, where, xf.node);
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
      mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    skipped_modes_ += first_instance;  // points and lines
    return;
  }
  auto position = prim.attributes.find("POSITION");
  if (position == prim.attributes.end()) {
    skipped_unpositioned_ += first_instance;
    return;
  }
  uint32_t material = material_for(variant_material(prim), where);
  const Material& mat = scene_.materials[material];
  use_textures(mat);
  // The file is read by the primitive's first instance (of any load of a GltfAnimation, which
  // keeps what it read: Gltf::kept), once it read all it needed; the others take that.
  KeptPrimitive scratch;  // nothing is kept: the record goes with this instance
  KeptPrimitive* kept = gltf_.kept ? &gltf_.kept->primitives[{mesh, index}] : &scratch;
  const bool read = !kept->complete;
  if (read) *kept = KeptPrimitive{};  // begun again after a read that failed
  if (read && prim.extensions.count("KHR_draco_mesh_compression")) decode_draco(gltf_, prim, where);

  // The work is bounded from the accessors' counts, before anything is read: an instance costs
  // its triangles, never its accessors' sizes (only the vertices its indices use are read).
  if (read) {
    kept->vertex_count = accessor_count(gltf_, position->second, "POSITION of " + where);
    read_corners(prim, where, xf, *kept);
  } else {
    count_triangles(kept->triangles, where, xf.node);
  }
  Vertices v(gltf_, prim, where, xf, mat, *kept, read);
  std::vector<std::array<uint32_t, 3>> corners = v.take(kept->corners);
  v.select(corners);
  if (read && gltf_.kept) kept->corners = corners;
  // A mirrored instance turns counter-clockwise (front) into clockwise: swap back.
  if (xf.flips)
    for (auto& c : corners) std::swap(c[1], c[2]);
  v.read_positions(position->second);
  read_normals(v);
  const size_t before = scene_.geometry.size();  // the triangles of earlier primitives
  read_texcoords(v, before);
  read_colors(v, before);
  v.read_tangents();
  add_triangles(v, corners, material, before);
  scene_.primitive_count += first_instance;
  kept->complete = true;
}

// Each instance's triangles, counted against the limit and the memory before they are added.
void MeshLoader::count_triangles(size_t triangles, const std::string& where, int node) {
  if (triangles > kMaxTriangles - scene_.geometry.size())
    gltf_.fail("has more than " + str(kMaxTriangles) + " triangles");
  // A small file can instance a large mesh many times: the triangles are bounded by memory as
  // they are added, before they are.
  add_work(triangles, where, node);
}

// The triangles' corners (vertex indices) into kept.corners, in the order the file winds them
// (the front face); the triangles are counted as work before the indices are read.
void MeshLoader::read_corners(const tinygltf::Primitive& prim, const std::string& where,
                              const Transform& xf, KeptPrimitive& kept) {
  const size_t vertex_count = kept.vertex_count;
  const int mode = prim.mode;
  const size_t corner_count = prim.indices == -1
                                  ? vertex_count
                                  : accessor_count(gltf_, prim.indices, "indices of " + where);
  // Lists: a trailing incomplete triangle is ignored. Strips and fans: the spec's corner order
  // (every strip triangle keeps the first one's winding); their degenerate triangles (repeated
  // indices, used to join strips) are dropped.
  const size_t triangles = mode == TINYGLTF_MODE_TRIANGLES ? corner_count / 3
                           : corner_count >= 3             ? corner_count - 2
                                                           : 0;
  kept.triangles = triangles;
  count_triangles(triangles, where, xf.node);

  std::vector<uint32_t> indices;
  if (prim.indices != -1)
    indices = read_indices(gltf_, prim.indices, "indices of " + where, vertex_count);
  std::vector<std::array<uint32_t, 3>>& corners = kept.corners;
  corners.reserve(triangles);
  for (size_t t = 0; t < triangles; ++t) {
    size_t c[3] = {3 * t, 3 * t + 1, 3 * t + 2};
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
      c[0] = t, c[1] = t + 1 + t % 2, c[2] = t + 2 - t % 2;
    else if (mode == TINYGLTF_MODE_TRIANGLE_FAN)
      c[0] = t + 1, c[1] = t + 2, c[2] = 0;
    if (!indices.empty())
      for (size_t& k : c) k = indices[k];
    if (mode != TINYGLTF_MODE_TRIANGLES && (c[0] == c[1] || c[1] == c[2] || c[0] == c[2])) continue;
    corners.push_back({uint32_t(c[0]), uint32_t(c[1]), uint32_t(c[2])});
  }
}

void MeshLoader::read_normals(Vertices& v) {
  if (auto normal = v.prim.attributes.find("NORMAL"); normal != v.prim.attributes.end()) {
    if (v.read) {
      v.same_count(normal->second, "NORMAL of " + v.where);
      v.kept.normals =
          read_vec3(gltf_, normal->second, "NORMAL of " + v.where, v.which, v.direction_types);
    }
    v.normals = v.take(v.kept.normals);
    v.morph("NORMAL", v.normals, v.direction_types);
    for (size_t i = 0; i < v.normals.size(); ++i)
      v.normals[i] = v.normal_matrix(i) * v.normals[i];  // normalised per corner (add_triangles)
    if (!keep_normals_) start_normals();
  }
}

// Texture coordinates, only for the sets some material samples (and, for an anisotropic
// material without TANGENT, the set its tangents come from, if the primitive has it); by slot
// (Gltf::texcoord_sets: TEXCOORD_0 and _1, then the later sets materials name). `before`
// triangles precede the primitive's.
void MeshLoader::read_texcoords(Vertices& v, size_t before) {
  const tinygltf::Primitive& prim = v.prim;
  const size_t slots = gltf_.texcoord_sets.size();
  if (texcoords_.size() < slots) texcoords_.resize(slots);
  v.uv.resize(slots);
  if (v.read) v.kept.uv.resize(slots);
  std::vector<bool> needed(slots, false);  // does this primitive's material sample the slot?
  for (const TextureRef* ref : v.mat.sampled_textures())
    if (ref && *ref) needed[ref->texcoord] = true;
  for (uint32_t slot = 0; slot < slots; ++slot) {
    const bool for_tangents =
        v.anisotropic && slot == v.tangent_set &&
        !(prim.attributes.count("TANGENT") && prim.attributes.count("NORMAL"));
    if (!needed[slot] && !for_tangents) continue;
    const std::string name = "TEXCOORD_" + str(gltf_.texcoord_sets[slot]);
    auto attribute = prim.attributes.find(name);
    if (attribute == prim.attributes.end()) {
      if (!needed[slot]) continue;  // tangents from nothing: see untangented_anisotropic_
      gltf_.fail(v.where + ": its material samples " + name +
                 ", which the primitive does not have");
    }
    if (v.read) {
      const std::string role = name + " of " + v.where;
      v.same_count(attribute->second, role);
      std::vector<glm::vec4> values =
          read_floats(gltf_, attribute->second, role, 2, 2, v.texcoord_types, 0.f, v.which);
      v.kept.uv[slot].resize(values.size());
      for (size_t i = 0; i < values.size(); ++i) v.kept.uv[slot][i] = glm::vec2(values[i]);
    }
    v.uv[slot] = v.take(v.kept.uv[slot]);
    if (needed[slot] && !texcoords_[slot].on) {
      texcoords_[slot].start(before, glm::vec2(0.f));
      kept_texcoords_.push_back(slot);
    }
  }
}

void MeshLoader::read_colors(Vertices& v, size_t before) {
  if (auto attribute = v.prim.attributes.find("COLOR_0"); attribute != v.prim.attributes.end()) {
    if (v.read) {
      const std::string role = "COLOR_0 of " + v.where;
      v.same_count(attribute->second, role);
      v.kept.colors = read_floats(gltf_, attribute->second, role, 3, 4,
                                  {kUnsignedByte | kUnsignedShort}, 1.f, v.which);
      for (size_t i = 0; i < v.kept.colors.size(); ++i) {
        // Float colours must lie in [0, 1] (the spec's words), normalized ones do by their type.
        const glm::vec4& c = v.kept.colors[i];
        if (!(glm::all(glm::greaterThanEqual(c, glm::vec4(0.f))) &&
              glm::all(glm::lessThanEqual(c, glm::vec4(1.f)))))
          gltf_.fail("accessor " + str(attribute->second) + " (" + role + ") element " +
                     str(v.vertex(i)) + " is not within [0, 1]");
      }
    }
    v.colors = v.take(v.kept.colors);
    colors_.start(before, glm::vec4(1.f));
  }
}

// The triangles of `corners` (of material `material`) added to the scene, with their corners'
// attributes; `before` triangles precede them.
void MeshLoader::add_triangles(const Vertices& v,
                               const std::vector<std::array<uint32_t, 3>>& corners,
                               uint32_t material, size_t before) {
  const std::vector<glm::vec3>& points = v.points;
  // Shading normals per corner, as stored: computed once, when they are kept or tangents are
  // generated from them.
  const bool generate = v.tangents.empty() && v.wants_tangents && v.tangent_set < v.uv.size() &&
                        !v.uv[v.tangent_set].empty();
  std::vector<glm::vec3> corner_normals;  // 3 per triangle of `corners`
  if (keep_normals_ || generate) {
    corner_normals.reserve(3 * corners.size());
    for (const auto& c : corners) {
      const glm::vec3 g = geometric_normal(points[c[0]], points[c[1]], points[c[2]]);
      for (uint32_t i : c)
        corner_normals.push_back(v.normals.empty() ? g : unit_or(v.normals[i], g));
    }
  }
  std::vector<glm::vec4> corner_tangents;  // 3 per triangle of `corners`
  if (!v.tangents.empty()) {
    corner_tangents.reserve(3 * corners.size());
    for (const auto& c : corners)
      for (uint32_t i : c) corner_tangents.push_back(v.tangents[i]);
  } else if (generate) {
    corner_tangents = generate_tangents(points, v.uv[v.tangent_set], corners, corner_normals);
  }
  if (v.wants_tangents) tangents_.start(before, glm::vec4(0.f));
  // (Without either, anisotropy follows an arbitrary frame: scene/surface.cpp.)
  untangented_anisotropic_ += v.anisotropic && corner_tangents.empty() && !corners.empty();

  // Triangles of zero area (their edges' cross product, in double, is zero) are left out, with
  // their corners' attributes, and counted: no ray hits them, and a file of millions of them at
  // one point (80 M zero vertices of an accessor without a bufferView) would send every ray
  // there through all of them.
  // Which triangles stay, in parallel; then each is written at its place, in parallel (the
  // arrays grow once).
  const size_t n = corners.size();
  std::vector<uint32_t> place(n);  // among the triangles that stay; ~0u: left out
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const auto& range) {
    for (size_t t = range.begin(); t != range.end(); ++t) {
      const std::array<uint32_t, 3>& c = corners[t];
      const glm::dvec3 a(points[c[0]]);
      const glm::dvec3 e = glm::cross(glm::dvec3(points[c[1]]) - a, glm::dvec3(points[c[2]]) - a);
      place[t] = e.x == 0.0 && e.y == 0.0 && e.z == 0.0 ? ~0u : 0u;
    }
  });
  size_t kept = 0;
  for (uint32_t& p : place)
    if (p == 0u) p = uint32_t(kept++);
  degenerate_ += n - kept;
  Geometry& geometry = scene_.geometry;
  const size_t first = geometry.size();
  geometry.resize(first + kept, material);
  if (keep_normals_) normals_.resize(3 * (first + kept));
  for (uint32_t slot : kept_texcoords_) texcoords_[slot].data.resize(3 * (first + kept));
  if (colors_.on) colors_.data.resize(3 * (first + kept));
  if (tangents_.on) tangents_.data.resize(3 * (first + kept));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const auto& range) {
    for (size_t t = range.begin(); t != range.end(); ++t) {
      if (place[t] == ~0u) continue;
      const std::array<uint32_t, 3>& c = corners[t];
      const size_t to = first + place[t];
      for (int k = 0; k < 3; ++k) {
        const uint32_t i = c[size_t(k)];
        const size_t corner = 3 * to + size_t(k);
        geometry.corners[to][size_t(k)] = points[i];
        if (keep_normals_) normals_[corner] = corner_normals[3 * t + size_t(k)];
        for (uint32_t slot : kept_texcoords_)
          texcoords_[slot].data[corner] = v.uv[slot].empty() ? glm::vec2(0.f) : v.uv[slot][i];
        if (colors_.on) colors_.data[corner] = v.colors.empty() ? glm::vec4(1.f) : v.colors[i];
        if (tangents_.on)
          tangents_.data[corner] =
              corner_tangents.empty() ? glm::vec4(0.f) : corner_tangents[3 * t + size_t(k)];
      }
    }
  });
}

}  // namespace dacrt::gltf
