#include "dacrt/integrators/lambert_lanes.h"

#include "dacrt/integrators/lambert_kernel.h"

namespace dacrt {

// Defined in lambert_lanes_avx512.cpp.
void shade_lambert_avx512(const LambertScene& scene, const LambertIn& in, LambertOut& out);

namespace {

struct OneLane {
  using F = float;
  static float load(const float* a, int k) { return a[k]; }
  static void store(float* a, int k, float v) { a[k] = v; }
  static void mask(uint32_t& m, int k, bool b) { m |= uint32_t(b) << k; }
};

}  // namespace

void shade_lambert_scalar(const LambertScene& scene, const LambertIn& in, int lanes,
                          LambertOut& out) {
  out.taken = out.shadow = out.bounce = 0;
  for (int k = 0; k < lanes; ++k) lambert_vertex<OneLane>(scene, in, k, out);
}

void shade_lambert(const LambertScene& scene, const LambertIn& in, int lanes, LambertOut& out) {
  if (!lambert_avx512_available()) return shade_lambert_scalar(scene, in, lanes, out);
  shade_lambert_avx512(scene, in, out);
  const uint32_t used = lanes >= 32 ? ~0u : (1u << lanes) - 1u;
  out.taken &= used, out.shadow &= used, out.bounce &= used;
}

}  // namespace dacrt
