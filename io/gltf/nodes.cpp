// glTF nodes: the chosen scene's node tree walked from its roots, each node's TRS or matrix
// transform composed into a world transform, and what a node places there: its mesh (once per
// EXT_mesh_gpu_instancing instance), its camera and its KHR_lights_punctual light.
#include <glm/gtc/matrix_transform.hpp>

#include "dacrt/io/gltf/internal.h"

namespace dacrt::gltf {
namespace {

// EXT_mesh_gpu_instancing's per-instance TRANSLATION, ROTATION and SCALE as matrices (T R S);
// nothing when the node does not use it (and an empty list for zero instances).
std::optional<std::vector<glm::mat4>> instance_transforms(const Gltf& gltf,
                                                          const tinygltf::Node& node, int index,
                                                          MeshLoader& meshes) {
  auto ext = node.extensions.find("EXT_mesh_gpu_instancing");
  if (ext == node.extensions.end()) return std::nullopt;
  const std::string where = "node " + str(index) + " EXT_mesh_gpu_instancing";
  if (!ext->second.IsObject() || !ext->second.Has("attributes") ||
      !ext->second.Get("attributes").IsObject())
    gltf.fail(where + " has no attributes");
  const tinygltf::Value& attributes = ext->second.Get("attributes");
  auto accessor = [&](const char* name) {
    if (!attributes.Has(name)) return -1;
    const tinygltf::Value& v = attributes.Get(name);
    if (!v.IsNumber()) gltf.fail(where + ": " + name + " is not an accessor index");
    return int(v.GetNumberAsDouble());
  };
  const int t = accessor("TRANSLATION"), r = accessor("ROTATION"), s = accessor("SCALE");
  // Reading the instances is work of its own (a mesh without triangles costs nothing else), so
  // it is bounded with the triangles before it is done; a GltfAnimation's later loads count the
  // same work and take the transforms its first load read (Gltf::kept).
  if (gltf.kept)
    if (auto known = gltf.kept->instances.find(index); known != gltf.kept->instances.end()) {
      for (uint64_t units : known->second.work) meshes.add_work(units, where, index);
      return known->second.transforms;
    }
  std::vector<uint64_t> work;
  for (const auto& [a, name] : {std::pair{t, "TRANSLATION"}, {r, "ROTATION"}, {s, "SCALE"}})
    if (a != -1) {
      work.push_back(accessor_count(gltf, a, std::string(name) + " of " + where));
      meshes.add_work(work.back(), where, index);
    }
  std::vector<glm::vec3> translation, scale;
  std::vector<glm::quat> rotation;
  size_t count = 0;
  bool counted = false;
  auto same_count = [&](size_t n, const char* name) {
    if (counted && n != count)
      gltf.fail(where + ": " + name + " has " + str(n) + " instances, not " + str(count));
    count = n, counted = true;
  };
  // With KHR_mesh_quantization, translations and scales may be normalized BYTE or SHORT too.
  const IntegerTypes quantized = {uint8_t(gltf.quantized ? kByte | kShort : 0), 0};
  if (t != -1)
    translation = read_vec3(gltf, t, "TRANSLATION of " + where, nullptr, quantized),
    same_count(translation.size(), "TRANSLATION");
  if (s != -1)
    scale = read_vec3(gltf, s, "SCALE of " + where, nullptr, quantized),
    same_count(scale.size(), "SCALE");
  if (r != -1)
    rotation = read_rotations(gltf, r, "ROTATION of " + where),
    same_count(rotation.size(), "ROTATION");
  if (!counted) gltf.fail(where + " has none of TRANSLATION, ROTATION and SCALE");
  std::vector<glm::mat4> out(count);
  for (size_t i = 0; i < count; ++i) {
    glm::mat4 m(1.f);
    if (!translation.empty()) m = glm::translate(m, translation[i]);
    if (!rotation.empty()) m *= glm::mat4_cast(rotation[i]);
    if (!scale.empty()) m = glm::scale(m, scale[i]);
    if (!finite(glm::vec3(m[0])) || !finite(glm::vec3(m[1])) || !finite(glm::vec3(m[2])) ||
        !finite(glm::vec3(m[3])))
      gltf.fail(where + ": instance " + str(i) + " has a non-finite transform");
    out[i] = m;
  }
  if (gltf.kept) gltf.kept->instances[index] = {std::move(work), out};
  return out;
}

glm::dmat4 local_transform(const Gltf& gltf, int index) {
  const tinygltf::Node& n = gltf.model.nodes[size_t(index)];
  const NodePose* pose = gltf.pose.empty() ? nullptr : &gltf.pose[size_t(index)];
  std::string what = "node " + str(index);
  auto expect = [&](const std::vector<double>& v, size_t size, const char* name) {
    if (!v.empty() && v.size() != size)
      gltf.fail(what + ": " + name + " has " + str(v.size()) + " numbers, not " + str(size));
    return !v.empty();
  };
  glm::dmat4 m(1.0);
  if (expect(n.matrix, 16, "matrix")) {
    for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = n.matrix[size_t(i)];  // both column-major
    // glTF requires the bottom row to be 0 0 0 1; keep the transform affine whatever the file
    // says.
    m[0][3] = m[1][3] = m[2][3] = 0.0;
    m[3][3] = 1.0;
  } else {
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    // An animated value replaces the node's own (read_animations refused matrix nodes).
    if (pose && pose->translation)
      t[3] = glm::dvec4(*pose->translation, 1.0);
    else if (expect(n.translation, 3, "translation"))
      t[3] = glm::dvec4(n.translation[0], n.translation[1], n.translation[2], 1.0);
    std::optional<glm::dvec4> q;
    if (pose && pose->rotation) {
      q = glm::dvec4(pose->rotation->x, pose->rotation->y, pose->rotation->z, pose->rotation->w);
    } else if (expect(n.rotation, 4, "rotation")) {
      // The spec asks for a unit quaternion. Files round theirs, so within 1 % of unit length it
      // is normalised (in double); further off, the file does not say which rotation it means.
      q = glm::dvec4(n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3]);
      const double length = glm::length(*q);
      if (!(std::abs(length - 1.0) <= 0.01))
        gltf.fail(what + ": rotation is not a unit quaternion (its length is " + num(length) + ")");
    }
    if (q) {
      const double length = glm::length(*q);
      if (!(length > 0.0) || !std::isfinite(length))
        gltf.fail(what + ": rotation is not a usable quaternion");
      const glm::dvec4 u = *q / length;
      r = glm::mat4_cast(glm::dquat(u.w, u.x, u.y, u.z));
    }
    if (pose && pose->scale)
      s = glm::scale(glm::dmat4(1.0), *pose->scale);
    else if (expect(n.scale, 3, "scale"))
      for (int axis = 0; axis < 3; ++axis) s[axis][axis] = n.scale[size_t(axis)];
    m = t * r * s;
  }
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(m[c][r])) gltf.fail(what + ": transform is not finite");
  return m;
}

