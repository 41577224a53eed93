// What `dacrt merge` checks before it adds parts of one render (`render --samples FIRST:LAST`):
// the parts must be of the same render (every match.* key of their EXR headers equal), must not
// share a sample, and must together hold every sample of the --spp render unless gaps are
// allowed. The plan orders the parts by their first sample and lists the samples no part has.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace dacrt {

struct PartHeader {
  std::string file;
  uint32_t first = 0, last = 0;                // the part's samples [first, last)
  uint32_t spp = 0;                            // of the whole render (match.spp)
  std::map<std::string, std::string> match;    // the match.* attributes
};

struct PartPlan {
  uint32_t spp = 0;
  std::vector<size_t> order;                             // the parts by first sample
  std::vector<std::pair<uint32_t, uint32_t>> missing;    // samples in no part, in order
};

// Throws Error with one line naming the files: no parts; parts of different renders ("b.exr and
// a.exr are not parts of one render: match.seed is 6 in b.exr, 5 in a.exr"); a part past its
// render's spp; two parts that share samples; samples in no part (unless allow_gaps).
PartPlan plan_merge(const std::vector<PartHeader>& parts, bool allow_gaps);

// The part a file's header attributes describe: sampleRange FIRST:LAST, match.spp and every
// match.* attribute. Error naming the file when one is missing or malformed.
PartHeader part_from_attributes(const std::string& file,
                                const std::map<std::string, std::string>& attributes);

// For continuing a render from its output: Error unless the file's match.* attributes are
// `now`'s ("out.exr is not an earlier run of this render: match.seed is 6 in out.exr, 5 here").
void check_same_render(const PartHeader& file, const std::map<std::string, std::string>& now);

// "0:4, 6:8": ranges as text.
std::string ranges_text(const std::vector<std::pair<uint32_t, uint32_t>>& ranges);

}  // namespace dacrt
