// Registry: plugins (backends, integrators) by name. Each plugin adds itself with one static
// registration line; the CLI, the benchmarks and the tests create them by name.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "dacrt/util/error.h"

namespace dacrt {

template <typename Factory>
class Registry {
 public:
  explicit Registry(std::string kind) : kind_(std::move(kind)) {}

  void add(std::string name, Factory factory) { factories_[std::move(name)] = std::move(factory); }

  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& [name, factory] : factories_) out.push_back(name);
    return out;
  }

  // Throws Error listing what is available when `name` is unknown.
  const Factory& find(std::string_view name) const {
    auto it = factories_.find(name);
    if (it != factories_.end()) return it->second;
    std::string list;
    for (const auto& n : names()) list += (list.empty() ? "" : ", ") + n;
    throw Error("unknown " + kind_ + " '" + std::string(name) + "' (available: " + list + ")");
  }

 private:
  std::string kind_;
  std::map<std::string, Factory, std::less<>> factories_;
};

}  // namespace dacrt
