// The numerical stress suite (tests/stress.h), short version: every check, for every backend, at
// the translations and scales the README's table claims (and at the origin); glTF node scales of
// 1e-30 and 1e30 and a triangle spanning ±3e38. `make stress` runs the sweep below instead
// (test suite "stress-sweep", skipped in ctest), which finds the largest translation and scale at
// which each check holds.
#include "stress.h"

#include <doctest/doctest.h>

#include <cstdio>
#include <map>

#include "gltf_writer.h"
#include "io/gltf.h"
#include "util/error.h"

using namespace dacrt;
using namespace dacrt::test;
using namespace dacrt::test::stress;

namespace {

// The levels README.md claims: translation 1e5 and 1e6 at scale 1, scale 1e-4 and 1e4 at the
// origin, and more where the sweep found them to hold.
const Placement claimed[] = {{0.0, 1.0}, {1e5, 1.0}, {1e6, 1.0}, {0.0, 1e-4}, {0.0, 1e4}};

void run_claimed(const Check& check, double largest_translation = 1e6) {
  for (const Placement& at : claimed)
    for (const std::string& backend : backends()) {
      if (at.translate > largest_translation) continue;
      if (check.exact_backends_only && (backend == "brute" || backend == "embree")) continue;
      const Verdict v = check.run(at, backend);
      INFO(std::string(check.name) << ", " << backend << ", " << describe(at) << ": " << v.failure);
      CHECK(v.holds());
    }
}

}  // namespace

TEST_CASE("stress: no NaN or inf in the film, far from the origin and at tiny and huge scales") {
  run_claimed(checks()[0]);
}

// Claimed at the origin and at scales 1e-4 and 1e4 only.
TEST_CASE("stress: no light leaks into a closed mesh lit from outside, camera inside") {
  run_claimed(checks()[1], 0.0);
}

// Known to fail (found by this suite, not fixed on this branch): at 1e5 and 1e6 from the origin
// light leaks into the closed box. offset_ray_origin moves spawned origins by 256 ulps of |p|
// (up to 2^-15 |p|: 3 units at 1e5), past the far wall of a box 2 wide.
TEST_CASE("stress: no light leaks at 1e5 and 1e6 from the origin" * doctest::may_fail()) {
  for (const double t : {1e5, 1e6})
    for (const std::string& backend : backends()) {
      const Verdict v = no_leaks({t, 1.0}, backend);
      INFO(backend << ", translate " << t << ": " << v.failure);
      CHECK(v.holds());
    }
}

TEST_CASE("stress: no acne on a plane lit and seen at grazing angles") {
  run_claimed(checks()[2]);
}

// On the grazing plane, rays lying in its plane used to get a different closest hit from dacrt
// and dacrt-naive than from brute force: exact_t (tracer/triangle.h) gave them a t far from the
// triangle, whose box DACRT culled.
TEST_CASE("stress: dacrt and dacrt-naive find brute force's closest hits for the stress rays") {
  run_claimed(checks()[3]);
}

// The sweep: translation 10^k at scale 1 and scale 10^±k at the origin, each check and backend,
// from 1 outwards until it fails; prints the largest level where it holds for every backend.
TEST_CASE("stress sweep: the largest translation and scale at which each check holds" *
          doctest::test_suite("stress-sweep") * doctest::skip()) {
  enum Axis { translation, small_scale, large_scale };
  const char* axis_names[] = {"translation", "smallest scale", "largest scale"};
  auto placement = [](Axis axis, int k) {
    const double p = std::pow(10.0, k);
    return axis == translation ? Placement{p, 1.0}
                               : Placement{0.0, axis == small_scale ? 1.0 / p : p};
  };
  std::printf("| check | backend | largest translation | smallest scale | largest scale |\n");
  std::printf("|---|---|---|---|---|\n");
  for (const Check& check : checks())
    for (const std::string& backend : backends()) {
      if (check.exact_backends_only && (backend == "brute" || backend == "embree")) continue;
      std::string cells[3];
      for (Axis axis : {translation, small_scale, large_scale}) {
        int holds = -1;
        std::string why;
        for (int k = 0; k <= (axis == translation ? 12 : 38); ++k) {
          const Verdict v = check.run(placement(axis, k), backend);
          if (!v.holds()) {
            why = v.failure;
            break;
          }
          holds = k;
        }
        cells[axis] =
            holds < 0 ? "none" : (axis == small_scale ? "1e-" : "1e") + std::to_string(holds);
        MESSAGE(std::string(check.name)
                << ", " << backend << ", " << std::string(axis_names[axis]) << ": holds to "
                << cells[axis] << (why.empty() ? "" : "; next level: " + why));
      }
      std::printf("| %s | %s | %s | %s | %s |\n", check.name, backend.c_str(), cells[0].c_str(),
                  cells[1].c_str(), cells[2].c_str());
      std::fflush(stdout);
    }
}
