// glTF animations: the file's samplers and channels read once into plain data (checked against
// the spec: times finite, non-negative and strictly increasing, output counts and types per
// target path, targets that exist), then evaluated at a time t into a pose: each animated node's
// translation, rotation, scale and morph weights (STEP, LINEAR with quaternion slerp,
// CUBICSPLINE Hermite splines), every animation of the file playing at once, each held at its
// ends outside its keyframes.
#include "dacrt/io/gltf/internal.h"
#include "dacrt/util/text.h"

namespace dacrt::gltf {
namespace {

// The node's morph target count: its mesh's primitives' (0 without a mesh).
size_t target_count(const tinygltf::Model& model, int node) {
  const int mesh = model.nodes[size_t(node)].mesh;
  if (mesh < 0 || size_t(mesh) >= model.meshes.size()) return 0;
  const auto& primitives = model.meshes[size_t(mesh)].primitives;
  return primitives.empty() ? 0 : primitives[0].targets.size();
}

size_t components_of(AnimationPath path) {
  switch (path) {
    case AnimationPath::translation:
    case AnimationPath::scale:
      return 3;
    case AnimationPath::rotation:
      return 4;
    case AnimationPath::weights:
      return 1;
  }
  return 0;
}

// Output accessor types the spec allows per path, besides FLOAT (normalised integers).
IntegerTypes output_types(AnimationPath path) {
  if (path == AnimationPath::rotation || path == AnimationPath::weights)
    return {kByte | kUnsignedByte | kShort | kUnsignedShort, 0};
  return {};
}

// The spec's slerp (Appendix: interpolation): along the shorter arc, linear when a and b are
// almost the same.
glm::dquat slerp(glm::dquat a, glm::dquat b, double s) {
  double d = glm::dot(a, b);
  if (d < 0.0) b = -b, d = -d;
  if (d > 0.9995) return glm::normalize(a * (1.0 - s) + b * s);
  const double theta = std::acos(std::min(d, 1.0)), sin_theta = std::sin(theta);
  return a * (std::sin((1.0 - s) * theta) / sin_theta) + b * (std::sin(s * theta) / sin_theta);
}

}  // namespace

// Keyframe values (floats) in all of a file's samplers, at most: they are kept for the load and
// every frame (an accessor without a bufferView could ask for 2^28 zeros at no cost in the file).
constexpr uint64_t kMaxAnimationFloats = uint64_t(1) << 26;

namespace {

// The channels of animation `anim` (`at` names it) into `animation`, checked; returns the path
// each sampler serves (-1: none).
std::vector<int> read_channels(const Gltf& gltf, const tinygltf::Animation& anim,
                               const std::string& at, Animation& animation) {
  const tinygltf::Model& model = gltf.model;
  std::vector<int> sampler_path(anim.samplers.size(), -1);
  std::set<std::pair<int, int>> targets;  // (node, path): one channel each
  for (size_t c = 0; c < anim.channels.size(); ++c) {
    const tinygltf::AnimationChannel& ch = anim.channels[c];
    const std::string where = at + ".channels[" + str(c) + "]";
    AnimationPath path;
    if (ch.target_path == "translation")
      path = AnimationPath::translation;
    else if (ch.target_path == "rotation")
      path = AnimationPath::rotation;
    else if (ch.target_path == "scale")
      path = AnimationPath::scale;
    else if (ch.target_path == "weights")
      path = AnimationPath::weights;
    else if (ch.target_path == "pointer") {
      print_message("warning: " + gltf.path + ": " + where +
                    " targets a KHR_animation_pointer pointer, which this version does not "
                    "read (the channel is skipped)");
      continue;
    } else
      gltf.fail(where + ".target.path: \"" + ch.target_path.substr(0, 40) +
                "\" is not translation, rotation, scale or weights");
    if (ch.sampler < 0 || size_t(ch.sampler) >= anim.samplers.size())
      gltf.fail(where + ".sampler: sampler " + str(ch.sampler) + " does not exist (" +
                str(anim.samplers.size()) + " samplers)");
    if (ch.target_node < 0 || size_t(ch.target_node) >= model.nodes.size())
      gltf.fail(where + ".target.node: node " + str(ch.target_node) + " does not exist (" +
                str(model.nodes.size()) + " nodes)");
    const tinygltf::Node& node = model.nodes[size_t(ch.target_node)];
    if (!node.matrix.empty() && path != AnimationPath::weights)
      gltf.fail(where + ".target.node: node " + str(ch.target_node) +
                " has a matrix (animated nodes must use translation, rotation and scale)");
    if (path == AnimationPath::weights && target_count(model, ch.target_node) == 0)
      gltf.fail(where + ".target.node: node " + str(ch.target_node) +
                " has no morph targets for a weights channel");
    if (!targets.insert({ch.target_node, int(path)}).second)
      gltf.fail(where + ": node " + str(ch.target_node) + " " + ch.target_path +
                " is the target of an earlier channel too");
    int& served = sampler_path[size_t(ch.sampler)];
    const size_t weights = target_count(model, ch.target_node);
    // A sampler serves one kind of output: its layout depends on it (and, for weights, on the
    // target count).
    const int kind = path == AnimationPath::weights ? 4 + int(weights) : int(path);
    if (served != -1 && served != kind)
      gltf.fail(where + ": sampler " + str(ch.sampler) +
                " serves channels of different output layouts");
    served = kind;
    animation.channels.push_back({uint32_t(ch.sampler), uint32_t(ch.target_node), path,
                                  path == AnimationPath::weights ? weights : components_of(path)});
  }
  return sampler_path;
}

// Sampler `in` (`where` names it) into `sampler`, checked and, when a channel uses it (`served`,
// the path it serves), its keyframes read; `floats` counts the file's keyframe numbers.
void read_sampler(const Gltf& gltf, const tinygltf::AnimationSampler& in, const std::string& where,
                  int served, uint64_t& floats, AnimationSampler& sampler) {
  const tinygltf::Model& model = gltf.model;
  if (in.interpolation == "STEP")
    sampler.interpolation = Interpolation::step;
  else if (in.interpolation == "CUBICSPLINE")
    sampler.interpolation = Interpolation::cubic;
  else if (in.interpolation == "LINEAR" || in.interpolation.empty())
    sampler.interpolation = Interpolation::linear;
  else
    gltf.fail(where + ".interpolation: \"" + in.interpolation.substr(0, 40) +
              "\" is not LINEAR, STEP or CUBICSPLINE");
  if (served == -1) return;  // no channel uses it: not read
  const auto path = AnimationPath(std::min(served, 3));
  sampler.components = path == AnimationPath::weights ? size_t(served - 4) : components_of(path);
  // Input: FLOAT SCALAR times.
  if (in.input < 0 || size_t(in.input) >= model.accessors.size())
    gltf.fail(where + ".input: accessor " + str(in.input) + " does not exist");
  if (model.accessors[size_t(in.input)].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT ||
      model.accessors[size_t(in.input)].type != TINYGLTF_TYPE_SCALAR)
    gltf.fail(where + ".input: accessor " + str(in.input) + " must be FLOAT SCALAR");
  // Bounded before anything is read: the times and (at most 3 × 4 × targets a keyframe) the
  // values.
  const uint64_t keys = accessor_count(gltf, in.input, where + ".input");
  if (in.output < 0 || size_t(in.output) >= model.accessors.size())
    gltf.fail(where + ".output: accessor " + str(in.output) + " does not exist");
  floats += keys + uint64_t(accessor_count(gltf, in.output, where + ".output")) * 4;
  if (floats > kMaxAnimationFloats)
    gltf.fail(where + " brings the file's keyframes to more than " + str(kMaxAnimationFloats) +
              " numbers");
  const std::vector<glm::vec4> times = read_floats(gltf, in.input, where + ".input", 1, 1, {}, 0.f);
  if (times.empty()) gltf.fail(where + ".input: accessor " + str(in.input) + " is empty");
  sampler.input.resize(times.size());
  for (size_t k = 0; k < times.size(); ++k) {
    const float t = times[k].x;
    if (!std::isfinite(t) || t < 0.f || (k > 0 && !(t > sampler.input[k - 1])))
      gltf.fail(where + ".input: time " + str(k) + " (" + num(t) +
                ") is not finite, non-negative and greater than the one before");
    sampler.input[k] = t;
  }
  const size_t per_key = sampler.interpolation == Interpolation::cubic ? 3 : 1;
  if (per_key == 3 && times.size() < 2)
    gltf.fail(where + ": CUBICSPLINE needs at least 2 keyframes, not " + str(times.size()));
  // Output: components per element as the path says; weights are SCALARs, one per target.
  const int per_element = path == AnimationPath::weights ? 1 : int(components_of(path));
  if (in.output < 0 || size_t(in.output) >= model.accessors.size())
    gltf.fail(where + ".output: accessor " + str(in.output) + " does not exist");
  const std::vector<glm::vec4> values = read_floats(gltf, in.output, where + ".output", per_element,
                                                    per_element, output_types(path), 0.f);
  const size_t elements_per_key =
      per_key * (path == AnimationPath::weights ? sampler.components : size_t(1));
  if (values.size() != times.size() * elements_per_key)
    gltf.fail(where + ".output: accessor " + str(in.output) + " has " + str(values.size()) +
              " elements, not " + str(times.size() * elements_per_key) + " (" + str(times.size()) +
              " keyframes × " + str(elements_per_key) + ")");
  sampler.output.reserve(values.size() * size_t(per_element));
  for (size_t k = 0; k < values.size(); ++k)
    for (int c = 0; c < per_element; ++c) {
      if (!std::isfinite(values[k][c]))
        gltf.fail(where + ".output: element " + str(k) + " is not finite");
      sampler.output.push_back(values[k][c]);
    }
}

}  // namespace

std::vector<Animation> read_animations(const Gltf& gltf) {
  const tinygltf::Model& model = gltf.model;
  uint64_t floats = 0;  // read so far, in every sampler
  std::vector<Animation> out;
  out.reserve(model.animations.size());
  for (size_t a = 0; a < model.animations.size(); ++a) {
    const tinygltf::Animation& anim = model.animations[a];
    const std::string at = "animations[" + str(a) + "]";
    Animation animation;
    // The path each sampler serves (samplers are read for their first channel's path).
    const std::vector<int> sampler_path = read_channels(gltf, anim, at, animation);
    animation.samplers.resize(anim.samplers.size());
    for (size_t s = 0; s < anim.samplers.size(); ++s)
      read_sampler(gltf, anim.samplers[s], at + ".samplers[" + str(s) + "]", sampler_path[s],
                   floats, animation.samplers[s]);
    out.push_back(std::move(animation));
  }
  return out;
}

void sample(const AnimationSampler& s, double t, bool rotation, float* out) {
  const size_t n = s.input.size(), m = s.components;
  const size_t per_key = s.interpolation == Interpolation::cubic ? 3 : 1;
  // The value of keyframe k (the middle of in-tangent, value, out-tangent for cubic).
  auto value = [&](size_t k, size_t c) {
    return double(s.output[(per_key * k + per_key / 2) * m + c]);
  };
  auto finish = [&](const double* v) {
    if (rotation) {
      glm::dquat q(v[3], v[0], v[1], v[2]);
      const double len = glm::length(q);
      q = len > 0.0 ? q / len : glm::dquat(1.0, 0.0, 0.0, 0.0);
      out[0] = float(q.x), out[1] = float(q.y), out[2] = float(q.z), out[3] = float(q.w);
    } else {
      for (size_t c = 0; c < m; ++c) out[c] = float(v[c]);
    }
  };
  std::vector<double> v(m);
  // Outside the keyframes (and with one keyframe) the nearest keyframe's value holds.
  if (n == 1 || t <= double(s.input.front()) || t >= double(s.input.back())) {
    const size_t k = n == 1 || t <= double(s.input.front()) ? 0 : n - 1;
    for (size_t c = 0; c < m; ++c) v[c] = value(k, c);
    return finish(v.data());
  }
  // The keyframe k with input[k] <= t < input[k + 1].
  const size_t k =
      size_t(std::upper_bound(s.input.begin(), s.input.end(), float(t)) - s.input.begin()) - 1;
  const size_t k0 = std::min(k, n - 2);
  const double t0 = s.input[k0], t1 = s.input[k0 + 1], td = t1 - t0;
  const double u = std::clamp((t - t0) / td, 0.0, 1.0);
  switch (s.interpolation) {
    case Interpolation::step:
      for (size_t c = 0; c < m; ++c) v[c] = value(k0, c);
      break;
    case Interpolation::linear:
      if (rotation) {
        const glm::dquat q = slerp(
            glm::dquat(value(k0, 3), value(k0, 0), value(k0, 1), value(k0, 2)),
            glm::dquat(value(k0 + 1, 3), value(k0 + 1, 0), value(k0 + 1, 1), value(k0 + 1, 2)), u);
        v = {q.x, q.y, q.z, q.w};
      } else {
        for (size_t c = 0; c < m; ++c) v[c] = (1.0 - u) * value(k0, c) + u * value(k0 + 1, c);
      }
      break;
    case Interpolation::cubic: {
      // The spec's Hermite spline: v_k, its out-tangent b_k, v_k+1 and its in-tangent a_k+1,
      // the tangents scaled by the keyframes' spacing.
      const double u2 = u * u, u3 = u2 * u;
      const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
                   h11 = u3 - u2;
      for (size_t c = 0; c < m; ++c) {
        const double vk = s.output[(3 * k0 + 1) * m + c], bk = s.output[(3 * k0 + 2) * m + c];
        const double vk1 = s.output[(3 * (k0 + 1) + 1) * m + c],
                     ak1 = s.output[(3 * (k0 + 1)) * m + c];
        v[c] = h00 * vk + h10 * td * bk + h01 * vk1 + h11 * td * ak1;
      }
      break;
    }
  }
  finish(v.data());
}

std::vector<NodePose> pose_at(const std::vector<Animation>& animations, size_t nodes, double t) {
  std::vector<NodePose> pose(nodes);
  for (const Animation& a : animations)
    for (const AnimationChannel& ch : a.channels) {
      const AnimationSampler& s = a.samplers[ch.sampler];
      NodePose& p = pose[ch.node];
      std::vector<float> v(ch.components);
      sample(s, t, ch.path == AnimationPath::rotation, v.data());
      switch (ch.path) {
        case AnimationPath::translation:
          p.translation = glm::dvec3(v[0], v[1], v[2]);
          break;
        case AnimationPath::scale:
          p.scale = glm::dvec3(v[0], v[1], v[2]);
          break;
        case AnimationPath::rotation:
          p.rotation = glm::dquat(v[3], v[0], v[1], v[2]);
          break;
        case AnimationPath::weights:
          p.weights = std::move(v);
          break;
      }
    }
  return pose;
}

namespace {

// "animation 2 ("run")", or "animation 2" for an unnamed one.
std::string animation_name(const tinygltf::Model& model, size_t a) {
  const std::string& name = model.animations[a].name;
  return str(a) + (name.empty() ? "" : " (\"" + one_line(name.substr(0, 60)) + "\")");
}

// "0 ("walk"), 1 ("run")", at most the first 20.
std::string animation_list(const tinygltf::Model& model, const std::vector<size_t>& which) {
  std::string out;
  for (size_t k = 0; k < which.size() && k < 20; ++k)
    out += (k ? ", " : "") + animation_name(model, which[k]);
  if (which.size() > 20) out += ", ... (" + str(which.size()) + " in all)";
  return out;
}

}  // namespace

std::vector<size_t> choose_animations(const Gltf& gltf, const std::string& choice) {
  const size_t count = gltf.model.animations.size();
  std::vector<size_t> all(count);
  for (size_t a = 0; a < count; ++a) all[a] = a;
  if (choice == "all") return all;
  if (choice.empty()) return count ? std::vector<size_t>{0} : std::vector<size_t>{};
  const std::string has =
      count ? "it has " + str(count) + ": " + animation_list(gltf.model, all) : "it has none";
  // Digits are an index (so that every animation can be chosen, whatever its name: "all" too).
  if (choice.size() <= 9 &&
      std::all_of(choice.begin(), choice.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    const size_t index = std::stoul(choice);
    if (index < count) return {index};
    throw SettingError(gltf.path + ": --animation " + choice +
                       " is not an animation index of the file (" + has + ")");
  }
  for (size_t a = 0; a < count; ++a)
    if (gltf.model.animations[a].name == choice) return {a};
  throw SettingError(gltf.path + ": --animation \"" + one_line(choice.substr(0, 100)) +
                     "\" is not an animation of the file (" + has + ")");
}

std::vector<AnimationSummary> summarize_animations(const Gltf& gltf,
                                                   const std::vector<Animation>& animations,
                                                   const std::vector<size_t>& chosen) {
  std::vector<AnimationSummary> out(animations.size());
  // Each target (node, path) and the animations that animate it.
  std::map<std::pair<uint32_t, int>, std::vector<size_t>> by_target;
  for (size_t a = 0; a < animations.size(); ++a) {
    out[a].name = gltf.model.animations[a].name;
    for (const AnimationChannel& ch : animations[a].channels) {
      out[a].end = std::max(out[a].end, double(animations[a].samplers[ch.sampler].input.back()));
      std::vector<size_t>& list = by_target[{ch.node, int(ch.path)}];
      if (list.empty() || list.back() != a) list.push_back(a);
    }
  }
  for (size_t a : chosen) out[a].plays = true;
  for (const auto& [target, list] : by_target)
    for (size_t a : list)
      for (size_t b : list)
        if (a != b) out[a].shares.push_back(b);
  for (AnimationSummary& s : out) {
    std::sort(s.shares.begin(), s.shares.end());
    s.shares.erase(std::unique(s.shares.begin(), s.shares.end()), s.shares.end());
  }
  return out;
}

std::string animation_note(const Gltf& gltf, const std::vector<AnimationSummary>& summaries,
                           const std::string& choice) {
  const std::string how = " (--animation NAME|INDEX|all chooses)";
  if (choice == "all") {
    std::vector<size_t> sharing;
    for (size_t a = 0; a < summaries.size(); ++a)
      if (!summaries[a].shares.empty()) sharing.push_back(a);
    if (sharing.empty()) return "";
    return "note: " + gltf.path + ": every animation plays (--animation all), and animations " +
           animation_list(gltf.model, sharing) +
           " animate the same targets: a target they share takes the last one's value" + how;
  }
  if (!choice.empty() || summaries.size() < 2) return "";
  std::vector<size_t> others;
  for (size_t a = 1; a < summaries.size(); ++a) others.push_back(a);
  const std::vector<size_t>& shares = summaries[0].shares;
  std::string text = "note: " + gltf.path + ": animation " + animation_name(gltf.model, 0) +
                     " plays, not " + animation_list(gltf.model, others);
  if (!shares.empty())
    text += " (of which " + animation_list(gltf.model, shares) + " animate" +
            (shares.size() == 1 ? "s" : "") + " the same targets)";
  return text + how;
}

double animation_end(const std::vector<Animation>& animations) {
  double end = 0.0;
  for (const Animation& a : animations)
    for (const AnimationChannel& ch : a.channels)
      end = std::max(end, double(a.samplers[ch.sampler].input.back()));
  return end;
}

}  // namespace dacrt::gltf
