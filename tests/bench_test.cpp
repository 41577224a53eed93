// `dacrt bench`: the ray generators on a closed box seen from inside (with and without an emissive
// ceiling), whose answers are known, and the command end to end on a tiny glTF.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

#include "bench/args.h"
#include "bench/command.h"
#include "bench/rays.h"
#include "bench/report.h"
#include "bench/run.h"
#include "gltf_writer.h"
#include "dacrt/tracer/backend.h"

using namespace dacrt;
using namespace dacrt::bench;
using namespace dacrt::test;

namespace {

// The 12 triangles of the box [-1, 1]^3, wound so that every normal points inwards. With
// `emissive_ceiling`, the two triangles of the y = +1 face use material 1, which emits.
std::vector<std::array<glm::vec3, 3>> box_triangles() {
  std::vector<std::array<glm::vec3, 3>> tris;
  for (int axis = 0; axis < 3; ++axis)
    for (float side : {-1.f, 1.f}) {
      int u = (axis + 1) % 3, v = (axis + 2) % 3;
      auto corner = [&](float a, float b) {
        glm::vec3 p(0.f);
        p[axis] = side, p[u] = a, p[v] = b;
        return p;
      };
      glm::vec3 c00 = corner(-1, -1), c10 = corner(1, -1), c11 = corner(1, 1), c01 = corner(-1, 1);
      for (auto t :
           {std::array<glm::vec3, 3>{c00, c10, c11}, std::array<glm::vec3, 3>{c00, c11, c01}}) {
        glm::vec3 n = glm::cross(t[1] - t[0], t[2] - t[0]);
        if (n[axis] * side > 0.f) std::swap(t[1], t[2]);  // inwards: against the face's side
        tris.push_back(t);
      }
    }
  return tris;
}

bool on_ceiling(const std::array<glm::vec3, 3>& t) {
  return t[0].y == 1.f && t[1].y == 1.f && t[2].y == 1.f;
}

// A camera at the box's centre looking down -z (at the z = -1 wall).
Scene box_scene(bool emissive_ceiling) {
  Scene s;
  s.path = "box";
  s.materials.resize(2);
  s.materials[0].name = "white";
  s.materials[1].name = "light";
  if (emissive_ceiling) s.materials[1].emission = glm::vec3(1.f);
  for (const auto& t : box_triangles()) s.geometry.add(t[0], t[1], t[2], on_ceiling(t) ? 1 : 0);
  Camera cam;
  cam.yfov = 0.7f;
  s.cameras.push_back(cam);
  return s;
}

struct Traced {
  RayBatch primary;
  HitBatch hits;
  SurfacePoints points;
};

Traced trace_primary(const Scene& s, int w, int h) {
  Traced t;
  t.primary = primary_rays(s.cameras[0], w, h);
  auto brute = Backend::create("brute", s.geometry);
  brute->intersect(t.primary, t.hits);
  t.points = surface_points(s.geometry, t.primary, t.hits);
  return t;
}

void check_unit_directions(const RayBatch& b) {
  for (size_t i = 0; i < b.size(); ++i)
    REQUIRE(glm::length(b.direction(i)) == doctest::Approx(1.0).epsilon(1e-5));
}

std::vector<uint8_t> occluded_by(const char* backend, const Scene& s, const RayBatch& b) {
  auto be = Backend::create(backend, s.geometry);
  std::vector<uint8_t> occ(b.size());
  be->occluded(b, occ);
  return occ;
}

bool same_rays(const RayBatch& a, const RayBatch& b) {
  return a.ox == b.ox && a.oy == b.oy && a.oz == b.oz && a.dx == b.dx && a.dy == b.dy &&
         a.dz == b.dz && a.tmin == b.tmin && a.tmax == b.tmax && a.path == b.path;
}

}  // namespace

