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

Backend::Update Backend::frames_option(const Options& options, std::string_view backend,
                                       Update fallback) {
  const std::string value = options.get("frames", std::string(to_string(fallback)));
  if (value == "refit") return Update::refit;
  if (value == "rebuild") return Update::rebuild;
  if (value == "new") return Update::none;
  throw Error("backend " + std::string(backend) + ": option frames=" + value +
              " is not refit, rebuild or new");
}

const char* to_string(Backend::Update how) {
  switch (how) {
    case Backend::Update::refit:
      return "refit";
    case Backend::Update::rebuild:
      return "rebuild";
    case Backend::Update::build:
      return "build";
    case Backend::Update::none:
      return "new";
  }
  return "new";
}

}  // namespace dacrt
