#include "apps/merge.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "dacrt/render/request.h"
#include "dacrt/io/color.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/film_exr.h"
#include "dacrt/io/image_file.h"
#include "dacrt/render/header.h"
#include "dacrt/render/part_plan.h"
#include "dacrt/render/render_job.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/memory.h"
#include "dacrt/util/paths.h"
#include "dacrt/util/progress.h"
#include "dacrt/util/help_text.h"
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
  --preview FILE             the image alone, as render's --preview: .png or .jpg through the
                             display view, .hdr or .exr linear
  --view NAME                a .png or .jpg preview's display view (`dacrt views` lists them)
  --exposure STOPS           a .png or .jpg preview's exposure in stops (default 0)
  --quiet                    no progress or summary on stderr
  -h, --help                 this text
)help";

struct MergeArgs {
  std::vector<std::string> parts;
  std::string output, preview, display_flag;
  DisplayOptions display;
  bool allow_gaps = false, keep_sums = false, quiet = false, help = false;
};

MergeArgs parse_merge(const std::vector<std::string>& given) {
  MergeArgs m;
  std::vector<std::string> args = given;
  const std::vector<std::string> flags = help_flag_names(merge_help);
  for (size_t i = 0; i < args.size(); ++i) {
    split_option_value(args, i, flags);
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
      throw UsageError("unknown option " + a + did_you_mean(a, help_option_names(merge_help)));
    } else {
      m.parts.push_back(a);
    }
  }
  if (m.parts.empty()) throw UsageError("merge needs the parts: dacrt merge PART.exr... -o OUT.exr");
  if (m.output.empty()) throw UsageError("merge needs -o OUT.exr");
  if (output_format("-o", m.output) != ImageFormat::exr)
    throw UsageError("-o " + m.output + ": the merged image keeps what its parts held, in an "
                     "EXR (-o OUT.exr); --preview, or dacrt convert, makes a PNG or JPEG of it");
  const bool display = !m.preview.empty() && holds_display_values(output_format("--preview", m.preview));
  if (!m.display_flag.empty() && !display)
    throw UsageError(m.display_flag +
                     " needs a PNG or JPEG --preview: it changes only display values");
  return m;
}

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
    if (const std::string most = part_cut_short(attributes); !most.empty())
      throw Error(file + " was cut short (some pixels have samples up to " + most +
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
    seconds += part_render_seconds(p.file, attributes);
    if (const std::string backend = part_backend(attributes); !backend.empty())
      backends.insert(backend);
    progress.update(++done, 0);
  }
  progress.finish();

  // The header: the first part's, with what the union holds.
  const MergedHeader header = merged_header(headers[plan.order.front()].attributes, parts, plan,
                                            film, backends, seconds, m.keep_sums);
  const uint32_t least = film.min_count();
  if (!plan.missing.empty())
    print_message("warning: samples " + ranges_text(plan.missing) + " of the " +
                  std::to_string(plan.spp) + "-spp render are in no part: " + m.output +
                  " has " + std::to_string(least) + " spp");
  write_film_exr(m.output, film, header.meta, header.exact);
  if (!m.preview.empty())
    write_image(m.preview, film.resolve(), m.display, header.meta, {}, "--preview");
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