TEST_CASE("bench rays: primary rays hit what the camera sees") {
  Scene s = box_scene(true);
  const int w = 16, h = 8;
  Traced t = trace_primary(s, w, h);
  REQUIRE(t.primary.size() == size_t(w * h));
  check_unit_directions(t.primary);
  REQUIRE(t.points.size() == t.primary.size());  // a closed box: every ray hits
  const float tan_half = std::tan(0.35f), aspect = float(w) / h;
  for (size_t i = 0; i < t.points.size(); ++i) {
    int x = int(i % w), y = int(i / w);
    // Pixel centres on the far wall z = -1, one unit in front of the camera.
    glm::vec3 expected((2.f * (x + 0.5f) / w - 1.f) * tan_half * aspect,
                       (1.f - 2.f * (y + 0.5f) / h) * tan_half, -1.f);
    CHECK(t.points.pixel[i] == i);
    CHECK(glm::length(t.points.point[i] - expected) < 1e-5f);
    CHECK(glm::length(t.points.normal[i] - glm::vec3(0, 0, 1)) < 1e-6f);  // facing the camera
  }
}

TEST_CASE("bench rays: resolution for a ray count stays within the side limit") {
  // A camera aspectRatio of 1e-7 (untrusted files say anything) asked for 3 162 278 rows.
  CHECK(resolution_for_count(size_t(1) << 20, 1e-7f) == glm::ivec2(1, 32768));
  CHECK(resolution_for_count(size_t(1) << 20, 1e7f) == glm::ivec2(32768, 1));
}

TEST_CASE("bench rays: resolution for a ray count keeps the aspect") {
  CHECK(resolution_for_count(4096, 0.f) == glm::ivec2(64, 64));
  CHECK(resolution_for_count(4096, 1.f) == glm::ivec2(64, 64));
  CHECK(resolution_for_count(65536, 2.f) == glm::ivec2(362, 181));
  CHECK(resolution_for_count(1, 0.5f) == glm::ivec2(1, 1));
}

TEST_CASE("bench rays: shadow rays end on emitters and see them") {
  Scene s = box_scene(true);
  // A wide camera so that points land on every wall, the ceiling included. An odd aspect keeps
  // every pixel off the box's edges, where an origin offset along one face's normal would still
  // lie in the other face.
  s.cameras[0].yfov = 2.8f;
  Traced t = trace_primary(s, 24, 23);
  REQUIRE(t.points.size() == 24 * 23);
  const ShadowTargets lights(s);
  REQUIRE(!lights.empty());
  const size_t n = 3000;
  RayBatch b = shadow_rays(s, lights, t.points, n, 7);
  REQUIRE(b.size() == n);
  check_unit_directions(b);
  for (size_t i = 0; i < n; ++i) {
    glm::vec3 end = b.origin(i) + b.tmax[i] * b.direction(i);
    CHECK(b.tmin[i] == 0.f);
    CHECK(end.y == doctest::Approx(1.0).epsilon(1e-4));  // on the ceiling, the only emitter
    CHECK(std::abs(end.x) <= 1.0001f);
    CHECK(std::abs(end.z) <= 1.0001f);
    CHECK(b.path[i] == t.points.pixel[i % t.points.size()]);
  }
  // Inside a convex box every point sees every point of the ceiling: with the origins and the
  // ends offset off their surfaces, no segment may touch the box.
  for (const char* backend : {"brute", "dacrt"}) {
    auto occ = occluded_by(backend, s, b);
    CHECK_MESSAGE(std::count(occ.begin(), occ.end(), 1) == 0, backend);
  }
}

