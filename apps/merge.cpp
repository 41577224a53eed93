#include "apps/merge.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "apps/render_options.h"
#include "dacrt/io/color.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/film_exr.h"
#include "dacrt/render/part_plan.h"
#include "dacrt/render/render_job.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/memory.h"
#include "dacrt/util/paths.h"
#include "dacrt/util/progress.h"
#include "dacrt/util/text.h"

namespace dacrt {
namespace {

constexpr const char* merge_help = R"help(Usage: dacrt merge PART.exr... -o OUT.exr [options]

Adds the parts of one render into its image: each part is an EXR that `dacrt render --samples
FIRST:LAST` wrote (or any render output that kept its exact sums: --keep-sums, or a render cut
short). Their sums are added exactly, so OUT is bit for bit the image that one render of all
their samples makes: colour, every AOV, variance and sample counts. The parts must be of the same
render (every match.* attribute of their headers equal: the scene's files, size, camera,
integrator, sampler, seed, spp, ...), must not share a sample, and must hold every sample of the
--spp render. Anything else is refused with one line naming the files.

Options
  -o, --output OUT.exr       the merged image (required)
  --allow-gaps               merge parts that leave samples out: a warning and the header's
                             samplesMissing say which; the image has the samples there are
  --keep-sums                keep the exact sums in OUT even when it holds the whole render (it
                             keeps them anyway when it is one range of it: OUT is then a part too)
  --preview FILE.png         an 8-bit preview, as render's (--view NAME, --exposure STOPS)
  --quiet                    no progress or summary on stderr
  -h, --help                 this text
)help";

struct MergeArgs {
  std::vector<std::string> parts;
  std::string output, preview, display_flag;
  DisplayOptions display;
  bool allow_gaps = false, keep_sums = false, quiet = false, help = false;
};

MergeArgs parse_merge(const std::vector<std::string>& args) {
  MergeArgs m;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      m.help = true;
      return m;
    } else if (a == "-o" || a == "--output") {
      m.output = value();
    } else if (a == "--preview") {
      m.preview = value();
    } else if (parse_display_option(args, i, m.display, m.display_flag)) {
    } else if (a == "--allow-gaps") {
      m.allow_gaps = true;
    } else if (a == "--keep-sums") {
      m.keep_sums = true;
    } else if (a == "--quiet") {
      m.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError("unknown option " + a);
    } else {
      m.parts.push_back(a);
    }
  }
  if (m.parts.empty()) throw UsageError("merge needs the parts: dacrt merge PART.exr... -o OUT.exr");
  if (m.output.empty()) throw UsageError("merge needs -o OUT.exr");
  if (!m.display_flag.empty() && m.preview.empty())
    throw UsageError(m.display_flag + " needs --preview (it changes only the PNG preview)");
  return m;
}

// The attributes a merged file gets anew rather than from its first part.
const std::set<std::string> recomputed = {
    "spp",        "backend",        "integrator",       "renderSeconds",  "sampleRange",
    "sampleRangeMost", "samplesPerPixel", "stoppedBy", "samplesDropped", "samplesClamped",
    "exactSums",  "software",       "dacrtVersion",     "mergedFrom",     "samplesMissing",
    "sampleRanges"};

}  // namespace

