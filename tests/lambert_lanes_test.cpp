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

#include "dacrt/materials/gltf_brdf.h"
#include "dacrt/materials/sampling.h"
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

TEST_CASE("brdf lanes: each instance this CPU runs gives GltfBrdf::sample's answers, bit for bit") {
  std::vector<LambertLanes> instances{LambertLanes::one};
  if (lambert_available(LambertLanes::avx2)) instances.push_back(LambertLanes::avx2);
  for (const LambertLanes instance : instances) {
    INFO("instance " << std::string(name(instance)));
    Draw r{0xb5df};
    int lanes_run = 0, sampled = 0, specular = 0, plain = 0;
    for (int round = 0; round < 400; ++round) {
      BrdfIn in{};
      struct Expected {
        bool sampled;
        glm::vec3 wi, weight;
        float pdf;
      } expected[BrdfIn::lanes];
      const int lanes = round % 5 == 4 ? 1 + round % 16 : 16;
      for (int k = 0; k < BrdfIn::lanes; ++k) {
        const int kind = (round * 16 + k) % 19;
        BrdfParams p;
        p.base_color = glm::vec3(r(), r(), r());
        p.metallic = kind == 1 ? 0.f : kind == 2 ? 1.f : r();
        p.roughness = kind == 3 ? 0.f : kind == 4 ? 1.f : r();
        p.ior = r.in(1.f, 3.f);
        if (kind == 5) p.specular = r(), p.specular_color = glm::vec3(r(), r(), r());
        if (kind == 6) p.base_color = glm::vec3(0.f);
        if (kind == 7) p.clearcoat = 0.5f;  // not plain: the lane is not taken
        const GltfBrdf brdf(p);
        glm::vec3 wo = glm::normalize(glm::vec3(r.in(-1, 1), r.in(-1, 1), r.in(0, 1)));
        if (kind == 8) wo = glm::vec3(0.f, 0.f, 1.f);  // (the visible normal's t1 fallback)
        if (kind == 9) wo.z = -wo.z;                   // below: no sample
        if (kind == 10) wo = glm::normalize(glm::vec3(1.f, 0.f, 1e-4f));  // grazing
        float u_lobe = r(), u1 = r(), u2 = r();
        if (kind == 11) u1 = 0.f;
        if (kind == 12) u2 = 0.5f, u1 = 0.5f;
        if (kind == 13) u_lobe = 0.f;
        const Frame frame(glm::normalize(glm::vec3(r.in(-1, 1), r.in(-1, 1), r.in(-1, 1))));
        glm::vec3 ng = glm::normalize(frame.n + 0.5f * glm::vec3(r.in(-1, 1), r.in(-1, 1), 0.f));
        if (kind == 14) ng = -ng;
        in.ok[k] = brdf.plain();
        plain += k < lanes && brdf.plain();
        for (int a = 0; a < 3; ++a) {
          in.wo[a][k] = wo[a], in.base[a][k] = brdf.base()[a], in.f0[a][k] = brdf.f0()[a];
          in.frame[0][a][k] = frame.s[a], in.frame[1][a][k] = frame.t[a];
          in.frame[2][a][k] = frame.n[a], in.ng[a][k] = ng[a];
        }
        in.u_lobe[k] = u_lobe, in.u[0][k] = u1, in.u[1][k] = u2;
        in.metallic[k] = brdf.metallic(), in.alpha[k] = brdf.alpha(), in.f90[k] = brdf.f90();
        // What PathTracer::material does with the one-at-a-time BRDF.
        const auto s = brdf.sample(wo, u_lobe, u1, u2);
        Expected& e = expected[k];
        e.sampled = false;
        if (brdf.plain() && s) {
          e.wi = frame.to_world(s->wi), e.weight = s->weight, e.pdf = s->pdf;
          e.sampled = s->wi.z > 0.f && glm::dot(e.wi, ng) > 0.f;
          specular += e.sampled && u_lobe < 0.5f * brdf.metallic();  // (surely the GGX lobe)
        }
      }
      BrdfOut out;
      sample_brdf(instance, in, lanes, out);
      INFO("round " << round);
      auto same = [](float a, float b) {
        return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b);
      };
      int differ = 0;
      for (int k = 0; k < lanes; ++k) {
        const bool lane = out.sampled >> k & 1;
        CHECK(lane == expected[k].sampled);
        if (!lane || !expected[k].sampled) continue;
        for (int a = 0; a < 3; ++a) {
          differ += !same(out.wi[a][k], expected[k].wi[a]);
          differ += !same(out.weight[a][k], expected[k].weight[a]);
        }
        differ += !same(out.pdf[k], expected[k].pdf);
        ++sampled;
      }
      CHECK((out.sampled >> lanes) == 0u);
      CHECK(differ == 0);
      lanes_run += lanes;
    }
    // Not vacuous: most lanes are plain and sampled, many by the specular lobe.
    CHECK(plain > lanes_run * 3 / 4);
    CHECK(sampled > lanes_run / 3);
    CHECK(specular > lanes_run / 20);
  }
}
