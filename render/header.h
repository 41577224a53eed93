// The EXR header of a render: every attribute dacrt writes, by one writer. A render's header
// (render_header) says what the image holds (spp, sampleRange, samplesPerPixel, the camera,
// adaptive sampling, why it stopped) and what identifies the render (match_keys: the match.*
// attributes); a merge's (merged_header) is its first part's with what the union holds. The
// match keys are also what parts, a resumed render and the ranks of an MPI job must share.
#pragma once

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "dacrt/film/film.h"
#include "dacrt/io/exr.h"
#include "dacrt/render/part_plan.h"
#include "dacrt/render/render_job.h"
#include "dacrt/render/request.h"
#include "dacrt/render/run_report.h"
#include "dacrt/scene/scene.h"

namespace dacrt {

// "software": "dacrt VERSION", which every EXR dacrt writes carries (the images of renders and
// merges, converge's reference, diff's error map).
std::pair<std::string, std::string> software_attribute();

// The match.* attributes, as name and value, in the order they are written.
using MatchKeys = std::vector<std::pair<std::string, std::string>>;

// What parts of one render (--samples ranges) must share to be merged, as EXR attributes
// "match.NAME": the scene's files (`inputs_hash`, their fingerprint), the image, the view, the
// light, how samples are drawn and kept. Everything that changes a sample's value is here; the
// threads, the wavefront and the passes are not (they never change a pixel), nor is the backend,
// but for its intersection test: dacrt, dacrt-naive and brute share one and find the same hits
// bit for bit, Embree's differ in the last bits. `animation` says which animations play.
MatchKeys match_keys(const RenderRequest& r, const Shot& shot, const std::string& animation,
                     const std::string& inputs_hash, const std::string& backend);

// The header of a render's EXR: `film` rendered by `run` as `outcome` says, `spp` the count every
// pixel has.
ExrMetadata render_header(const RenderRequest& r, const Scene& scene, const Shot& shot,
                          const BackendRun& run, const Film& film, const RenderOutcome& outcome,
                          const MatchKeys& keys);

// Whether a render's EXR keeps the film's exact sums: a part (--samples), a render short of its
// range (a stop, the time limit, a checkpoint), or --keep-sums.
bool keeps_exact_sums(const RenderRequest& r, const RenderOutcome& outcome);

// A part's sampleRangeMost (some pixels have more samples: a pass cut short), or "".
std::string part_cut_short(const std::map<std::string, std::string>& attributes);
// A part's renderSeconds (0 without it); Error naming `file` unless it is a number of seconds.
double part_render_seconds(const std::string& file,
                           const std::map<std::string, std::string>& attributes);
// A part's backend attribute, or "".
std::string part_backend(const std::map<std::string, std::string>& attributes);

// The header of merged parts: the first part's attributes (`first`) but for those the union
// recomputes, `film`'s sample counts, the parts in `plan`'s order (mergedFrom), the ranges held
// (sampleRange, or sampleRanges when several) and those missing, the backends and the sum of the
// render seconds. `exact`: whether the file keeps the exact sums (one range short of the whole,
// or --keep-sums).
struct MergedHeader {
  ExrMetadata meta;
  bool exact = false;
};
MergedHeader merged_header(const std::map<std::string, std::string>& first,
                           const std::vector<PartHeader>& parts, const PartPlan& plan,
                           const Film& film, const std::set<std::string>& backends,
                           double seconds, bool keep_sums);

}  // namespace dacrt