// The morph weights node `index` renders mesh `mesh` with: animated, else the node's, else the
// mesh's, else zeros; one per morph target (the spec: as many as the mesh's targets).
std::vector<float> morph_weights(const Gltf& gltf, int index, int mesh) {
  const tinygltf::Node& n = gltf.model.nodes[size_t(index)];
  if (mesh < 0 || size_t(mesh) >= gltf.model.meshes.size()) return {};
  const tinygltf::Mesh& m = gltf.model.meshes[size_t(mesh)];
  const size_t targets = m.primitives.empty() ? 0 : m.primitives[0].targets.size();
  for (size_t p = 1; p < m.primitives.size(); ++p)
    if (m.primitives[p].targets.size() != targets)
      gltf.fail("meshes[" + str(mesh) + "].primitives[" + str(p) + "].targets: " +
                str(m.primitives[p].targets.size()) + " morph targets, but primitive 0 has " +
                str(targets) + " (they must have as many)");
  auto check = [&](const std::vector<double>& w, const std::string& at) {
    if (!w.empty() && w.size() != targets)
      gltf.fail(at + ": " + str(w.size()) + " weights for " + str(targets) + " morph targets");
    std::vector<float> out(w.size());
    for (size_t k = 0; k < w.size(); ++k) {
      const auto f = as_float(w[k]);
      if (!f) gltf.fail(at + ": weight " + str(k) + " is not a finite float");
      out[k] = *f;
    }
    return out;
  };
  const std::vector<float> of_mesh = check(m.weights, "meshes[" + str(mesh) + "].weights");
  const std::vector<float> of_node = check(n.weights, "nodes[" + str(index) + "].weights");
  if (!gltf.pose.empty() && !gltf.pose[size_t(index)].weights.empty())
    return gltf.pose[size_t(index)].weights;
  if (!of_node.empty()) return of_node;
  if (!of_mesh.empty()) return of_mesh;
  return std::vector<float>(targets, 0.f);
}

