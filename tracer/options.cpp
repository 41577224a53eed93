#include "dacrt/tracer/options.h"

#include <cstdlib>

namespace dacrt {

void Options::parse(std::string_view assignment) {
  auto eq = assignment.find('=');
  if (eq == std::string_view::npos || eq == 0)
    throw Error("option '" + std::string(assignment) + "' is not of the form key=value");
  set(std::string(assignment.substr(0, eq)), std::string(assignment.substr(eq + 1)));
}

Options Options::for_plugin(std::string_view name) const {
  Options o;
  o.threads = threads;
  for (const auto& [key, value] : values_) {
    const size_t dot = key.find('.');
    if (dot == std::string::npos)
      o.values_[key] = value;
    else if (std::string_view(key).substr(0, dot) == name)
      o.values_[key.substr(dot + 1)] = value;
  }
  return o;
}

void Options::check_prefixes(const std::vector<std::string>& plugins) const {
  for (const auto& [key, value] : values_) {
    const size_t dot = key.find('.');
    if (dot == std::string::npos) continue;
    const std::string prefix = key.substr(0, dot);
    bool known = false;
    for (const std::string& p : plugins) known = known || p == prefix;
    if (known) continue;
    std::string list;
    for (const std::string& p : plugins) list += (list.empty() ? "" : ", ") + p;
    throw Error("option '" + key + "=" + value + "' is for " +
                (prefix.empty() ? std::string("no backend (nothing before the dot)")
                                : "'" + prefix + "', which is not one of the backends used") +
                " (" + list + ")");
  }
}

std::string Options::get(std::string_view key, std::string fallback) const {
  auto it = values_.find(key);
  return it == values_.end() ? fallback : it->second;
}

double Options::get(std::string_view key, double fallback) const {
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  const std::string& s = it->second;
  char* end = nullptr;
  double value = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0')
    throw Error("option " + std::string(key) + "=" + s + ": not a number");
  return value;
}

int Options::get(std::string_view key, int fallback) const {
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  const std::string& s = it->second;
  int value = 0;
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || ptr != s.data() + s.size())
    throw Error("option " + std::string(key) + "=" + s + ": not an integer");
  return value;
}

void Options::check_known(std::string_view owner,
                          const std::set<std::string, std::less<>>& known) const {
  for (const auto& [key, value] : values_) {
    if (known.count(key)) continue;
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    throw Error(std::string(owner) + " has no option '" + key +
                "' (it knows: " + (list.empty() ? "none" : list) + ")");
  }
}

}  // namespace dacrt
