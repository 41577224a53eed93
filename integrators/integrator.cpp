#include "dacrt/integrators/integrator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "dacrt/util/error.h"
#include "dacrt/util/registry.h"

namespace dacrt {

namespace {
Registry<Integrator::Factory>& registry() {
  static Registry<Integrator::Factory> r("integrator");
  return r;
}
}  // namespace

Integrator::Registration::Registration(std::string name, Factory factory) {
  registry().add(std::move(name), std::move(factory));
}

std::vector<std::string> Integrator::names() {
  return registry().names();
}

std::unique_ptr<Integrator> Integrator::create(const Scene& scene, const Shot& shot,
                                               Backend& backend, const RenderSettings& settings) {
  return registry().find(settings.integrator)(scene, shot, backend, settings);
}

size_t resolve_wavefront(const RenderSettings& s, uint64_t paths) {
  const uint64_t n = s.wavefront > 0 ? s.wavefront : s.wavefront_budget / path_bytes(s.aovs);
  return size_t(std::clamp<uint64_t>(std::min(n, paths), 1, uint64_t(1) << 31));
}

}  // namespace dacrt