// Joints outside the scene's tree get world transforms too: their parents' chains, from the
// nodes' children lists (`reached`: the nodes the scene placed, whose `world` is known).
void place_outside_joints(const Gltf& gltf, const std::vector<int>& reached,
                          std::vector<glm::dmat4>& world) {
  const auto& nodes = gltf.model.nodes;
  std::vector<int> parent;
  std::vector<char> done(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) done[i] = reached[i] != -2;
  for (const tinygltf::Skin& skin : gltf.model.skins)
    for (int joint : skin.joints) {
      if (joint < 0 || size_t(joint) >= nodes.size() || done[size_t(joint)]) continue;
      if (parent.empty()) {
        parent.assign(nodes.size(), -1);
        for (size_t i = 0; i < nodes.size(); ++i)
          for (int c : nodes[i].children)
            if (c >= 0 && size_t(c) < nodes.size() && parent[size_t(c)] == -1)
              parent[size_t(c)] = int(i);
      }
      // The chain up to a placed node or a root, at most every node (else a cycle).
      std::vector<int> chain;
      for (int a = joint; a != -1 && !done[size_t(a)]; a = parent[size_t(a)]) {
        if (chain.size() > nodes.size())
          gltf.fail("node " + str(joint) + " (a joint) has a cycle among its ancestors");
        chain.push_back(a);
      }
      for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
        const int p = parent[size_t(*it)];
        world[size_t(*it)] = (p == -1 ? glm::dmat4(1.0) : world[size_t(p)]) *
                             local_transform(gltf, *it);
        done[size_t(*it)] = 1;
      }
    }
}

}  // namespace

// Depth-first, pre-order, with an explicit stack: deep trees cannot overflow the call stack, and
// a node reached twice (a cycle, two parents, or listed twice) is caught before it is pushed
// again.
void load_nodes(const Gltf& gltf, int scene, MeshLoader& meshes, Scene& out) {
  constexpr int kUnreached = -2, kRoot = -1;
  std::vector<int> parent(gltf.model.nodes.size(), kUnreached);
  struct Pending {
    int node;
    glm::dmat4 parent_world;
  };
  std::vector<Pending> stack;
  auto push = [&](int child, int from, const glm::dmat4& parent_world) {
    std::string by = from == kRoot ? "scene " + str(scene) : "node " + str(from);
    if (child < 0 || size_t(child) >= gltf.model.nodes.size())
      gltf.fail(by + " refers to node " + str(child) + ", which does not exist");
    int& p = parent[size_t(child)];
    if (p != kUnreached) {
      for (int a = from; a >= 0; a = parent[size_t(a)])
        if (a == child) gltf.fail("node " + str(child) + " is its own ancestor (cycle)");
      std::string first = p == kRoot ? "scene " + str(scene) : "node " + str(p);
      gltf.fail("node " + str(child) + " has two parents (" + first + " and " + by + ")");
    }
    p = from;
    stack.push_back({child, parent_world});
  };

  const auto& roots = gltf.model.scenes[size_t(scene)].nodes;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) push(*it, kRoot, glm::dmat4(1.0));
  // The world transforms first (skins need their joints'), then what the nodes place, in the
  // same order.
  std::vector<glm::dmat4> world(gltf.model.nodes.size(), glm::dmat4(1.0));
  std::vector<int> order;
  while (!stack.empty()) {
    Pending item = stack.back();
    stack.pop_back();
    const tinygltf::Node& node = gltf.model.nodes[size_t(item.node)];
    ++out.node_count;
    world[size_t(item.node)] = item.parent_world * local_transform(gltf, item.node);
    order.push_back(item.node);
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it)
      push(*it, item.node, world[size_t(item.node)]);
  }
  place_outside_joints(gltf, parent, world);
  std::map<int, std::vector<glm::dmat4>> skins;  // joint matrices, by skin
  for (int index : order) {
    const tinygltf::Node& node = gltf.model.nodes[size_t(index)];
    const glm::dmat4& w = world[size_t(index)];
    if (node.mesh != -1) {
      MeshPose mesh_pose;
      mesh_pose.weights = morph_weights(gltf, index, node.mesh);
      if (node.skin != -1) {
        if (node.skin < 0 || size_t(node.skin) >= gltf.model.skins.size())
          gltf.fail("nodes[" + str(index) + "].skin: skin " + str(node.skin) + " does not exist");
        auto known = skins.find(node.skin);
        if (known == skins.end())
          known = skins.emplace(node.skin, joint_matrices(gltf, node.skin, world)).first;
        mesh_pose.joints = &known->second;
      }
      // A skinned mesh is placed by its joints alone: the spec ignores its node's transform.
      const glm::dmat4 placed = node.skin != -1 ? glm::dmat4(1.0) : w;
      // EXT_mesh_gpu_instancing: the mesh once per instance, never at the node itself.
      if (auto instances = instance_transforms(gltf, node, index, meshes); !instances)
        meshes.add_mesh(node.mesh, placed, index, mesh_pose);
      else
        for (const glm::mat4& m : *instances)
          meshes.add_mesh(node.mesh, placed * glm::dmat4(m), index, mesh_pose);
    }
    if (node.camera != -1) out.cameras.push_back(load_camera(gltf, node.camera, w, index));
    if (auto light = load_light(gltf, node, w, index)) out.lights.push_back(*light);
  }
}

}  // namespace dacrt::gltf