int merge_main(const std::vector<std::string>& args) {
  const MergeArgs m = parse_merge(args);
  if (m.help) return std::fputs(merge_help, stdout), 0;
  std::vector<NamedFile> inputs, outputs = {{"-o", m.output}, {"--preview", m.preview}};
  for (const std::string& part : m.parts) {
    check_input_file(part, "part");
    inputs.push_back({"a part", part});
  }
  if (!m.preview.empty()) {
    set_color_warnings(!m.quiet);
    check_display_transform(m.display);
    for (const std::string& file : display_input_files())
      inputs.push_back({"the display configuration's file", file});
  }
  for (const NamedFile& out : outputs) check_writable(out.path);
  check_outputs(outputs, inputs);
  const auto t0 = std::chrono::steady_clock::now();

  // Every header first: nothing is read or added before the parts are known to fit.
  std::vector<ExrHeader> headers;
  std::vector<PartHeader> parts;
  for (const std::string& file : m.parts) {
    headers.push_back(read_sums_header(file, "to merge"));
    const auto& attributes = headers.back().attributes;
    if (const auto most = attributes.find("sampleRangeMost"); most != attributes.end())
      throw Error(file + " was cut short (some pixels have samples up to " + most->second +
                  "): finish it with `dacrt render ... --resume` before merging");
    parts.push_back(part_from_attributes(file, attributes));
  }
  const PartPlan plan = plan_merge(parts, m.allow_gaps);
  for (size_t i = 1; i < headers.size(); ++i)  // match.size said so; the files must agree
    if (headers[i].width != headers[0].width || headers[i].height != headers[0].height)
      throw Error(m.parts[i] + " is not " + std::to_string(headers[0].width) + " x " +
                  std::to_string(headers[0].height) + " pixels, as its match.size says");
  const int width = headers.front().width, height = headers.front().height;
  AovSet aovs;
  try {
    aovs = AovSet::parse(parts.front().match.at("match.aovs"));
  } catch (const std::exception&) {
    throw Error(m.parts.front() + ": its match.aovs attribute is missing or names unknown outputs");
  }

  // The merged film and one part's beside it, with the image channels and preview made from them.
  const uint64_t need = 2 * Film::bytes(width, height, aovs) +
                        uint64_t(width) * uint64_t(height) * (4 * Film::channel_count(aovs) + 15);
  if (need > available_memory())
    throw Error(m.parts.front() + ": merging " + std::to_string(width) + " x " +
                std::to_string(height) + " parts needs about " + format_bytes(need) +
                ", more than the " + format_bytes(available_memory()) + " of memory available");
  // The first part is read into the merged film itself, the others into one film beside it.
  Film film(width, height, aovs);
  std::optional<Film> part;
  Progress progress("merge", parts.size(), !m.quiet);
  double seconds = 0.0;
  std::set<std::string> backends;
  uint64_t done = 0;
  for (size_t i : plan.order) {
    const PartHeader& p = parts[i];
    if (done > 0 && !part) part.emplace(width, height, aovs);
    Film& into = done == 0 ? film : *part;
    read_film_state(p.file, headers[i], into, p.last - p.first, p.last - p.first);
    if (done > 0) film.merge(*part);  // tallies too
    const auto& attributes = headers[i].attributes;
    // Render times add up: each must be a number of seconds (a forged inf, NaN or 1e308 would
    // make the sum infinite).
    if (const auto it = attributes.find("renderSeconds"); it != attributes.end()) {
      char* end = nullptr;
      const double s = std::strtod(it->second.c_str(), &end);
      if (it->second.empty() || *end != '\0' || !(s >= 0.0 && s < 1e12))
        throw Error(p.file + ": its renderSeconds attribute \"" + one_line(it->second.substr(0, 40)) +
                    "\" is not a number of seconds");
      seconds += s;
    }
    if (attributes.count("backend")) backends.insert(attributes.at("backend"));
    progress.update(++done, 0);
  }
  progress.finish();

  // The header: the first part's, with what the union holds.
  std::vector<std::pair<uint32_t, uint32_t>> held;  // the samples in the parts, as ranges
  uint32_t next = 0;
  for (const auto& [from, to] : plan.missing) {
    if (from > next) held.push_back({next, from});
    next = to;
  }
  if (next < plan.spp) held.push_back({next, plan.spp});
  ExrMetadata meta;
  const uint32_t least = film.min_count(), most = film.max_count();
  meta.spp = int(least);
  for (const std::string& b : backends) meta.backend += (meta.backend.empty() ? "" : ", ") + b;
  meta.integrator = parts.front().match["match.integrator"];
  meta.render_seconds = seconds;
  for (const auto& [key, value] : headers[plan.order.front()].attributes)
    if (!recomputed.count(key)) meta.extra.push_back({key, value});
  std::string from;
  for (size_t i : plan.order)
    from += (from.empty() ? "" : ", ") + parts[i].file + " (" + std::to_string(parts[i].first) +
            ":" + std::to_string(parts[i].last) + ")";
  meta.extra.push_back({"mergedFrom", from});
  // One range is a part of the render (or the whole): sampleRange says which. Several are not
  // one range of anything: sampleRanges lists them.
  const bool one_range = held.size() == 1;
  if (one_range)
    meta.extra.push_back({"sampleRange", std::to_string(held[0].first) + ":" +
                                             std::to_string(held[0].second)});
  else
    meta.extra.push_back({"sampleRanges", ranges_text(held)});
  if (!plan.missing.empty()) {
    meta.extra.push_back({"samplesMissing", ranges_text(plan.missing)});
    print_message("warning: samples " + ranges_text(plan.missing) + " of the " +
                  std::to_string(plan.spp) + "-spp render are in no part: " + m.output +
                  " has " + std::to_string(least) + " spp");
  }
  meta.extra.push_back({"samplesPerPixel", samples_per_pixel_text(least, most)});
  meta.extra.push_back({"software", std::string("dacrt ") + version()});
  meta.extra.push_back({"dacrtVersion", version()});
  // One range short of the whole render is a part itself: it keeps its sums.
  const bool exact = one_range && (m.keep_sums || held[0] != std::pair(0u, plan.spp));
  write_film_exr(m.output, film, meta, exact);
  if (!m.preview.empty()) write_preview_png(m.preview, film.resolve(), m.display);
  if (!m.quiet) {
    char line[200];
    std::snprintf(line, sizeof line, ": %zu parts, %u of %u spp, merged in %.2f s", parts.size(),
                  least, plan.spp,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    print_message(m.output + line);
  }
  return 0;
}

}  // namespace dacrt
