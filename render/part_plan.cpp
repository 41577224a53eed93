#include "dacrt/render/part_plan.h"

#include <algorithm>
#include <numeric>

#include "dacrt/util/error.h"

namespace dacrt {
namespace {

std::string range(uint32_t first, uint32_t last) {
  return std::to_string(first) + ":" + std::to_string(last);
}

// The first key in which b differs from a (a key one has and the other lacks counts), or "".
std::string first_difference(const std::map<std::string, std::string>& a,
                             const std::map<std::string, std::string>& b) {
  for (const auto& [key, value] : a)
    if (auto it = b.find(key); it == b.end() || it->second != value) return key;
  for (const auto& [key, value] : b)
    if (!a.count(key)) return key;
  return "";
}

std::string value_in(const std::map<std::string, std::string>& match, const std::string& key) {
  const auto it = match.find(key);
  return it == match.end() ? "missing" : it->second;
}

// A decimal count in [0, 2^20], or −1.
int64_t count_in(const std::string& text) {
  if (text.empty() || text.size() > 7 ||
      !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return -1;
  const int64_t n = std::stoll(text);
  return n <= (1 << 20) ? n : -1;
}

}  // namespace

PartHeader part_from_attributes(const std::string& file,
                                const std::map<std::string, std::string>& attributes) {
  PartHeader part;
  part.file = file;
  for (const auto& [key, value] : attributes)
    if (key.rfind("match.", 0) == 0) part.match[key] = value;
  if (part.match.empty())
    throw Error(file + " has no match.* attributes: it was not written by dacrt render");
  const auto range = attributes.find("sampleRange");
  const size_t colon = range == attributes.end() ? std::string::npos : range->second.find(':');
  const int64_t first = colon == std::string::npos ? -1 : count_in(range->second.substr(0, colon));
  const int64_t last = colon == std::string::npos ? -1 : count_in(range->second.substr(colon + 1));
  const int64_t spp = count_in(value_in(part.match, "match.spp"));
  if (first < 0 || last < first)
    throw Error(file + ": its sampleRange attribute is missing or not FIRST:LAST");
  if (spp <= 0) throw Error(file + ": its match.spp attribute is missing or not a count");
  part.first = uint32_t(first), part.last = uint32_t(last), part.spp = uint32_t(spp);
  return part;
}

void check_same_render(const PartHeader& file, const std::map<std::string, std::string>& now) {
  const std::string key = first_difference(file.match, now);
  if (!key.empty())
    throw Error(file.file + " is not an earlier run of this render: " + key + " is " +
                value_in(file.match, key) + " in " + file.file + ", " + value_in(now, key) +
                " here");
}

std::string ranges_text(const std::vector<std::pair<uint32_t, uint32_t>>& ranges) {
  std::string text;
  for (const auto& [first, last] : ranges) {
    if (!text.empty()) text += ", ";
    text += range(first, last);
  }
  return text;
}

PartPlan plan_merge(const std::vector<PartHeader>& parts, bool allow_gaps) {
  if (parts.empty()) throw Error("merge needs at least one part");
  const PartHeader& base = parts.front();
  if (base.match.empty())
    throw Error(base.file + " has no match.* attributes: it was not written by dacrt render");
  for (const PartHeader& p : parts) {
    const std::string key = first_difference(base.match, p.match);
    if (!key.empty())
      throw Error(p.file + " and " + base.file + " are not parts of one render: " + key + " is " +
                  value_in(p.match, key) + " in " + p.file + ", " + value_in(base.match, key) +
                  " in " + base.file);
    if (!(p.first < p.last) || p.last > p.spp)
      throw Error(p.file + ": its samples " + range(p.first, p.last) + " are not part of a " +
                  std::to_string(p.spp) + "-spp render");
  }
  PartPlan plan;
  plan.spp = base.spp;
  plan.order.resize(parts.size());
  std::iota(plan.order.begin(), plan.order.end(), size_t(0));
  std::stable_sort(plan.order.begin(), plan.order.end(),
                   [&](size_t a, size_t b) { return parts[a].first < parts[b].first; });
  uint32_t next = 0;  // the first sample not yet in a part
  const PartHeader* previous = nullptr;
  for (size_t i : plan.order) {
    const PartHeader& p = parts[i];
    if (previous && p.first < previous->last)
      throw Error(previous->file + " (" + range(previous->first, previous->last) + ") and " +
                  p.file + " (" + range(p.first, p.last) + ") overlap: samples " +
                  range(p.first, std::min(p.last, previous->last)) + " are in both");
    if (p.first > next) plan.missing.push_back({next, p.first});
    next = p.last;
    previous = &p;
  }
  if (next < plan.spp) plan.missing.push_back({next, plan.spp});
  if (!plan.missing.empty() && !allow_gaps)
    throw Error("samples " + ranges_text(plan.missing) + " of the " + std::to_string(plan.spp) +
                "-spp render are in no part (--allow-gaps merges what there is)");
  return plan;
}

}  // namespace dacrt
