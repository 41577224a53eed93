// The render option table (render/request.h) is the parser, the help and the Python keywords:
// every option parses a value of its type through the table, is listed in `dacrt render --help`
// on its own lines (or on the lines of the option it goes with), and has one Python keyword;
// converge takes the options the table gives it. docs_test.cpp ties the help to docs/usage.md,
// tests/python/test_render.py the help to Python's keywords.
#include <doctest/doctest.h>

#include <map>
#include <set>
#include <string>
#include <vector>

#include "dacrt/render/request.h"

using namespace dacrt;

namespace {

// A valid value of each option, as the command line gives it.
std::string sample_value(const RenderOption& o) {
  static const std::map<std::string_view, std::string> by_name = {
      {"--view", "sRGB"},       {"--variant", "red"},       {"--animation", "walk"},
      {"--integrator", "ao"},   {"--sample-environment", "on"}, {"--sampler", "independent"},
      {"--light-sampler", "tree"}, {"--point-light", "0,1,0=1,1,1"}, {"--backend-option", "dacrt.bins=8"},
      {"--aov", "albedo,depth"}, {"--backend", "brute"},   {"--adaptive", "0.05"}};
  if (const auto it = by_name.find(o.name); it != by_name.end()) return it->second;
  switch (o.value) {
    case OptionValue::none: return "";
    case OptionValue::integer: return "3";
    case OptionValue::number: return "0.5";
    case OptionValue::path: return "out.exr";
    case OptionValue::point: return "1,2,3";
    case OptionValue::range: return "0:2";
    case OptionValue::colour_or_file: return "0.5,0.5,0.5";
    default: return "";  // a text option without a sample: the test below says so
  }
}

// The option column of an option's first help line: "  -o, --output OUT.exr".
std::string option_column(std::string_view help) {
  return std::string(help.substr(0, std::min<size_t>(help.find('\n'), 29)));
}

}  // namespace

TEST_CASE("render options: each has its help lines, one Python keyword, and parses its value") {
  std::set<std::string> names, keywords, sections_done;
  std::string section;
  for (const RenderOption& o : render_options()) {
    INFO(o.name);
    CHECK(names.insert(std::string(o.name)).second);
    if (o.uses & use_python) CHECK(keywords.insert(o.python_keyword()).second);
    // Sections are contiguous: --help prints each heading once.
    if (o.section != section) {
      CHECK(sections_done.insert(std::string(o.section)).second);
      section = o.section;
    }
    // The help names the option in its column (--height on --width's line).
    const std::string column = option_column(o.help.empty() ? find_render_option("--width")->help
                                                            : o.help);
    CHECK_MESSAGE(column.find(std::string(o.name)) != std::string::npos, column);
    if (!o.short_name.empty()) CHECK(column.find(std::string(o.short_name)) != std::string::npos);
    CHECK(render_help().find(std::string(o.help)) != std::string::npos);
    // The table's parser takes it with a value of its type, and the value alone.
    const std::string value = sample_value(o);
    REQUIRE_MESSAGE((o.value == OptionValue::none) == value.empty(),
                    "an option without a sample value here: add one");
    std::vector<std::string> args = {std::string(o.name), "SCENE"};
    if (!value.empty()) args.insert(args.begin() + 1, value);
    RenderRequest r;
    size_t i = 0;
    if (o.name == "--help") {
      CHECK_FALSE(parse_render_option(args, i, r));  // the caller's business
      continue;
    }
    CHECK(parse_render_option(args, i, r));
    CHECK(i == (value.empty() ? 0u : 1u));
    // Converge takes it where the table says so, and a configuration only what it may vary.
    i = 0;
    RenderRequest c;
    CHECK(parse_render_option(args, i, c, use_converge) == bool(o.uses & use_converge));
    i = 0;
    CHECK(parse_render_option(args, i, c, use_config) == bool(o.uses & use_config));
  }
  CHECK(find_render_option("-o")->name == "--output");
  CHECK(find_render_option("--spp")->python_keyword() == "spp");
  CHECK(find_render_option("--look-from")->python_keyword() == "look_from");
  CHECK(find_render_option("--aov")->python_keyword() == "aovs");
  CHECK(find_render_option("--nope") == nullptr);
}

TEST_CASE("render options: a value reaches the request, and a bad one is a usage error naming the flag") {
  const RenderRequest r = parse_render({"s.gltf", "--spp", "9", "--look-from", "1,2,3", "--aov",
                                        "albedo", "--point-light", "0,1,0=1,1,1",
                                        "--point-light", "0,2,0=1,1,1", "--samples", "2:5"});
  CHECK(r.settings.spp == 9);
  CHECK(r.settings.camera_override.from->y == 2.f);
  CHECK(r.settings.aovs.has(Aov::albedo));
  CHECK(r.settings.lights.size() == 2);
  CHECK(r.first_sample() == 2);
  CHECK(r.last_sample() == 5);
  CHECK(r.output == "s.exr");
  CHECK_THROWS_WITH_AS(parse_render({"s.gltf", "--spp", "0"}),
                       "--spp wants an integer in [1, 1048576], got '0'", UsageError);
  CHECK(parse_render({"s.gltf", "--spp=4", "--look-at=1,2,3"}).settings.spp == 4);
  CHECK_THROWS_WITH_AS(parse_render({"s.gltf", "--resume=1"}), "--resume takes no value",
                       UsageError);
  CHECK_THROWS_WITH_AS(parse_render({"s.gltf", "--spp", "0"}),
                       "--spp wants an integer in [1, 1048576], got '0'", UsageError);
  // The checks between options name them as the caller spells them.
  RenderRequest p;
  p.settings.spp = 4;
  p.samples = std::pair{0u, 8u};
  CHECK_THROWS_WITH_AS(check_request(p, [](std::string_view f) {
                         return std::string(f.substr(2)) + "=";
                       }),
                       "samples= 0:8 goes past spp= 4 (the render the samples belong to)",
                       UsageError);
}
