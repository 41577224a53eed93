#include "dacrt/integrators/lambert_lanes.h"

#include "dacrt/integrators/lambert_kernel.h"
#include "dacrt/util/cpu.h"

namespace dacrt {

// Defined in lambert_lanes_avx2.cpp and lambert_lanes_avx512.cpp.
void shade_lambert_avx2(const LambertScene& scene, const LambertIn& in, int lanes,
                        LambertOut& out);
void shade_lambert_avx512(const LambertScene& scene, const LambertIn& in, LambertOut& out);
void sample_brdf_avx2(const BrdfIn& in, int lanes, BrdfOut& out);

namespace {

struct OneLane {
  using F = float;
  static float load(const float* a, int k) { return a[k]; }
  static void store(float* a, int k, float v) { a[k] = v; }
  static void mask(uint32_t& m, int k, bool b) { m |= uint32_t(b) << k; }
};

}  // namespace

const char* name(LambertLanes instance) {
  switch (instance) {
    case LambertLanes::one: return "one float";
    case LambertLanes::avx2: return "AVX2";
    case LambertLanes::avx512: return "AVX-512";
  }
  return "?";
}

bool lambert_available(LambertLanes instance) {
  switch (instance) {
    case LambertLanes::one: return true;
    case LambertLanes::avx2: return avx2_available();
    case LambertLanes::avx512: return lambert_avx512_available();
  }
  return false;
}

LambertLanes lambert_widest() {
  static const LambertLanes widest = lambert_avx512_available() ? LambertLanes::avx512
                                     : avx2_available() ? LambertLanes::avx2
                                                                : LambertLanes::one;
  return widest;
}

void shade_lambert_scalar(const LambertScene& scene, const LambertIn& in, int lanes,
                          LambertOut& out) {
  out.taken = out.shadow = out.bounce = 0;
  for (int k = 0; k < lanes; ++k) lambert_vertex<OneLane>(scene, in, k, out);
}

void shade_lambert(LambertLanes instance, const LambertScene& scene, const LambertIn& in,
                   int lanes, LambertOut& out) {
  switch (instance) {
    case LambertLanes::one: return shade_lambert_scalar(scene, in, lanes, out);
    case LambertLanes::avx2: shade_lambert_avx2(scene, in, lanes, out); break;
    case LambertLanes::avx512: shade_lambert_avx512(scene, in, out); break;
  }
  const uint32_t used = lanes >= 32 ? ~0u : (1u << lanes) - 1u;
  out.taken &= used, out.shadow &= used, out.bounce &= used;
}

void shade_lambert(const LambertScene& scene, const LambertIn& in, int lanes, LambertOut& out) {
  shade_lambert(lambert_widest(), scene, in, lanes, out);
}

void sample_brdf(LambertLanes instance, const BrdfIn& in, int lanes, BrdfOut& out) {
  if (instance == LambertLanes::one) {
    out.sampled = 0;
    for (int k = 0; k < lanes; ++k) brdf_sample<OneLane>(in, k, out);
    return;
  }
  sample_brdf_avx2(in, lanes, out);
  out.sampled &= lanes >= 32 ? ~0u : (1u << lanes) - 1u;
}

void sample_brdf(const BrdfIn& in, int lanes, BrdfOut& out) {
  static const LambertLanes widest =
      avx2_available() ? LambertLanes::avx2 : LambertLanes::one;
  sample_brdf(widest, in, lanes, out);
}

}  // namespace dacrt
