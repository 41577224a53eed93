#include "tracer/backend.h"

#include "util/error.h"

#include <map>

namespace dacrt {

namespace {
std::map<std::string, Backend::Factory, std::less<>>& registry() {
  static std::map<std::string, Backend::Factory, std::less<>> r;
  return r;
}
}  // namespace

Backend::Registration::Registration(std::string name, Factory factory) {
  registry()[std::move(name)] = std::move(factory);
}

std::vector<std::string> Backend::names() {
  std::vector<std::string> out;
  for (const auto& [name, factory] : registry()) out.push_back(name);
  return out;
}

std::unique_ptr<Backend> Backend::create(std::string_view name, const Geometry& geometry,
                                         const Options& options) {
  auto it = registry().find(name);
  if (it == registry().end()) {
    std::string list;
    for (const auto& n : names()) list += (list.empty() ? "" : ", ") + n;
    throw Error("unknown backend '" + std::string(name) + "' (available: " + list + ")");
  }
  return it->second(geometry, options);
}

}  // namespace dacrt
