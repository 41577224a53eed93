// The native module `dacrt._dacrt` under the package `dacrt` (python/dacrt/__init__.py, which
// gives its functions their signatures and documentation): scenes loaded once and rendered many
// times, renders as numpy arrays (the CLI's pixels bit for bit: the keywords are the CLI's render
// options, from the same table, rendered by the same function as a session's), the backends on
// any rays, EXR files read back, and the bench and converge studies as plain data.
// Long calls release the GIL and stop cleanly on Ctrl-C (python/interruptible.h).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "dacrt/util/paths.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/gltf.h"
#include "dacrt/render/render_job.h"
#include "dacrt/render/request.h"
#include "dacrt/render/session.h"
#include "dacrt/scene/camera.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/util/error.h"
#include "image.h"
#include "interruptible.h"
#include "keywords.h"
#include "studies.h"

namespace py = pybind11;

namespace dacrt::python {

namespace {

// A scene loaded once: the file (kept to pose the scene at other times) and the scene as last
// posed. Renders of one scene take turns (posing changes it).
struct LoadedScene {
  std::string path;
  GltfOptions options;  // as loaded: the scene index and variant; no time (the rest pose)
  std::unique_ptr<GltfAnimation> file;
  Scene scene;
  std::optional<double> time;  // the time the scene is posed at; none: the rest pose
  std::mutex busy;

