// The glTF schema check of cameras, meshes (with their primitives' extensions), skins, nodes,
// scenes and KHR_lights_punctual lights, and of the node hierarchy that nodes and scenes make;
// the Checker is in io/gltf/schema_checker.h.
#include <string>

#include "dacrt/io/gltf/schema_checker.h"

namespace dacrt::gltf::schema {

void Checker::camera(const json& c, const Pointer& at) {
  const std::string type =
      enum_string(need(c, at, "type"), at / "type", {"perspective", "orthographic"});
  const json* perspective = has(c, at, "perspective");
  const json* orthographic = has(c, at, "orthographic");
  if (perspective && orthographic)
    fail(at, "has both perspective and orthographic (it must have one)");
  const bool is_perspective = type == "perspective";
  const json* p = is_perspective ? perspective : orthographic;
  const Pointer pp = at / type;
  if (!p) fail(pp, "is missing (it is required for type \"" + type + "\")");
  property(*p, pp);
  double znear = 0.0;
  if (is_perspective) {
    number_member(*p, pp, "aspectRatio", kPositive);
    number(need(*p, pp, "yfov"), pp / "yfov", kPositive);
    znear = number(need(*p, pp, "znear"), pp / "znear", kPositive);
  } else {
    for (const char* key : {"xmag", "ymag"})
      if (number(need(*p, pp, key), pp / key, kAnyNumber) == 0.0)
        fail(pp / key, "is 0 (it must not be zero)");
    znear = number(need(*p, pp, "znear"), pp / "znear", kNonNegative);
  }
  if (const json* v = has(*p, pp, "zfar", !is_perspective))
    if (const double zfar = number(*v, pp / "zfar", kPositive); !(zfar > znear))
      fail(pp / "zfar", describe(*v) + " is not greater than znear " + describe(p->at("znear")));
}

void Checker::mesh(const json& m, const Pointer& at) {
  const json& primitives =
      array(need(m, at, "primitives"), at / "primitives", "an array of objects");
  for (size_t i = 0; i < primitives.size(); ++i) {
    const Pointer p = at / "primitives" / i;
    const json& prim = property(primitives[i], p);
    attributes(need(prim, p, "attributes"), p / "attributes", true);
    index_member(prim, p, "indices", "accessors");
    index_member(prim, p, "material", "materials");
    if (const json* v = has(prim, p, "mode")) enum_int(*v, p / "mode", {0, 1, 2, 3, 4, 5, 6});
    if (const json* x = extension(prim, p, "KHR_materials_variants")) {
      const Pointer xt = p / "extensions" / "KHR_materials_variants";
      const json& mappings =
          array(need(*x, xt, "mappings"), xt / "mappings", "an array of objects");
      // A variant maps a primitive to one material: in one mapping at most.
      std::vector<bool> mapped(variant_count_, false);
      for (size_t k = 0; k < mappings.size(); ++k) {
        const json& mapping = property(mappings[k], xt / "mappings" / k);
        index_member(mapping, xt / "mappings" / k, "material", "materials", true);
        const Pointer vt = xt / "mappings" / k / "variants";
        const json& variants = need(mapping, xt / "mappings" / k, "variants");
        indices(variants, vt, "variants");
        for (size_t i = 0; i < variants.size(); ++i) {
          const size_t v = variants[i].get<size_t>();
          if (mapped[v]) fail(vt / i, "variant " + str(int64_t(v)) + " is mapped twice");
          mapped[v] = true;
        }
      }
    }
    if (const json* x = extension(prim, p, "KHR_draco_mesh_compression")) {
      const Pointer xt = p / "extensions" / "KHR_draco_mesh_compression";
      index_member(*x, xt, "bufferView", "bufferViews", true);
      const json& ids = property(need(*x, xt, "attributes"), xt / "attributes");
      for (auto it = ids.begin(); it != ids.end(); ++it)
        integer(it.value(), xt / "attributes" / it.key(), 0, kMaxInt);
    }
    if (const json* targets = has(prim, p, "targets")) {
      array(*targets, p / "targets", "an array of objects");
      for (size_t t = 0; t < targets->size(); ++t)
        attributes((*targets)[t], p / "targets" / t, false);
    }
  }
  weights_member(m, at, "weights");
}

void Checker::skin(const json& s, const Pointer& at) {
  indices(need(s, at, "joints"), at / "joints", "nodes");
  index_member(s, at, "inverseBindMatrices", "accessors");
  index_member(s, at, "skeleton", "nodes");
}

void Checker::node(const json& n, const Pointer& at) {
  index_member(n, at, "camera", "cameras");
  index_member(n, at, "mesh", "meshes");
  index_member(n, at, "skin", "skins");
  if (const json* c = has(n, at, "children")) indices(*c, at / "children", "nodes");
  numbers_member(n, at, "matrix", 16, kAnyNumber);
  numbers_member(n, at, "translation", 3, kAnyNumber);
  numbers_member(n, at, "rotation", 4, kSignedUnit);
  numbers_member(n, at, "scale", 3, kAnyNumber);
  if (has(n, at, "matrix"))
    for (const char* trs : {"translation", "rotation", "scale"})
      if (has(n, at, trs))
        fail(at / "matrix",
             std::string("is given with ") + trs + " (a node has a matrix or TRS, not both)");
  weights_member(n, at, "weights");
  for (const char* key : {"skin", "weights"})
    if (has(n, at, key) && !has(n, at, "mesh")) fail(at / key, "is given without a mesh");
  if (const json* x = extension(n, at, "KHR_lights_punctual"))
    index_member(*x, at / "extensions" / "KHR_lights_punctual", "light", "lights", true);
  if (const json* x = extension(n, at, "EXT_mesh_gpu_instancing")) {
    const Pointer p = at / "extensions" / "EXT_mesh_gpu_instancing";
    attributes(need(*x, p, "attributes"), p / "attributes", true);
  }
}

void Checker::scene(const json& s, const Pointer& at) {
  if (const json* nodes = has(s, at, "nodes")) indices(*nodes, at / "nodes", "nodes");
}

void Checker::light(const json& l, const Pointer& at) {
  // A type this version does not know (the validator warns) is left to the loader, which
  // skips the light with a warning.
  const json& type = need(l, at, "type");
  if (type.is_string() && type != "directional" && type != "point" && type != "spot") return;
  enum_string(type, at / "type", {"directional", "point", "spot"});
  numbers_member(l, at, "color", 3, kUnit);
  number_member(l, at, "intensity", kNonNegative);
  number_member(l, at, "range", kPositive);
  if (const json* spot = has(l, at, "spot")) {
    const Pointer sp = at / "spot";
    property(*spot, sp);
    double inner = 0.0, outer = kPi / 4;  // the defaults
    if (const json* v = has(*spot, sp, "innerConeAngle"))
      inner = number(*v, sp / "innerConeAngle", kInnerCone);
    if (const json* v = has(*spot, sp, "outerConeAngle"))
      outer = number(*v, sp / "outerConeAngle", kOuterCone);
    if (!(inner < outer))
      fail(sp / "innerConeAngle", "is not less than outerConeAngle (" + std::to_string(inner) +
                                      " >= " + std::to_string(outer) + ")");
  }
}

void Checker::hierarchy() const {
  const size_t n = count("nodes");
  if (n == 0) return;
  const json& nodes = root_.at("nodes");
  std::vector<int64_t> parent(n, -1);
  std::vector<size_t> slot(n, 0);  // where in its parent's children
  for (size_t i = 0; i < n; ++i) {
    auto children = nodes[i].find("children");
    if (children == nodes[i].end()) continue;
    for (size_t k = 0; k < children->size(); ++k) {
      const auto c = (*children)[k].get<size_t>();
      if (parent[c] >= 0)
        fail(Pointer() / "nodes" / i / "children" / k,
             "node " + str(int64_t(c)) + " is already a child of node " + str(parent[c]) +
                 " (a node has one parent at most)");
      parent[c] = int64_t(i), slot[c] = k;
    }
  }
  // With one parent each, a cycle is a loop of parent links: walk up from every node.
  std::vector<uint8_t> state(n, 0);  // 0 not seen, 1 on the current walk, 2 leads to a root
  std::vector<size_t> walk;
  for (size_t s = 0; s < n; ++s) {
    walk.clear();
    int64_t v = int64_t(s);
    while (v >= 0 && state[size_t(v)] == 0) {
      state[size_t(v)] = 1;
      walk.push_back(size_t(v));
      v = parent[size_t(v)];
    }
    if (v >= 0 && state[size_t(v)] == 1)
      fail(Pointer() / "nodes" / size_t(parent[size_t(v)]) / "children" / slot[size_t(v)],
           "node " + str(v) + " is its own ancestor (a cycle)");
    for (size_t w : walk) state[w] = 2;
  }
  const size_t scenes = count("scenes");
  for (size_t s = 0; s < scenes; ++s) {
    const json& scene = root_.at("scenes")[s];
    auto roots = scene.find("nodes");
    if (roots == scene.end()) continue;
    for (size_t k = 0; k < roots->size(); ++k)
      if (const auto r = (*roots)[k].get<size_t>(); parent[r] >= 0)
        fail(Pointer() / "scenes" / s / "nodes" / k,
             "node " + str(int64_t(r)) + " is not a root node (it is a child of node " +
                 str(parent[r]) + ")");
  }
}

}  // namespace dacrt::gltf::schema