TEST_CASE("bench rays: without emitters, shadow rays aim at the point above the scene") {
  Scene s = box_scene(false);
  s.cameras[0].yfov = 2.8f;
  Traced t = trace_primary(s, 16, 15);
  const ShadowTargets lights(s);
  REQUIRE(lights.empty());
  const glm::vec3 above = point_above(s.bounds());
  CHECK(above == glm::vec3(0.f, 4.f, 0.f));  // centre + 2 × the side (2) in +y
  RayBatch b = shadow_rays(s, lights, t.points, t.points.size(), 1);
  REQUIRE(b.size() == t.points.size());
  check_unit_directions(b);
  auto occ = occluded_by("brute", s, b);
  size_t ceiling_points = 0;
  for (size_t i = 0; i < b.size(); ++i) {
    glm::vec3 end = b.origin(i) + b.tmax[i] * b.direction(i);
    CHECK(glm::length(end - above) < 1e-5f);
    // The target is outside the closed box: blocked, except from the ceiling, whose rays start
    // on its outer side (the normal facing the target).
    bool ceiling = s.geometry.material[t.hits.prim[t.points.pixel[i]]] == 1;
    CHECK(occ[i] == (ceiling ? 0 : 1));
    ceiling_points += ceiling;
  }
  CHECK(ceiling_points > 0);
  CHECK(ceiling_points < b.size());
}

TEST_CASE("bench rays: ambient occlusion and bounce rays") {
  Scene s = box_scene(true);
  s.cameras[0].yfov = 2.8f;
  Traced t = trace_primary(s, 32, 31);
  const size_t n = 20000;
  RayBatch ao = ao_rays(s, t.points, n, 3);
  RayBatch bounce = bounce_rays(t.points, n, 3);
  REQUIRE(ao.size() == n);
  REQUIRE(bounce.size() == n);
  check_unit_directions(ao);
  check_unit_directions(bounce);
  const float diagonal = std::sqrt(12.f);
  double mean_cos = 0.0;
  for (size_t i = 0; i < n; ++i) {
    size_t j = i % t.points.size();
    const glm::vec3& nrm = t.points.normal[j];
    CHECK(ao.tmax[i] == doctest::Approx(0.1 * diagonal));
    CHECK(bounce.tmax[i] == infinity);
    CHECK(glm::dot(ao.direction(i), nrm) >= -1e-6f);
    CHECK(glm::dot(bounce.direction(i), nrm) >= -1e-6f);
    // Origins cycle through the points, just off the surface on the normal's side.
    glm::vec3 off = bounce.origin(i) - t.points.point[j];
    CHECK(glm::length(off) < 1e-3f);
    CHECK(glm::dot(off, nrm) > 0.f);
    CHECK(bounce.path[i] == t.points.pixel[j]);
    mean_cos += glm::dot(bounce.direction(i), nrm);
  }
  // Cosine-weighted: E[cos θ] = 2/3.
  CHECK(mean_cos / n == doctest::Approx(2.0 / 3.0).epsilon(0.02));
  // Different ray types draw different directions from the same seed.
  CHECK(ao.dx != bounce.dx);
  // Bounce rays never leave a closed box: all hit, and never the triangle they start on.
  auto dacrt = Backend::create("dacrt", s.geometry);
  HitBatch hits;
  dacrt->intersect(bounce, hits);
  for (size_t i = 0; i < n; ++i) {
    REQUIRE(hits.hit(i));
    CHECK(hits.prim[i] != t.hits.prim[t.points.pixel[i % t.points.size()]]);
  }
}

TEST_CASE("bench rays: random rays start inside the box") {
  Scene s = box_scene(true);
  const size_t n = 5000;
  RayBatch b = random_rays(s.bounds(), n, 5);
  REQUIRE(b.size() == n);
  check_unit_directions(b);
  glm::vec3 mean_dir(0.f);
  for (size_t i = 0; i < n; ++i) {
    glm::vec3 o = b.origin(i);
    CHECK(glm::all(glm::greaterThanEqual(o, glm::vec3(-1.f))));
    CHECK(glm::all(glm::lessThanEqual(o, glm::vec3(1.f))));
    CHECK(b.tmax[i] == infinity);
    mean_dir += b.direction(i);
  }
  CHECK(glm::length(mean_dir / float(n)) < 0.05f);  // uniform on the sphere
  auto brute = Backend::create("brute", s.geometry);
  HitBatch hits;
  brute->intersect(b, hits);
  CHECK(std::count(hits.prim.begin(), hits.prim.end(), HitBatch::miss) == 0);
}

