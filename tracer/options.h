// Options: key=value settings for a plugin (backend or integrator), as given on the command line
// with --backend-option. Each plugin reads the keys it knows; unknown keys are an error, so a typo
// never silently falls back to a default.
#pragma once

#include <charconv>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "dacrt/util/error.h"

namespace dacrt {

class Options {
 public:
  Options() = default;

  void set(std::string key, std::string value) { values_[std::move(key)] = std::move(value); }
  // Parses "key=value"; throws Error on anything else.
  void parse(std::string_view assignment);
  bool has(std::string_view key) const { return values_.count(std::string(key)) != 0; }

  std::string get(std::string_view key, std::string fallback) const;
  double get(std::string_view key, double fallback) const;
  int get(std::string_view key, int fallback) const;

  // The options one plugin of several gets: keys "name.key" as "key", keys meant for another
  // plugin ("other.key") dropped, unprefixed keys kept.
  Options for_plugin(std::string_view name) const;

  // Throws Error naming the first key "prefix.key" whose prefix is not one of `plugins` (a typo
  // such as "dacr.bins" or ".bins" would otherwise be dropped by for_plugin without a word).
  void check_prefixes(const std::vector<std::string>& plugins) const;

  // Throws Error naming `owner` if a key outside `known` was given.
  void check_known(std::string_view owner, const std::set<std::string, std::less<>>& known) const;

  int threads = 0;  // 0 = every core; not a key=value option (it has its own flag)

 private:
  std::map<std::string, std::string, std::less<>> values_;
};

}  // namespace dacrt
