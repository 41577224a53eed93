// plan_merge: what `dacrt merge` checks of its parts' headers before adding them.
#include "dacrt/render/part_plan.h"

#include <doctest/doctest.h>

#include <map>

#include "dacrt/util/error.h"

using namespace dacrt;

namespace {

// A part of an 8-spp render, its match keys changed by `changes` (an empty value: key removed).
PartHeader part(const std::string& file, uint32_t first, uint32_t last, uint32_t spp = 8,
                const std::map<std::string, std::string>& changes = {}) {
  PartHeader p{file, first, last, spp,
               {{"match.seed", "5"}, {"match.spp", std::to_string(spp)}, {"match.size", "24x16"}}};
  for (const auto& [key, value] : changes)
    if (value.empty())
      p.match.erase(key);
    else
      p.match.insert_or_assign(key, value);
  return p;
}

}  // namespace

TEST_CASE("part plan: parts in any order, by first sample, every sample in one part") {
  const PartPlan plan = plan_merge({part("c.exr", 5, 8), part("a.exr", 0, 2), part("b.exr", 2, 5)},
                                   false);
  CHECK(plan.spp == 8);
  CHECK(plan.order == std::vector<size_t>{1, 2, 0});
  CHECK(plan.missing.empty());
  CHECK(plan_merge({part("all.exr", 0, 8)}, false).order == std::vector<size_t>{0});
}

TEST_CASE("part plan: gaps, overlaps and other renders are refused, naming the files") {
  CHECK_THROWS_WITH_AS(plan_merge({part("a.exr", 0, 2), part("b.exr", 4, 6)}, false),
                       "samples 2:4, 6:8 of the 8-spp render are in no part (--allow-gaps merges "
                       "what there is)",
                       Error);
  const PartPlan gaps = plan_merge({part("b.exr", 4, 6), part("a.exr", 1, 2)}, true);
  CHECK(ranges_text(gaps.missing) == "0:1, 2:4, 6:8");
  CHECK_THROWS_WITH_AS(plan_merge({part("a.exr", 0, 5), part("b.exr", 3, 8)}, false),
                       "a.exr (0:5) and b.exr (3:8) overlap: samples 3:5 are in both", Error);
  CHECK_THROWS_WITH_AS(plan_merge({part("a.exr", 0, 8), part("b.exr", 2, 4)}, true),
                       "a.exr (0:8) and b.exr (2:4) overlap: samples 2:4 are in both", Error);
  CHECK_THROWS_WITH_AS(plan_merge({part("a.exr", 0, 4), part("b.exr", 4, 8, 8, {{"match.seed", "6"}})},
                                  false),
                       "b.exr and a.exr are not parts of one render: match.seed is 6 in b.exr, 5 "
                       "in a.exr",
                       Error);
  CHECK_THROWS_WITH_AS(plan_merge({part("a.exr", 0, 4), part("b.exr", 4, 8, 8, {{"match.size", ""}})},
                                  false),
                       doctest::Contains("match.size is missing in b.exr, 24x16 in a.exr"), Error);
  CHECK_THROWS_WITH_AS(
      plan_merge({part("a.exr", 0, 4), part("b.exr", 4, 8, 8, {{"match.aovs", "albedo"}})}, false),
                       doctest::Contains("match.aovs is albedo in b.exr, missing in a.exr"), Error);
  CHECK_THROWS_WITH_AS(plan_merge({part("a.exr", 0, 9)}, true),
                       "a.exr: its samples 0:9 are not part of a 8-spp render", Error);
  CHECK_THROWS_AS(plan_merge({}, true), Error);
  PartHeader foreign = part("x.exr", 0, 8);
  foreign.match.clear();
  CHECK_THROWS_WITH_AS(plan_merge({foreign}, false), doctest::Contains("x.exr has no match.*"),
                       Error);
}
