// glTF skins: the joint matrices of a skin (each joint's world transform times its inverse bind
// matrix) and each vertex's skinning matrix, the JOINTS_n / WEIGHTS_n sets' weighted sum of them,
// all checked against the spec (joints that exist, FLOAT MAT4 inverse bind matrices, joint indices
// within the skin, weights' types, sets in pairs).
#include "dacrt/io/gltf/internal.h"

namespace dacrt::gltf {

namespace {

// Skin `skin`'s inverse bind matrices, one per joint (identity when the skin has none), checked.
std::vector<glm::dmat4> inverse_binds(const Gltf& gltf, int skin) {
  const tinygltf::Skin& s = gltf.model.skins[size_t(skin)];
  const std::string at = "skins[" + str(skin) + "]";
  if (s.joints.empty()) gltf.fail(at + ".joints is empty");
  for (size_t j = 0; j < s.joints.size(); ++j)
    if (s.joints[j] < 0 || size_t(s.joints[j]) >= gltf.model.nodes.size())
      gltf.fail(at + ".joints[" + str(j) + "]: node " + str(s.joints[j]) + " does not exist (" +
                str(gltf.model.nodes.size()) + " nodes)");
  std::vector<glm::dmat4> out(s.joints.size(), glm::dmat4(1.0));
  if (s.inverseBindMatrices == -1) return out;
  const int a = s.inverseBindMatrices;
  const std::string role = at + ".inverseBindMatrices";
  if (a < 0 || size_t(a) >= gltf.model.accessors.size())
    gltf.fail(role + ": accessor " + str(a) + " does not exist");
  const tinygltf::Accessor& acc = gltf.model.accessors[size_t(a)];
  if (acc.type != TINYGLTF_TYPE_MAT4 || acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
    gltf.fail(role + ": accessor " + str(a) + " must be FLOAT MAT4");
  if (acc.count < s.joints.size())  // the spec: at least one a joint
    gltf.fail(role + ": accessor " + str(a) + " has " + str(acc.count) + " matrices for " +
              str(s.joints.size()) + " joints");
  const std::vector<glm::vec4> columns = read_matrix_columns(gltf, a, role);
  for (size_t j = 0; j < s.joints.size(); ++j)  // those past the joints are not used
    for (int c = 0; c < 4; ++c) {
      const glm::vec4& column = columns[4 * j + size_t(c)];
      if (!finite(glm::vec3(column)) || !std::isfinite(column.w))
        gltf.fail(role + ": matrix " + str(j) + " is not finite");
      out[j][c] = glm::dvec4(column);
    }
  return out;
}

// The same, read once for the loads of a GltfAnimation (Gltf::kept).
std::vector<glm::dmat4> kept_inverse_binds(const Gltf& gltf, int skin) {
  if (!gltf.kept) return inverse_binds(gltf, skin);
  auto known = gltf.kept->inverse_binds.find(skin);
  if (known == gltf.kept->inverse_binds.end())
    known = gltf.kept->inverse_binds.emplace(skin, inverse_binds(gltf, skin)).first;
  return known->second;
}

}  // namespace

void check_skins(const Gltf& gltf) {
  for (size_t s = 0; s < gltf.model.skins.size(); ++s) kept_inverse_binds(gltf, int(s));
}

std::vector<glm::dmat4> joint_matrices(const Gltf& gltf, int skin,
                                       const std::vector<glm::dmat4>& world) {
  std::vector<glm::dmat4> out = kept_inverse_binds(gltf, skin);
  const std::vector<int>& joints = gltf.model.skins[size_t(skin)].joints;
  for (size_t j = 0; j < joints.size(); ++j) out[j] = world[size_t(joints[j])] * out[j];
  return out;
}

std::vector<SkinSet> read_skin_sets(const Gltf& gltf, const tinygltf::Primitive& prim,
                                    const std::string& where, size_t vertex_count, Elements which) {
  // The sets JOINTS_0 / WEIGHTS_0, JOINTS_1 / WEIGHTS_1, ... in pairs, numbered from 0 without
  // gaps (the spec's TEXCOORD-like naming); however many there are, each is bounded by the
  // file's attributes.
  size_t sets = 0;
  for (;; ++sets) {
    const bool j = prim.attributes.count("JOINTS_" + str(sets)) != 0,
               w = prim.attributes.count("WEIGHTS_" + str(sets)) != 0;
    if (j != w)
      gltf.fail(where + ": " + (j ? "JOINTS_" : "WEIGHTS_") + str(sets) + " has no " +
                (j ? "WEIGHTS_" : "JOINTS_") + str(sets));
    if (!j) break;
  }
  for (const auto& [name, accessor] : prim.attributes)
    for (const char* prefix : {"JOINTS_", "WEIGHTS_"})
      if (name.rfind(prefix, 0) == 0) {
        const std::string number = name.substr(std::string(prefix).size());
        if (number.empty() || number.size() > 9 ||
            number.find_first_not_of("0123456789") != std::string::npos ||
            std::stoul(number) >= sets || (number.size() > 1 && number[0] == '0'))
          gltf.fail(where + ": " + name.substr(0, 40) + " is not one of the sets JOINTS_0.." +
                    (sets ? str(sets - 1) : std::string("(none)")) + " in pairs with WEIGHTS_n");
      }
  if (sets == 0) gltf.fail(where + " is skinned (its node has a skin) but has no JOINTS_0");
  std::vector<SkinSet> out(sets);
  for (size_t set = 0; set < sets; ++set) {
    const int ja = prim.attributes.at("JOINTS_" + str(set)),
              wa = prim.attributes.at("WEIGHTS_" + str(set));
    const std::string jrole = "JOINTS_" + str(set) + " of " + where,
                      wrole = "WEIGHTS_" + str(set) + " of " + where;
    for (const auto& [a, role] : {std::pair{ja, jrole}, {wa, wrole}})
      if (accessor_count(gltf, a, role) != vertex_count)
        gltf.fail("accessor " + str(a) + " (" + role + ") has " +
                  str(accessor_count(gltf, a, role)) + " elements but POSITION has " +
                  str(vertex_count));
    // JOINTS: UNSIGNED_BYTE or UNSIGNED_SHORT VEC4, not normalized (read as the integers).
    if (gltf.model.accessors[size_t(ja)].componentType == TINYGLTF_COMPONENT_TYPE_FLOAT)
      gltf.fail("accessor " + str(ja) + " (" + jrole +
                ") must be UNSIGNED_BYTE or UNSIGNED_SHORT VEC4 (it is FLOAT)");
    out[set].joints_accessor = ja, out[set].weights_accessor = wa;
    out[set].joints =
        read_floats(gltf, ja, jrole, 4, 4, {0, kUnsignedByte | kUnsignedShort}, 0.f, which);
    // WEIGHTS: FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT, VEC4.
    out[set].weights =
        read_floats(gltf, wa, wrole, 4, 4, {kUnsignedByte | kUnsignedShort, 0}, 0.f, which);
  }
  return out;
}

std::vector<glm::dmat4> skin_matrices(const Gltf& gltf, const std::vector<SkinSet>& sets,
                                      const std::string& where,
                                      const std::vector<glm::dmat4>& joints, Elements which) {
  const size_t n = sets.empty() ? 0 : sets[0].weights.size();
  std::vector<glm::dmat4> out(n, glm::dmat4(0.0));
  std::vector<double> total(n, 0.0);
  for (size_t set = 0; set < sets.size(); ++set) {
    const int ja = sets[set].joints_accessor, wa = sets[set].weights_accessor;
    const std::string jrole = "JOINTS_" + str(set) + " of " + where,
                      wrole = "WEIGHTS_" + str(set) + " of " + where;
    const std::vector<glm::vec4>& j = sets[set].joints;
    const std::vector<glm::vec4>& w = sets[set].weights;
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 4; ++c) {
        const float weight = w[i][c];
        if (!(weight >= 0.f) || !std::isfinite(weight))
          gltf.fail("accessor " + str(wa) + " (" + wrole + ") element " +
                    str(which ? (*which)[i] : i) + " has a negative or non-finite weight");
        if (weight == 0.f) continue;  // its joint may be anything (the spec: 0 by convention)
        const size_t joint = size_t(j[i][c]);
        if (joint >= joints.size())
          gltf.fail("accessor " + str(ja) + " (" + jrole + ") element " +
                    str(which ? (*which)[i] : i) + " names joint " + str(joint) +
                    ", but the skin has " + str(joints.size()));
        out[i] += double(weight) * joints[joint];
        total[i] += weight;
      }
  }
  // The spec wants each vertex's weights to sum to 1; they are quantised or rounded in files, so
  // the sum is divided out. A vertex without any weight stays where its mesh puts it.
  for (size_t i = 0; i < n; ++i)
    out[i] = total[i] > 0.0 ? out[i] / total[i] : glm::dmat4(1.0);
  return out;
}

}  // namespace dacrt::gltf
