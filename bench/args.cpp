#include "bench/args.h"

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <iterator>
#include <stdexcept>

#include "dacrt/tracer/backend.h"
#include "dacrt/tracer/dacrt/dacrt.h"
#include "dacrt/util/error.h"

namespace dacrt::bench {

namespace {

constexpr const char* bench_help_text = R"(Usage: dacrt bench SCENE [options]

Times every backend on the same rays, in the same run: build seconds (Backend::create), trace
seconds (one intersect or occluded call on the whole batch), Mrays/s without and with the build,
and the backend's peak working memory (MB = 10^6 bytes, the largest of the runs). Each backend
first makes one warm-up run per ray type, discarded; then each figure is the median of --repeat
runs, in brackets its 95 % confidence interval from order statistics (below 6 runs, which cannot
reach 95 %, the range of the runs and its coverage: 94 % for 5). Each run builds the backend anew.
Runs alternate between backends so that noise on a shared machine hits them alike. The table
goes to stdout, progress to stderr.

Ray types
  primary    the scene's first camera (framed on the bounds if the file has none), one ray per
             pixel centre; intersect
  shadow     primary hits to random points on emitters, or without emitters to a point above the
             scene (box centre + 2 × its largest side in +y); occluded
  ao         primary hits, cosine-weighted around the normal, tmax = 10 % of the box diagonal;
             occluded
  bounce     primary hits, cosine-weighted diffuse directions, tmax = inf; intersect
  random     uniform origins in the scene's box (a side under 1 % of the longest widened to that,
             so no origin lies on a flat scene's plane), uniform directions, tmax = inf; intersect
  Secondary rays start at the primary hits found by one reference backend (dacrt) before any
  timing; primary misses make none, so their count is the number of hits unless --count is given.

Options
  --rays LIST                ray types, comma-separated (default: primary,shadow,ao,bounce,random)
  --backends LIST            backends, comma-separated (default: every registered one but brute)
  --width W, --height H      primary resolution (default 1024 × 1024, or about 1024² pixels in the
                             camera's aspect ratio); one of them alone keeps the camera's aspect
  --count N                  rays per batch: primary renders about √N × √N pixels (camera aspect
                             kept; --width/--height win); shadow, ao, bounce draw exactly N rays,
                             ray i starting at primary hit i mod (number of hits); random draws N
  --repeat N                 timed runs per measurement, after the warm-up (default 5)
  --threads T                worker threads (default: all cores)
  --backend-option KEY=VALUE setting for the dacrt and dacrt-naive backends only, repeatable
                             (keys: @KEYS@)
  --sweep rays               each ray type at batch sizes 2^14, 2^15, ..., 2^22 (as --count)
  --sweep triangles          the scene decimated to every k-th triangle, k = 1, 2, 4, 8, 16, 32,
                             each with every ray type at --count
  --json FILE                also write the results as JSON
  --report DIR               also DIR/index.html: a self-contained page with the table and plots
                             of Mrays/s and speed-up per ray type, each with its interval
  --seed S                   seed of the ray generators (default 0)
  --tmax-at-hit              intersect rays (primary, bounce, random) end at their closest hit, found
                             by the reference backend before any timing: the work a traversal
                             would do if it always found the closest hit first (its order perfect)
  --quiet                    no progress on stderr
  -h, --help                 this text

The "speed-up vs B, higher is faster" column is the baseline B's trace seconds over the row's,
repeat by repeat, then their median and interval; B is embree when benchmarked, else dacrt-naive.
The JSON keeps every timed run's figures beside their median, interval and coverage.
)";

long parse_bench_int(const std::string& flag, const std::string& text, long lo, long hi) {
  char* end = nullptr;
  errno = 0;
  long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
    throw std::invalid_argument(flag + " wants an integer in [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "], got '" + text + "'");
  return v;
}

std::vector<std::string> split_list(const std::string& flag, const std::string& text) {
  std::vector<std::string> items;
  size_t start = 0;
  while (true) {
    size_t comma = text.find(',', start);
    std::string item = text.substr(start, comma == std::string::npos ? comma : comma - start);
    if (item.empty())
      throw std::invalid_argument(flag + " wants a comma-separated list, got '" + text + "'");
    bool seen = false;
    for (const auto& i : items) seen |= i == item;
    if (!seen) items.push_back(item);
    if (comma == std::string::npos) return items;
    start = comma + 1;
  }
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& i : items) out += (out.empty() ? "" : ", ") + i;
  return out;
}

}  // namespace

