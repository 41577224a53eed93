// The Lambert lanes (integrators/lambert_lanes.h): sixteen vertices at once, by each instance of
// the kernel the CPU runs, give what they give one at a time, bit for bit, including which lanes
// they take. Their estimator is checked by the renders of Lambert scenes in integrator_test.cpp
// and convergence_suite_test.cpp (the furnace, Lambert's polygon formula), which go through them.
#include "dacrt/integrators/lambert_lanes.h"

#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>
#include <glm/glm.hpp>

#include "dacrt/util/random.h"

using namespace dacrt;

namespace {

struct Draw {
  uint64_t state;
  float operator()() { return float((state = mix64(state + 1)) >> 40) * 0x1p-24f; }
  float in(float lo, float hi) { return lo + (hi - lo) * (*this)(); }
};

// Sixteen plausible vertices and their emitters, with the cases the lanes must agree on too:
// zero components, points on edges and corners, dead paths, black albedo and throughput, a NaN in
// the throughput, emitters near enough for solid-angle sampling, behind the point, degenerate.
void random_lanes(Draw& r, LambertIn& in, int round) {
  for (int k = 0; k < LambertIn::lanes; ++k) {
    const int kind = (round * 16 + k) % 23;
    in.ok[k] = kind != 3;
    glm::vec3 d(r.in(-1, 1), r.in(-1, 1), r.in(-1, 1));
    if (kind == 5) d.x = 0.f;
    if (kind == 6) d = glm::vec3(0.f, -1.f, 0.f);
    d = glm::normalize(d);
    for (int a = 0; a < 3; ++a) {
      in.d[a][k] = d[a];
      for (int c = 0; c < 3; ++c) {
        in.corner[c][a][k] = kind == 7 && c == 2 ? in.corner[1][a][k] : r.in(-2, 2);
        in.normal[c][a][k] = r.in(-1, 1);
        in.light_corner[c][a][k] = (kind == 8 ? 0.01f : 1.f) * r.in(-3, 3);
      }
      in.albedo[a][k] = kind == 9 ? 0.f : r();
      in.beta[a][k] = kind == 10 ? 0.f : r.in(0, 2);
      if (kind == 17 && a == 2) in.beta[a][k] = NAN;  // (minps and maxps pick by operand order)
      in.light_radiance[a][k] = r.in(0, 20);
      in.light_normal[a][k] = r.in(-1, 1);
    }
    float u = r(), v = r();
    if (u + v > 1.f) u = 1.f - u, v = 1.f - v;
    if (kind == 11) u = 0.f;
    if (kind == 12) u = 1.f, v = 0.f;
    in.u[k] = u, in.v[k] = v;
    in.below_max[k] = kind != 13;
    in.roulette[k] = kind % 2;
    in.u_roulette[k] = r();
    in.u_bsdf[0][k] = kind == 14 ? 0.f : r(), in.u_bsdf[1][k] = kind == 15 ? 0.5f : r();
    in.u_light[0][k] = r(), in.u_light[1][k] = r();
    in.light_ok[k] = kind != 16;
    glm::vec3 centre(0.f);
    for (int c = 0; c < 3; ++c)
      centre +=
          glm::vec3(in.light_corner[c][0][k], in.light_corner[c][1][k], in.light_corner[c][2][k]) /
          3.f;
    const glm::vec3 n = glm::normalize(
        glm::vec3(in.light_normal[0][k], in.light_normal[1][k], in.light_normal[2][k]));
    for (int a = 0; a < 3; ++a) in.light_centre[a][k] = centre[a], in.light_normal[a][k] = n[a];
    in.light_radius2[k] = r.in(0.001f, 2.f);
    in.light_area[k] = r.in(0.01f, 3.f);
    in.light_pmf[k] = r.in(0.1f, 1.f);
    in.light_double_sided[k] = kind % 3 == 0;
  }
}

}  // namespace

TEST_CASE(
    "lambert lanes: each instance this CPU runs gives the answers of one at a time, bit for bit") {
  std::vector<LambertLanes> wide;
  for (const LambertLanes instance : lambert_instances)
    if (instance != LambertLanes::one && lambert_available(instance)) wide.push_back(instance);
  if (wide.empty()) MESSAGE("neither AVX2 nor AVX-512 on this CPU: only the one-lane code runs");
  wide.push_back(LambertLanes::one);  // (and the dispatch: shade_lambert by the widest)
  for (const LambertLanes instance : wide) {
    INFO("instance " << std::string(name(instance)));
    Draw r{0x5eed};
    int taken = 0, shadows = 0, bounces = 0, lanes_run = 0;
    for (const bool normals : {false, true})
      for (const bool lights : {false, true})
        for (const bool solid_angle : {false, true}) {
          const LambertScene scene{normals, lights, solid_angle, 0.5f, 2.f};
          for (int round = 0; round < 40; ++round) {
            LambertIn in{};
            random_lanes(r, in, round);
            const int lanes = round % 5 == 4 ? 1 + round % 16 : 16;
            LambertOut wide_out, one;
            if (instance == LambertLanes::one)
              shade_lambert(scene, in, lanes, wide_out);
            else
              shade_lambert(instance, scene, in, lanes, wide_out);
            shade_lambert_scalar(scene, in, lanes, one);
            INFO("normals " << normals << ", lights " << lights << ", solid angle "
                            << solid_angle << ", round " << round);
            REQUIRE(wide_out.taken == one.taken);
            REQUIRE(wide_out.shadow == one.shadow);
            REQUIRE(wide_out.bounce == one.bounce);
            auto same = [&](const float* a, const float* b, int k) {
              return std::bit_cast<uint32_t>(a[k]) == std::bit_cast<uint32_t>(b[k]);
            };
            int differ = 0;
            for (int k = 0; k < lanes; ++k) {
              const uint32_t bit = 1u << k;
              if (!(one.taken & bit)) continue;
              for (int a = 0; a < 3; ++a) {
                differ += !same(wide_out.beta[a], one.beta[a], k);
                differ += !same(wide_out.origin[a], one.origin[a], k);
                if (one.bounce & bit)
                  differ += !same(wide_out.direction[a], one.direction[a], k);
                if (one.shadow & bit) {
                  differ += !same(wide_out.to_light[a], one.to_light[a], k);
                  differ += !same(wide_out.contribution[a], one.contribution[a], k);
                }
              }
              if (one.bounce & bit) differ += !same(wide_out.pdf, one.pdf, k);
            }
            CHECK(differ == 0);
            lanes_run += lanes;
            taken += std::popcount(one.taken), shadows += std::popcount(one.shadow);
            bounces += std::popcount(one.bounce);
          }
        }
    // Not vacuous: most lanes are taken, and they make both kinds of ray.
    CHECK(taken > lanes_run / 2);
    CHECK(shadows > lanes_run / 20);  // (lights are off in half the runs)
    CHECK(bounces > lanes_run / 4);
  }
}