  // Poses the scene at `t` (none: the rest pose) unless it is there already.
  void pose(std::optional<double> t) {
    if (t == time) return;
    if (t)
      file->pose(*t, scene);
    else
      scene = file->load();
    time = t;
  }
};

using ScenePtr = std::shared_ptr<LoadedScene>;

// Seconds as `--time` takes them: finite, >= 0 and below 1e9 (ValueError otherwise).
void check_time(std::optional<double> time) {
  if (time && !valid_time(*time))
    throw py::value_error("time= wants seconds, a number >= 0 and below 1e9, got " +
                          std::string(py::str(py::float_(*time))));
}

ScenePtr load_scene(const std::string& path, std::optional<std::string> variant,
                    std::optional<int> scene_index, std::optional<double> time,
                    std::optional<std::string> animation) {
  auto s = std::make_shared<LoadedScene>();
  s->path = path;
  if (variant) s->options.variant = *variant;
  if (animation) s->options.animation = *animation;
  if (scene_index) s->options.scene = *scene_index;
  GltfOptions at = s->options;
  at.time = time;
  s->file = std::make_unique<GltfAnimation>(path, s->options);
  s->scene = time ? GltfAnimation(path, at, false).load() : s->file->load();
  s->time = time;
  return s;
}

// Each camera as `dacrt info` prints it: index, name (None when unnamed), position, up, a point
// it looks at (on its axis, as far as the scene's centre), vertical field of view in degrees
// (None for an orthographic camera, whose view height is given instead), aspect ratio (None:
// the image's), and whether it is the file's (False: made to frame the scene).
py::list cameras(const Scene& scene) {
  const Box b = scene.bounds();
  const glm::vec3 centre = b.empty() ? glm::vec3(0.f) : b.center();
  auto triple = [](glm::vec3 v) { return py::make_tuple(v.x, v.y, v.z); };
  py::list out;
  for (size_t c = 0; c < scene.cameras.size(); ++c) {
    const Camera& cam = scene.cameras[c];
    py::dict d;
    d["index"] = c;
    d["name"] = cam.name.empty() ? py::object(py::none()) : py::object(message_text(cam.name));
    d["position"] = triple(cam.position());
    d["look_at"] = triple(look_at_point(cam, centre));
    d["up"] = triple(cam.up());
    d["orthographic"] = cam.orthographic;
    d["fov"] = cam.orthographic ? py::object(py::none())
                                : py::object(py::float_(double(cam.yfov) * 180.0 / M_PI));
    d["ortho_height"] = cam.orthographic ? py::object(py::float_(2.0 * double(cam.ymag)))
                                         : py::object(py::none());
    d["aspect"] = cam.aspect > 0 ? py::object(py::float_(cam.aspect)) : py::object(py::none());
    d["from_file"] = scene.cameras_from_file > 0;
    out.append(d);
  }
  return out;
}

py::dict scene_info(const LoadedScene& s) {
  const Scene& scene = s.scene;
  const MaterialCounts counts = count_materials(scene);
  const Scene::Ignored& ig = scene.ignored;
  py::dict skipped;
  skipped["ktx2_textures"] = ig.ktx2_textures;
  skipped["sourceless_textures"] = ig.sourceless_textures;
  skipped["unknown_lights"] = ig.unknown_lights;
  skipped["unmorphed_primitives"] = ig.unmorphed_primitives;
  skipped["untangented_anisotropic"] = ig.untangented_anisotropic;
  skipped["occlusion_textures"] = ig.occlusion_textures;
  skipped["extensions"] = ig.extensions;
  const Box b = scene.bounds();
  py::dict info;
  info["path"] = path_text(s.path);
  info["triangles"] = scene.geometry.size();
  info["degenerate_triangles"] = scene.degenerate_triangles;
  info["meshes"] = scene.mesh_count;
  info["primitives"] = scene.primitive_count;
  info["nodes"] = scene.node_count;
  info["materials"] = scene.materials.size();
  info["textured_materials"] = counts.textured;
  info["alpha_mask_materials"] = counts.masked;
  info["alpha_blend_materials"] = counts.blended;
  info["transmissive_materials"] = counts.transmissive;
  info["emissive_triangles"] = counts.emissive_triangles;
  info["cameras_from_file"] = scene.cameras_from_file;  // 0: cameras[0] frames the scene
  info["cameras"] = cameras(scene);
  info["punctual_lights"] = scene.lights.size();
  info["variants"] = scene.variants;
  info["animations"] = s.file->animation_count();
  info["animation_end"] = s.file->end();
  py::list clips;  // each animation: name, last keyframe time, whether it plays
  for (const AnimationSummary& a : s.file->animations()) {
    py::dict clip;
    clip["name"] = message_text(a.name);
    clip["end"] = a.end;
    clip["plays"] = a.plays;
    clip["shares_targets_with"] = a.shares;
    clips.append(clip);
  }
  info["animation_list"] = clips;
  info["bounds"] = py::make_tuple(py::make_tuple(b.lo.x, b.lo.y, b.lo.z),
                                  py::make_tuple(b.hi.x, b.hi.y, b.hi.z));
  info["skipped"] = skipped;
  return info;
}

// An H×W array of one channel, or H×W×n of several, from the film's channels.
py::array_t<float> stack(const std::vector<const Channel*>& channels, int width, int height) {
  const size_t n = channels.size(), pixels = size_t(width) * size_t(height);
  py::array_t<float> out(n == 1 ? std::vector<py::ssize_t>{height, width}
                                : std::vector<py::ssize_t>{height, width, py::ssize_t(n)});
  float* data = out.mutable_data();
  for (size_t p = 0; p < pixels; ++p)
    for (size_t c = 0; c < n; ++c) data[p * n + c] = channels[c]->values[p];
  return out;
}

py::object render(const py::object& scene, const py::kwargs& kwargs) {
  ScenePtr loaded;
  std::string path;
  if (py::isinstance<LoadedScene>(scene)) {
    loaded = py::cast<ScenePtr>(scene);
    path = loaded->path;
  } else {
    path = path_argument(scene, "scene");
  }
  RenderRequest r = render_request(path, kwargs);
  const bool aovs_asked = kwargs.contains("aovs");
  if (r.backend.find(',') != std::string::npos)
    throw UsageError("backend=: one backend a call (" + r.backend + ")");
  if (loaded && r.gltf.variant != loaded->options.variant)
    throw UsageError("variant= is the loaded scene's: give it to load()");
  // The animations that play are the loaded scene's: animation= may only repeat them.
  if (loaded && kwargs.contains("animation") && r.gltf.animation != loaded->options.animation)
    throw UsageError(
        "animation= is the loaded scene's (" +
        (loaded->options.animation.empty() ? std::string("the first") : loaded->options.animation) +
        "): give it to load()");
  check_render_choices(r, {r.backend});

  std::atomic<bool> stop{false};
  r.passes.stop = &stop;
  const FilmRender done = run_interruptible(stop, [&]() -> FilmRender {
    if (!loaded) return render_to_film(r, GltfAnimation(path, r.gltf, false).load());
    const std::lock_guard<std::mutex> lock(loaded->busy);
    loaded->pose(r.gltf.time);
    return render_to_film(r, loaded->scene);
  });

  const Film& film = done.film;
  const std::vector<Film::Output> outputs = film.outputs(film.min_count() != film.max_count());
  std::vector<const Channel*> rgb;
  for (const Channel& c : outputs.front().channels) rgb.push_back(&c);
  const py::array_t<float> image = stack(rgb, film.width(), film.height());
  py::list notes;
  for (const std::string& note : done.notes) notes.append(message_text(note));
  if (!aovs_asked) return py::make_tuple(image, py::none(), notes);
  py::dict aovs;
  for (size_t k = 1; k < outputs.size(); ++k) {
    std::vector<const Channel*> layer;
    for (const Channel& c : outputs[k].channels) layer.push_back(&c);
    aovs[py::str(outputs[k].name)] = stack(layer, film.width(), film.height());
  }
  return py::make_tuple(image, aovs, notes);
}

// Rays from two N×3 arrays; ValueError for other shapes.
RayBatch rays_from(const py::array_t<float, py::array::c_style | py::array::forcecast>& origins,
                   const py::array_t<float, py::array::c_style | py::array::forcecast>& directions,
                   float tmin, float tmax) {
  if (origins.ndim() != 2 || origins.shape(1) != 3 || directions.ndim() != 2 ||
      directions.shape(1) != 3 || origins.shape(0) != directions.shape(0))
    throw py::value_error("origins and directions must be N×3 arrays of the same N");
  const size_t n = size_t(origins.shape(0));
  if (n >= HitBatch::miss) throw py::value_error("too many rays for one call (at most 2^32 - 2)");
  if (!(tmin >= 0.f) || !(tmax >= tmin))
    throw py::value_error("tmin must be >= 0 and tmax >= tmin");
  RayBatch rays;
  rays.resize(n);
  const float* o = origins.data();
  const float* d = directions.data();
  for (size_t i = 0; i < n; ++i)
    rays.set(i, {o[3 * i], o[3 * i + 1], o[3 * i + 2]}, {d[3 * i], d[3 * i + 1], d[3 * i + 2]},
             tmin, tmax, uint32_t(i));
  return rays;
}

py::object trace(const ScenePtr& scene, const py::array_t<float, py::array::c_style | py::array::forcecast>& origins,
                 const py::array_t<float, py::array::c_style | py::array::forcecast>& directions,
                 const std::string& backend_name, float tmin, float tmax, bool occluded) {
  check_backend(backend_name);
  const RayBatch rays = rays_from(origins, directions, tmin, tmax);
  const py::ssize_t n = py::ssize_t(rays.size());
  std::atomic<bool> stop{false};  // a backend call is not stopped midway: Ctrl-C waits for it
  if (occluded) {
    py::array_t<bool> out(n);
    bool* data = out.mutable_data();
    run_interruptible(stop, [&] {
      const std::lock_guard<std::mutex> lock(scene->busy);
      auto backend = Backend::create(backend_name, scene->scene.geometry);
      std::vector<uint8_t> hit(rays.size());
      backend->occluded(rays, hit);
      for (size_t i = 0; i < hit.size(); ++i) data[i] = hit[i] != 0;
      return 0;
    });
    return out;
  }
  py::array_t<float> t(n), u(n), v(n);
  py::array_t<uint32_t> prim(n);
  float *tp = t.mutable_data(), *up = u.mutable_data(), *vp = v.mutable_data();
  uint32_t* pp = prim.mutable_data();
  run_interruptible(stop, [&] {
    const std::lock_guard<std::mutex> lock(scene->busy);
    auto backend = Backend::create(backend_name, scene->scene.geometry);
    HitBatch hits;
    backend->intersect(rays, hits);
    for (size_t i = 0; i < hits.size(); ++i)
      tp[i] = hits.t[i], up[i] = hits.u[i], vp[i] = hits.v[i], pp[i] = hits.prim[i];
    return 0;
  });
  py::dict out;
  out["t"] = t, out["prim"] = prim, out["u"] = u, out["v"] = v;
  return out;
}

py::dict exr_channels(const py::object& path_object) {
  const ExrFile f = read_exr_file(path_argument(path_object, "path"));
  py::dict out;
  for (const Channel& c : f.channels) out[py::str(c.name)] = stack({&c}, f.width, f.height);
  return out;
}

// load(): the arguments as --variant and --animation take them, checked (TypeError, ValueError),
// then the file loaded with the GIL released.
ScenePtr load(const py::object& path, const py::object& variant, std::optional<int> scene,
              std::optional<double> time, const py::object& animation) {
  const std::string bytes = path_argument(path, "path");
  // A variant name as the CLI takes it: any bytes (a str with surrogate escapes too).
  std::optional<std::string> name;
  if (!variant.is_none()) {
    if (!py::isinstance<py::str>(variant) && !py::isinstance<py::bytes>(variant))
      throw py::type_error("variant= wants a str, not " +
                           std::string(py::str(variant.get_type().attr("__name__"))));
    name = path_argument(variant, "variant");
  }
  // An animation as --animation takes it: a name (str or bytes), an index, or "all".
  std::optional<std::string> clip;
  if (!animation.is_none()) {
    if (py::isinstance<py::bool_>(animation) ||
        !(py::isinstance<py::int_>(animation) || py::isinstance<py::str>(animation) ||
          py::isinstance<py::bytes>(animation)))
      throw py::type_error("animation= wants a name, an index or 'all', not " +
                           std::string(py::str(animation.get_type().attr("__name__"))));
    if (py::isinstance<py::int_>(animation)) {
      const long long index = py::cast<long long>(animation);
      if (index < 0) throw py::value_error("animation= wants an index >= 0");
      clip = std::to_string(index);
    } else {
      clip = path_argument(animation, "animation");
      if (clip->empty()) throw py::value_error("animation= wants a name, an index or 'all'");
    }
  }
  check_time(time);
  const py::gil_scoped_release release;
  return load_scene(bytes, std::move(name), scene, time, std::move(clip));
}

}  // namespace

}  // namespace dacrt::python