TEST_CASE("bench rays: a flat scene's random rays start off its plane, and every backend agrees") {
  // One triangle in z = 0 (its box is flat). Origins on the plane would make the hit at t = 0 a
  // matter of each backend's rounding: this scene had Embree answer 133 of 256 rays, dacrt 115.
  Scene s;
  s.materials.resize(1);
  s.geometry.add({0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, 0);
  const size_t n = 4096;
  RayBatch b = random_rays(s.bounds(), n, 3);
  size_t above = 0;
  for (size_t i = 0; i < n; ++i) {
    REQUIRE(b.origin(i).z != 0.f);
    CHECK(std::abs(b.origin(i).z) <= 0.005f);
    above += b.origin(i).z > 0.f;
  }
  CHECK(above > n / 3);
  CHECK(above < 2 * n / 3);
  HitBatch reference;
  Backend::create("brute", s.geometry)->intersect(b, reference);
  const size_t hits =
      n - size_t(std::count(reference.prim.begin(), reference.prim.end(), HitBatch::miss));
  // About a quarter: the origin is over the triangle (half of the box) and the ray goes towards it.
  CHECK(hits > n / 5);
  CHECK(hits < n / 3);
  for (const std::string& name : Backend::names()) {
    HitBatch h;
    Backend::create(name, s.geometry)->intersect(b, h);
    INFO(name);
    CHECK(h.prim == reference.prim);
  }
}

TEST_CASE("bench rays: a seed gives the same rays, another seed others") {
  Scene s = box_scene(true);
  Traced t = trace_primary(s, 8, 8);
  const ShadowTargets lights(s);
  CHECK(same_rays(primary_rays(s.cameras[0], 8, 8), t.primary));
  CHECK(same_rays(shadow_rays(s, lights, t.points, 500, 9),
                  shadow_rays(s, lights, t.points, 500, 9)));
  CHECK(same_rays(ao_rays(s, t.points, 500, 9), ao_rays(s, t.points, 500, 9)));
  CHECK(same_rays(bounce_rays(t.points, 500, 9), bounce_rays(t.points, 500, 9)));
  CHECK(same_rays(random_rays(s.bounds(), 500, 9), random_rays(s.bounds(), 500, 9)));
  CHECK(!same_rays(shadow_rays(s, lights, t.points, 500, 9),
                   shadow_rays(s, lights, t.points, 500, 10)));
  CHECK(!same_rays(bounce_rays(t.points, 500, 9), bounce_rays(t.points, 500, 10)));
  CHECK(!same_rays(random_rays(s.bounds(), 500, 9), random_rays(s.bounds(), 500, 10)));
  SurfacePoints none;
  CHECK(bounce_rays(none, 100, 0).size() == 0);
  CHECK(shadow_rays(s, lights, none, 100, 0).size() == 0);
}

TEST_CASE("bench: decimation keeps every k-th triangle") {
  Scene s = box_scene(true);
  CHECK(decimate(s, 1).geometry.size() == 12);
  CHECK(decimate(s, 2).geometry.size() == 6);
  CHECK(decimate(s, 8).geometry.size() == 2);
  CHECK(decimate(s, 32).geometry.size() == 1);
  CHECK(decimate(s, 4).geometry.vertex(1, 2) == s.geometry.vertex(4, 2));
  CHECK(decimate(s, 4).cameras.size() == 1);
}

namespace {

// The box as a glTF file: walls in one primitive, the emissive ceiling in another. No camera:
// the loader frames the box from outside.
std::string write_box_gltf(const TempDir& dir) {
  std::vector<glm::vec3> walls, ceiling;
  for (const auto& t : box_triangles())
    for (const auto& p : t) (on_ceiling(t) ? ceiling : walls).push_back(p);
  GltfWriter w;
  w.add_material({{"name", "white"}});
  w.add_material({{"name", "light"}, {"emissiveFactor", {1.0, 1.0, 1.0}}});
  nlohmann::json prims =
      nlohmann::json::array({GltfWriter::primitive(w.add_vec3(walls), {{"material", 0}}),
                             GltfWriter::primitive(w.add_vec3(ceiling), {{"material", 1}})});
  int node = w.add_node({{"mesh", w.add_mesh(prims)}});
  w.set_scene({node});
  return w.write_gltf(dir / "box.gltf");
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

}  // namespace

TEST_CASE("bench: end to end on a glTF, with JSON") {
  TempDir dir("bench");
  const std::string scene = write_box_gltf(dir), json = dir / "bench.json";
  std::ostringstream out;
  int code = bench_command({scene, "--count", "4096", "--repeat", "1", "--json", json, "--quiet",
                            "--threads", "2", "--seed", "3"},
                           out);
  CHECK(code == 0);
  const auto backends = default_bench_backends();
  CHECK(std::find(backends.begin(), backends.end(), "brute") == backends.end());
  CHECK(std::find(backends.begin(), backends.end(), "dacrt") != backends.end());

  nlohmann::json j = read_json(json);
  CHECK(j["scene"] == scene);
  CHECK(j["triangles"] == 12);
  CHECK(j["threads"].get<int>() >= 1);
  CHECK(j["threads"].get<int>() <= 2);
  REQUIRE(j["results"].size() == 5 * backends.size());
  std::set<std::pair<std::string, std::string>> seen;
  for (const auto& r : j["results"]) {
    for (const char* field : {"backend", "rays", "count", "build_s", "trace_s", "mrays_per_s",
                              "mrays_per_s_with_build", "peak_mb"})
      CHECK_MESSAGE(r.contains(field), field);
    seen.insert({r["rays"].get<std::string>(), r["backend"].get<std::string>()});
    CHECK(r["count"] == 4096);  // 64 × 64 primary rays; exactly 4096 of the others
    CHECK(r["trace_s"].get<double>() > 0.0);
    CHECK(r["build_s"].get<double>() >= 0.0);
    CHECK(r["mrays_per_s"].get<double>() ==
          doctest::Approx(4096 / r["trace_s"].get<double>() * 1e-6));
    CHECK(r["mrays_per_s_with_build"].get<double>() <= r["mrays_per_s"].get<double>());
    CHECK(r["peak_mb"].get<double>() >= 0.0);
  }
  CHECK(seen.size() == 5 * backends.size());
  // The same rays went to every backend: they agree on what was hit or occluded.
  for (const auto& a : j["results"])
    for (const auto& b : j["results"])
      if (a["rays"] == b["rays"]) CHECK(a["hits"] == b["hits"]);

  const std::string table = out.str();
  CHECK(table.find("| rays ") != std::string::npos);
  CHECK(table.find("Mrays/s with build") != std::string::npos);
  for (const char* ray : {"primary", "shadow", "ao", "bounce", "random"})
    CHECK_MESSAGE(table.find("| " + std::string(ray)) != std::string::npos, ray);
}

TEST_CASE("bench: a discarded warm-up, every timed run kept, medians with intervals, speed-ups") {
  TempDir dir("bench-runs");
  const std::string scene = write_box_gltf(dir), json = dir / "runs.json";
  CHECK(parse_bench_args({scene}).repeat == 5);
  std::ostringstream out;
  REQUIRE(bench_command({scene, "--count", "1024", "--repeat", "6", "--rays", "primary,shadow",
                         "--backends", "dacrt,dacrt-naive", "--json", json, "--quiet"},
                        out) == 0);
  const nlohmann::json j = read_json(json);
  CHECK(j["repeat"] == 6);
  CHECK(j["warmup_runs"] == 1);
  CHECK(j["method"].get<std::string>().find("1 discarded warm-up run") != std::string::npos);
  REQUIRE(j["results"].size() == 2 * 2);
  auto sorted = [](const nlohmann::json& runs) {
    std::vector<double> v = runs.get<std::vector<double>>();
    std::sort(v.begin(), v.end());
    return v;
  };
  for (const auto& r : j["results"]) {
    INFO(r["rays"].get<std::string>() << " " << r["backend"].get<std::string>());
    // The warm-up ran (the runner counts it) and none of its figures is among the six.
    CHECK(r["warmups"] == 1);
    const auto& in = r["intervals"];
    for (const char* figure :
         {"build_s", "trace_s", "total_s", "mrays_per_s", "mrays_per_s_with_build", "speedup"}) {
      INFO(figure);
      const std::vector<double> v = sorted(in[figure]["runs"]);
      REQUIRE(v.size() == 6);
      // Six runs: the median between the 3rd and 4th, the interval the range (96.9 %).
      CHECK(in[figure]["median"].get<double>() == doctest::Approx(0.5 * (v[2] + v[3])));
      CHECK(in[figure]["low"].get<double>() == v.front());
      CHECK(in[figure]["high"].get<double>() == v.back());
      CHECK(in[figure]["coverage"].get<double>() == doctest::Approx(1 - 2.0 / 64));
      if (std::string(figure) != "total_s")
        CHECK(r[figure].get<double>() == in[figure]["median"].get<double>());
    }
    // Speed-up: the baseline's trace seconds over the row's, repeat by repeat.
    for (const auto& b : j["results"]) {
      if (b["backend"] != "dacrt-naive" || b["rays"] != r["rays"]) continue;
      for (size_t i = 0; i < 6; ++i)
        CHECK(in["speedup"]["runs"][i].get<double>() ==
              doctest::Approx(b["intervals"]["trace_s"]["runs"][i].get<double>() /
                              in["trace_s"]["runs"][i].get<double>()));
    }
  }
  // The table names the convention and the method, and gives each figure its interval.
  const std::string table = out.str();
  CHECK(table.find("| speed-up vs dacrt-naive, higher is faster |") != std::string::npos);
  CHECK(table.find("after 1 discarded warm-up run per backend and ray type") != std::string::npos);
  CHECK(table.find("97 % confidence interval (runs 1 and 6 of the 6 sorted)") != std::string::npos);
  CHECK(table.find(" [") != std::string::npos);
  // Fewer than six runs cannot reach 95 %: the range, with the coverage it has.
  CHECK(method_text(5).find("their range (n=5: range, 94 % coverage") != std::string::npos);
  CHECK(method_text(9).find("its 96 % confidence interval (runs 2 and 8") != std::string::npos);
  CHECK(method_text(1).find("without an interval") != std::string::npos);
}

TEST_CASE("bench: triangle sweep and ray subsets") {
  TempDir dir("bench-sweep");
  const std::string scene = write_box_gltf(dir), json = dir / "sweep.json";
  std::ostringstream out;
  CHECK(bench_command({scene, "--sweep", "triangles", "--count", "1024", "--repeat", "2", "--rays",
                       "primary,bounce", "--backends", "dacrt,dacrt-naive", "--json", json,
                       "--quiet", "--backend-option", "bins=8"},
                      out) == 0);
  nlohmann::json j = read_json(json);
  CHECK(j["sweep"] == "triangles");
  CHECK(j["baseline"] == "dacrt-naive");
  REQUIRE(j["results"].size() == 6 * 2 * 2);
  std::set<size_t> triangles;
  for (const auto& r : j["results"]) {
    triangles.insert(r["triangles"].get<size_t>());
    CHECK(r["intervals"]["trace_s"]["runs"].size() == 2);
  }
  CHECK(triangles == std::set<size_t>{12, 6, 3, 2, 1});
}

TEST_CASE("bench: --tmax-at-hit keeps every closest hit and never adds work") {
  // Rays that end at their closest hit still find it (the same hits as open rays). dacrt-naive's
  // tree and order do not depend on the rays, so with them it can only cull more: no more box or
  // triangle tests than the open rays. (dacrt's sampled splits change with the rays.)
  // The Cornell box of scenes/ is closed, so bounce rays hit too; small leaves make the tree deep
  // enough for culling to show.
  TempDir dir("bench-tmax");
  const std::string scene = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";
  nlohmann::json runs[2];
  for (int at_hit = 0; at_hit < 2; ++at_hit) {
    const std::string json = dir / ("tmax" + std::to_string(at_hit) + ".json");
    std::vector<std::string> args = {scene,
                                     "--count",
                                     "4096",
                                     "--repeat",
                                     "1",
                                     "--rays",
                                     "primary,bounce,random",
                                     "--backends",
                                     "dacrt,dacrt-naive,brute",
                                     "--json",
                                     json,
                                     "--quiet",
                                     "--backend-option",
                                     "leaf_triangles=2",
                                     "--backend-option",
                                     "leaf_lanes=1"};
    if (at_hit) args.push_back("--tmax-at-hit");
    std::ostringstream out;
    REQUIRE(bench_command(args, out) == 0);
    runs[at_hit] = read_json(json);
    CHECK(runs[at_hit]["tmax_at_hit"] == bool(at_hit));
    CHECK((out.str().find("--tmax-at-hit") != std::string::npos) == bool(at_hit));
  }
  REQUIRE(runs[0]["results"].size() == runs[1]["results"].size());
  bool fewer = false;
  for (size_t i = 0; i < runs[0]["results"].size(); ++i) {
    const auto &open = runs[0]["results"][i], &clipped = runs[1]["results"][i];
    INFO(open["rays"].get<std::string>() << " " << open["backend"].get<std::string>());
    REQUIRE(open["backend"] == clipped["backend"]);
    CHECK(open["hits"] == clipped["hits"]);
    CHECK(open["hits"].get<uint64_t>() > 0);
    if (open["backend"] != "dacrt-naive") continue;
    const auto &a = open["backend_stats"], &b = clipped["backend_stats"];
    CHECK(b["box_tests"].get<uint64_t>() <= a["box_tests"].get<uint64_t>());
    CHECK(b["triangle_tests"].get<uint64_t>() <= a["triangle_tests"].get<uint64_t>());
    fewer |= b["triangle_tests"].get<uint64_t>() < a["triangle_tests"].get<uint64_t>();
  }
  CHECK(fewer);
}

TEST_CASE("bench: usage errors and scene errors") {
  TempDir dir("bench-errors");
  const std::string scene = write_box_gltf(dir);
  std::ostringstream out;
  for (std::vector<std::string> args :
       {std::vector<std::string>{},
        {scene, "--rays", "primary,lasers"},
        {scene, "--rays", ""},
        {scene, "--backends", "dacrt,warp-drive"},
        {scene, "--count", "0"},
        {scene, "--repeat", "x"},
        {scene, "--sweep", "pixels"},
        {scene, "--sweep", "rays", "--count", "100"},
        {scene, "--backend-option", "bins"},
        {scene, "--backend-option", "frobs=3"},
        {scene, "--backend-option", "bins=1"},
        {scene, "--backends", "brute", "--backend-option", "bins=8"},
        {scene, "--bogus"},
        {scene, scene},
        {scene, "--json"}}) {
    std::string joined;
    for (const auto& a : args) joined += a + " ";
    INFO(joined);
    CHECK_THROWS_AS(bench_command(args, out), std::invalid_argument);
  }
  CHECK_THROWS_AS(bench_command({dir / "missing.gltf", "--quiet"}, out), Error);
  CHECK_THROWS_AS(bench_command({scene, "--json", dir / "no/such/dir.json", "--quiet"}, out),
                  Error);
  std::ostringstream help;
  CHECK(bench_command({"--help"}, help) == 0);
  for (const char* flag : {"--rays", "--backends", "--count", "--threads", "--repeat",
                           "--backend-option", "--sweep", "--json", "--seed", "--quiet"})
    CHECK_MESSAGE(help.str().find(flag) != std::string::npos, flag);
}