std::string bench_help() {
  std::string text = bench_help_text, keys;
  size_t column = 29 + 7;  // where "(keys: " ends
  for (const auto& key : DacrtParams::keys()) {
    if (!keys.empty()) {
      keys += ",";
      ++column;
      if (column + 1 + key.size() > 100) {
        keys += "\n" + std::string(29, ' ');
        column = 29;
      } else {
        keys += " ";
        ++column;
      }
    }
    keys += key;
    column += key.size();
  }
  return text.replace(text.find("@KEYS@"), 6, keys);
}

std::vector<std::string> default_bench_backends() {
  std::vector<std::string> out;
  for (const auto& name : Backend::names())
    if (name != "brute") out.push_back(name);
  return out;
}

BenchArgs parse_bench_args(const std::vector<std::string>& args) {
  BenchArgs b;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw std::invalid_argument(a + " needs a value");
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      b.help = true;
      return b;
    } else if (a == "--rays") {
      b.rays.clear();
      for (const auto& name : split_list(a, value())) {
        auto r = bench_ray_from(name);
        if (!r) {
          std::vector<std::string> known;
          for (BenchRay k : all_bench_rays) known.emplace_back(to_string(k));
          throw std::invalid_argument("--rays: unknown ray type '" + name +
                                      "' (available: " + join(known) + ")");
        }
        b.rays.push_back(*r);
      }
    } else if (a == "--backends") {
      b.backends = split_list(a, value());
      const auto known = Backend::names();
      for (const auto& name : b.backends) {
        bool found = false;
        for (const auto& k : known) found |= k == name;
        if (!found)
          throw std::invalid_argument("--backends: unknown backend '" + name +
                                      "' (available: " + join(known) + ")");
      }
    } else if (a == "--width") {
      b.width = int(parse_bench_int(a, value(), 1, 1 << 15));
    } else if (a == "--height") {
      b.height = int(parse_bench_int(a, value(), 1, 1 << 15));
    } else if (a == "--count") {
      b.count = size_t(parse_bench_int(a, value(), 1, 1L << 26));
    } else if (a == "--repeat") {
      b.repeat = int(parse_bench_int(a, value(), 1, 1000));
    } else if (a == "--threads") {
      b.threads = int(parse_bench_int(a, value(), 1, 1024));
    } else if (a == "--backend-option") {
      try {
        b.backend_options.parse(value());
      } catch (const Error& e) {
        throw std::invalid_argument(std::string("--backend-option: ") + e.what());
      }
      b.has_backend_options = true;
    } else if (a == "--sweep") {
      const std::string& v = value();
      if (v == "rays")
        b.sweep = Sweep::rays;
      else if (v == "triangles")
        b.sweep = Sweep::triangles;
      else
        throw std::invalid_argument("--sweep wants rays or triangles, got '" + v + "'");
    } else if (a == "--json") {
      b.json = value();
    } else if (a == "--report") {
      b.report = value();
    } else if (a == "--seed") {
      b.seed = uint64_t(parse_bench_int(a, value(), 0, LONG_MAX));
    } else if (a == "--tmax-at-hit") {
      b.tmax_at_hit = true;
    } else if (a == "--quiet") {
      b.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw std::invalid_argument("unknown option " + a);
    } else if (b.scene.empty()) {
      b.scene = a;
    } else {
      throw std::invalid_argument("unexpected argument '" + a + "' (one scene at a time)");
    }
  }
  if (b.scene.empty()) throw std::invalid_argument("bench needs a SCENE");
  if (b.rays.empty()) b.rays.assign(std::begin(all_bench_rays), std::end(all_bench_rays));
  if (b.backends.empty()) b.backends = default_bench_backends();
  if (b.backends.empty()) throw std::invalid_argument("no backend to benchmark");
  if (b.sweep == Sweep::rays && (b.count || b.width || b.height))
    throw std::invalid_argument(
        "--sweep rays chooses the batch sizes itself: drop --count, --width "
        "and --height");
  if (b.has_backend_options) {
    bool any = false;
    for (const auto& name : b.backends) any |= takes_backend_options(name);
    if (!any)
      throw std::invalid_argument(
          "--backend-option applies to dacrt and dacrt-naive only, and neither is benchmarked");
  }
  return b;
}

}  // namespace dacrt::bench
