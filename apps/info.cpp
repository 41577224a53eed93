// `dacrt info SCENE`: what a scene holds, as a user reads it before a render.
#include "apps/info.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "dacrt/io/gltf.h"
#include "dacrt/render/render_job.h"
#include "dacrt/render/request.h"
#include "dacrt/scene/camera.h"
#include "dacrt/scene/scene.h"
#include "dacrt/util/error.h"

namespace dacrt {

namespace {

// The geometry, materials and lights.
void print_contents(const std::string& path, const Scene& scene, const MaterialCounts& counts) {
  const Geometry& g = scene.geometry;
  std::printf("scene      %s\n", path.c_str());
  std::printf("triangles  %zu", g.size());
  if (scene.degenerate_triangles > 0)
    std::printf(" (%zu more of zero area dropped: no ray can hit them)",
                scene.degenerate_triangles);
  std::printf("\n");
  std::printf("meshes     %zu (%zu triangle primitives, %zu nodes)\n", scene.mesh_count,
              scene.primitive_count, scene.node_count);
  std::printf(
      "materials  %zu (%zu emissive, %zu textured, %zu alpha MASK, %zu alpha BLEND, %zu "
      "transmissive)\n",
      scene.materials.size(), counts.emissive, counts.textured, counts.masked, counts.blended,
      counts.transmissive);
  size_t punctual[3] = {0, 0, 0};
  for (const PunctualLight& l : scene.lights) ++punctual[size_t(l.type)];
  std::printf(
      "lights     %zu emissive triangles, %zu punctual (%zu point, %zu spot, %zu directional)\n",
      counts.emissive_triangles, scene.lights.size(), punctual[0], punctual[1], punctual[2]);
}

// The images, the vertex attributes, what is not rendered as the file asks, the variants.
void print_inputs(const Scene& scene) {
  size_t image_bytes = 0, images = 0;
  for (const TextureImage& i : scene.images) {
    images += i.width > 0;
    image_bytes += i.rgba8.size() + 2 * i.rgba16.size();
  }
  std::printf("images     %zu decoded (%.1f MB), of %zu in the file\n", images,
              double(image_bytes) / 1e6, scene.images.size());
  std::string attributes = "POSITION";
  if (!scene.normals.empty()) attributes += ", NORMAL";
  for (size_t slot = 0; slot < scene.texcoords.size(); ++slot)
    if (!scene.texcoords[slot].empty())
      attributes += ", TEXCOORD_" + std::to_string(scene.texcoord_sets[slot]);
  if (!scene.colors.empty()) attributes += ", COLOR_0";
  if (!scene.tangents.empty()) attributes += ", tangents (from the file or generated)";
  std::printf("attributes %s\n", attributes.c_str());
  const Scene::Ignored& ig = scene.ignored;
  if (ig.ktx2_textures)
    std::printf("ignores    %zu KTX2 textures (rendered from their fallback images)\n",
                ig.ktx2_textures);
  if (ig.sourceless_textures || ig.unknown_lights)
    std::printf("skips      %zu textures without a source image, %zu lights of unknown types\n",
                ig.sourceless_textures, ig.unknown_lights);
  if (ig.untangented_anisotropic)
    std::printf("arbitrary  %zu anisotropic primitives without tangents (no TANGENT, no uvs)\n",
                ig.untangented_anisotropic);
  if (ig.unmorphed_primitives)
    std::printf("unmorphed  %zu primitives' TEXCOORD or COLOR morph targets (base values kept)\n",
                ig.unmorphed_primitives);
  if (!ig.extensions.empty())
    std::printf("not read   %s\n", one_line(ig.unread_extensions()).c_str());
  if (ig.occlusion_textures)
    std::printf(
        "occlusion  %zu materials' occlusion textures left unread (a path tracer computes "
        "occlusion)\n",
        ig.occlusion_textures);
  if (!scene.variants.empty()) {
    std::string names;
    for (const std::string& v : scene.variants) names += (names.empty() ? "" : ", ") + v;
    std::printf("variants   %zu (render --variant NAME): %s\n", scene.variants.size(),
                one_line(names).c_str());
  }
}

// The animations and which play.
void print_animations(const GltfAnimation& file) {
  if (!file.animation_count()) return;
  std::printf(
      "animation  %zu animations, keyframes to %g s (render --animation NAME|INDEX|all, --time "
      "T, --frames A:B --fps F)\n",
      file.animation_count(), file.end());
  const std::vector<AnimationSummary>& all = file.animations();
  for (size_t a = 0; a < all.size() && a < 1000; ++a) {
    std::string shares;
    for (size_t b : all[a].shares) shares += (shares.empty() ? "" : ", ") + std::to_string(b);
    std::printf(
        "  animation %zu%s: keyframes to %g s%s%s\n", a,
        all[a].name.empty() ? "" : (" \"" + one_line(all[a].name.substr(0, 200)) + "\"").c_str(),
        all[a].end, all[a].plays ? ", plays" : "",
        shares.empty() ? "" : (", animates targets of " + shares + " too").c_str());
  }
  if (all.size() > 1000) std::printf("  ... (%zu in all)\n", all.size());
}

// The cameras, each as the render flags of its view, and the bounds.
void print_cameras(const Scene& scene, const Box& b) {
  std::printf("cameras    %zu%s\n", scene.cameras_from_file,
              scene.cameras_from_file ? "" : " (renders frame the scene's bounds)");
  for (size_t c = 0; c < scene.cameras.size(); ++c) {
    const Camera& cam = scene.cameras[c];
    glm::vec3 p = cam.position();
    const std::string view = cam.orthographic
                                 ? "orthographic, height " + std::to_string(2.f * cam.ymag)
                                 : "yfov " + std::to_string(cam.yfov * 180.0 / M_PI) + "°";
    std::printf("  camera %zu %s: position (%g, %g, %g), %s, aspect %s\n", c,
                cam.name.empty() ? "(unnamed)" : cam.name.c_str(), p.x, p.y, p.z, view.c_str(),
                cam.aspect > 0 ? std::to_string(cam.aspect).c_str() : "from image");
    // The same view as render flags, ready to copy (an orthographic camera's view is perspective
    // with them, as --fov makes it).
    std::printf("    %s", camera_flags(cam, b.empty() ? glm::vec3(0.f) : b.center()).c_str());
    std::printf("\n");
  }
  if (b.empty())
    std::printf("bounds     empty\n");
  else
    std::printf("bounds     (%g, %g, %g) to (%g, %g, %g)\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y,
                b.hi.z);
}

// The lighting a render uses unless --environment says otherwise (render/render_job.h).
void print_lighting(const Scene& scene) {
  std::printf("lighting   %s\n", default_lighting(scene, 0).what.c_str());
}

// The work a render of this scene skips.
void print_skips(const Scene& scene, const MaterialCounts& counts) {
  std::string skips;
  auto skip = [&](bool yes, const char* what) {
    if (yes) skips += (skips.empty() ? "" : "; ") + std::string(what);
  };
  skip(!counts.emissive_triangles && scene.lights.empty(),
       "shadow rays (no emitters and no lights; an environment brings them back where it is "
       "sampled: --environment FILE.exr, or a uniform one in an open scene)");
  for (const std::string& what : scene.unused_work()) skip(true, what.c_str());
  std::printf("skips      %s\n", skips.empty() ? "nothing" : skips.c_str());
}

}  // namespace

int info_main(const std::vector<std::string>& args) {
  if (args.size() == 1 && (args[0] == "-h" || args[0] == "--help")) {
    std::puts("Usage: dacrt info SCENE [--scene INDEX] [--animation NAME|INDEX|all]");
    return 0;
  }
  GltfOptions options;
  const char* usage = "info needs one SCENE, and optionally --scene INDEX and --animation NAME";
  if (args.empty()) throw UsageError(usage);
  if (args[0].size() > 1 && args[0][0] == '-') throw UsageError("info: unknown option " + args[0]);
  for (size_t i = 1; i < args.size(); i += 2) {
    if (args[i] != "--scene" && args[i] != "--animation")
      throw UsageError(args[i].size() > 1 && args[i][0] == '-' ? "info: unknown option " + args[i]
                                                               : std::string(usage));
    if (i + 1 >= args.size()) throw UsageError(args[i] + " needs a value");
    if (args[i] == "--scene")
      options.scene = int(parse_int(args[i], args[i + 1], 0, 1 << 20));
    else if ((options.animation = args[i + 1]).empty())
      throw UsageError("--animation needs a name, an index or all");
  }
  const GltfAnimation file(args[0], options, false);  // loaded once, never posed
  const Scene scene = file.load();
  const MaterialCounts counts = count_materials(scene);
  print_contents(args[0], scene, counts);
  print_inputs(scene);
  print_animations(file);
  print_cameras(scene, scene.bounds());
  print_lighting(scene);
  print_skips(scene, counts);
  return 0;
}

}  // namespace dacrt
