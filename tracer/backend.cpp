#include "dacrt/tracer/backend.h"

#include "dacrt/util/registry.h"

namespace dacrt {

namespace {
Registry<Backend::Factory>& registry() {
  static Registry<Backend::Factory> r("backend");
  return r;
}
}  // namespace

Backend::Registration::Registration(std::string name, Factory factory) {
  registry().add(std::move(name), std::move(factory));
}

std::vector<std::string> Backend::names() {
  return registry().names();
}

std::unique_ptr<Backend> Backend::create(std::string_view name, const Geometry& geometry,
                                         const Options& options) {
  return registry().find(name)(geometry, options);
}

}  // namespace dacrt
