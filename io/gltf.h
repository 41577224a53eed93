// glTF 2.0 loading (.gltf and .glb) into a Scene. Throws dacrt::Error with a one-line message
// naming the file and the element at fault for anything malformed.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "dacrt/scene/scene.h"

namespace dacrt {

struct GltfOptions {
  int scene = -1;  // which scene of the file; -1 = the file's default scene (or scene 0)
  // KHR_materials_variants: the variant whose materials the primitives take; empty: their own.
  // A name the file does not have is a SettingError naming those it has.
  std::string variant{};
  // The time in seconds the file's animations are evaluated at (those `animation` chooses, each
  // held at its ends); none: the rest pose (the nodes as the file gives them, morph weights their
  // defaults: the node's, else the mesh's, else 0). A file without a camera is framed on its rest
  // pose at every time, so that the frames of a sequence share one view.
  std::optional<double> time{};
  // Which of the file's animations play: empty, the first (animation 0); "all", every one at once
  // (a target that several animate takes the last one's value); digits, the animation of that
  // index; anything else, the animation of that name (the first of equal names). An index the
  // file lacks or an unknown name is a SettingError naming the animations it has.
  std::string animation{};
};

// One of a file's animations as `dacrt info` lists it.
struct AnimationSummary {
  std::string name;            // as the file names it (may be empty)
  double end = 0.0;            // its last keyframe time, in seconds
  bool plays = false;          // GltfOptions::animation chose it
  std::vector<size_t> shares;  // the other animations that animate one of its targets too
};

Scene load_gltf(const std::string& path, const GltfOptions& options = {});
// The same from a file's bytes in memory (the fuzzer's entry point); `path` names them in
// messages and is where external buffers are looked for.
Scene load_gltf_memory(const std::string& path, const unsigned char* data, size_t size,
                       const GltfOptions& options = {});

// A glTF file read once (its model and checked animations are kept) whose scene can then be
// posed at other times without reading the file again: the frames of an animation.
class GltfAnimation {
 public:
  // Reads the file; throws Error as load_gltf does. `poses`: the scene will be posed, so the
  // first load keeps what posing reads (see pose()); false for a file loaded once (load_gltf, a
  // render of one frame), which then keeps no more than a load needs.
  GltfAnimation(const std::string& path, const GltfOptions& options = {}, bool poses = true);
  ~GltfAnimation();
  // The whole scene at options.time (load_gltf's).
  Scene load() const;
  // Re-makes `scene` (which load() made) at `time`, bit for bit as load() would make it at that
  // time. It replaces these members with new arrays (none is rewritten in place: a triangle of
  // zero area at one time is dropped, so their count changes): geometry (the triangles in the
  // file's order, each with its material index), degenerate_triangles, normals, texcoords,
  // colors, tangents, cameras, cameras_from_file, view_bounds and lights. Everything else stays
  // as load() made it and is never touched: materials, textures, images, variants, the counts,
  // files and `ignored`.
  // Nothing of the file is decoded or checked again: the first load (with `poses`) keeps each
  // primitive's corners and its vertices' attributes as its accessors gave them (after Draco or
  // meshopt decompression, sparse patches and normalisation, in the mesh's space), the skins'
  // inverse bind matrices, EXT_mesh_gpu_instancing's transforms and the materials; a pose
  // evaluates the animations at `time` (node transforms, joint matrices, morph weights) and
  // morphs, skins and places copies of those. The one read a pose may add: a morph target of
  // weight 0 until then is read the first time a pose weighs it, then kept. Without `poses`,
  // a pose reads the accessors again (their decompressed data is kept all the same).
  // load() and pose() take turns on one GltfAnimation.
  void pose(double time, Scene& scene) const;
  // The last keyframe time of the animations that play (0 without any).
  double end() const;
  // Every animation of the file, whether it plays or not.
  size_t animation_count() const;
  const std::vector<AnimationSummary>& animations() const;
  // What GltfOptions::animation chose, as match keys and messages say it: "none" (a file without
  // animations), "all", or the index.
  std::string animation_choice() const;
  // The accessors read and the bufferViews and primitives decompressed so far, for tests that
  // hold a pose to reading nothing.
  uint64_t decodes() const;

 private:
  struct Impl;
  friend Scene load_gltf_memory(const std::string&, const unsigned char*, size_t,
                                const GltfOptions&);
  std::unique_ptr<Impl> impl_;
};

}  // namespace dacrt