PYBIND11_MODULE(_dacrt, m) {
  using namespace dacrt;
  using namespace dacrt::python;
  m.doc() =
      "dacrt's native part: the package `dacrt` (python/dacrt/__init__.py) gives each function "
      "its signature, its documentation and its defaults, and calls these.";
  m.attr("__version__") = dacrt::version();

  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  error.doc() = "A scene, file or option dacrt refuses; the message is the CLI's one line.";
  // Messages as text whatever bytes they quote (a file or variant name need not be UTF-8);
  // pybind11's own exceptions (TypeError, ValueError raised here) pass on to its translator.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const py::builtin_exception&) {
      throw;
    } catch (const py::error_already_set&) {
      throw;
    } catch (const UsageError& e) {
      PyErr_SetObject(PyExc_ValueError, message_text(e.what()).ptr());
    } catch (const SettingError& e) {  // what the caller asked (a variant the file lacks)
      PyErr_SetObject(PyExc_ValueError, message_text(e.what()).ptr());
    } catch (const Error& e) {
      PyErr_SetObject(error.ptr(), message_text(e.what()).ptr());
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      PyErr_SetObject(PyExc_RuntimeError, message_text(e.what()).ptr());
    }
  });

  py::class_<LoadedScene, ScenePtr>(m, "Scene",
                                    "A glTF scene loaded once (dacrt.load), rendered and traced "
                                    "many times; renders of one scene take turns.")
      .def_property_readonly("path", [](const LoadedScene& s) { return path_text(s.path); })
      .def_property_readonly(
          "info", [](const LoadedScene& s) { return scene_info(s); },
          "What `dacrt info` says, as a dict: triangles, meshes, materials (and how many are "
          "textured, alpha-tested, transmissive), emissive triangles, cameras (a dict each: "
          "index, name, position, look_at, up, orthographic, fov in degrees or ortho_height, "
          "aspect, from_file), cameras_from_file (0: none in the file, cameras[0] frames the "
          "scene), punctual lights, variants, animations, bounds, and `skipped`: what the file "
          "asks for that is not rendered as specified.")
      .def("__repr__", [](const LoadedScene& s) {
        return "<dacrt.Scene " + std::string(py::repr(path_text(s.path))) + ", " +
               std::to_string(s.scene.geometry.size()) + " triangles>";
      });

  // The signatures and the documentation are the package's (python/dacrt/__init__.py).
  m.def("load", &load, py::arg("path"), py::kw_only(), py::arg("variant") = py::none(),
        py::arg("scene") = py::none(), py::arg("time") = py::none(),
        py::arg("animation") = py::none());
  // render(scene, **options) -> (image, aovs or None, the shot's notes)
  m.def("render", &render, py::arg("scene"));
  m.def("trace", &trace, py::arg("scene"), py::arg("origins"), py::arg("directions"),
        py::kw_only(), py::arg("backend") = "dacrt", py::arg("tmin") = 0.f,
        py::arg("tmax") = std::numeric_limits<float>::infinity(), py::arg("occluded") = false);
  m.def("read_exr", &exr_channels, py::arg("path"));
  m.def("_render_keywords", &render_keywords,
        "The keywords render() takes (the render option table's Python column, and progress).");
  m.def("_render_keyword_table", &render_keyword_table,
        "Each render option Python takes, from the render option table: (keyword, value type, "
        "repeatable, taken by converge(), its help lines).");

  add_studies(m);
  add_image(m);
}
