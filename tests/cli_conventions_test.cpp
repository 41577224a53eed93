// The command line's conventions, as users of other tools expect them (issue 50): --opt=value is
// --opt value, a misspelt option or value gets the nearest one, a usage error points to the help
// of the command it was made in and exits 2 (a display view that does not exist too), and
// --version says the version.
#include <doctest/doctest.h>

#include <string>

#include "cli.h"
#include "dacrt/render/render_job.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {
const std::string cornell = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";

// The first line of stderr.
std::string first_line(const Run& r) { return r.err.substr(0, r.err.find('\n')); }
}  // namespace

TEST_CASE("cli conventions: --opt=value is --opt value, in render, converge, merge and diff") {
  TempDir dir("cli-equals");
  const std::string small = " --width 8 --height 8 --quiet";
  const Run spaced = run(dir, "render " + cornell + small + " --spp 2 --seed 3 -o " +
                                  (dir / "a.exr"));
  const Run joined = run(dir, "render " + cornell + small + " --spp=2 --seed=3 --output=" +
                                  (dir / "b.exr") + " --backend-option=dacrt.bins=16");
  REQUIRE(spaced.code == 0);
  REQUIRE_MESSAGE(joined.code == 0, joined.err);
  // The same render (the EXR's pixels; bins do not change a hit).
  CHECK(slurp(dir / "a.exr").size() == slurp(dir / "b.exr").size());
  // A flag takes no value; a value may itself hold '=' or begin with "--".
  Run flag = run(dir, "render " + cornell + " --keep-sums=yes");
  CHECK(flag.code == 2);
  CHECK(first_line(flag).find("--keep-sums takes no value") != std::string::npos);
  Run converge = run(dir, "converge " + cornell + " --time-budget=0");
  CHECK(converge.code == 2);
  CHECK(first_line(converge).find("--time-budget wants a positive number") != std::string::npos);
  Run merge = run(dir, "merge --output=" + (dir / "m.exr"));
  CHECK(merge.code == 2);
  CHECK(first_line(merge).find("merge needs the parts") != std::string::npos);
  Run diff = run(dir, "diff a.exr b.exr --scale=2");
  CHECK(diff.code == 2);
  CHECK(first_line(diff).find("--scale needs --preview") != std::string::npos);
}

TEST_CASE("cli conventions: a misspelt option, command or value gets the nearest one") {
  TempDir dir("cli-suggest");
  struct Case {
    std::string args, says;
  };
  const Case cases[] = {
      {"render x.gltf --sampels 0:2", "unknown option --sampels (did you mean --samples?)"},
      {"render x.gltf --spp-pass=4", "unknown option --spp-pass (see"},
      {"render x.gltf --integrator pth", "unknown integrator 'pth' (did you mean path?)"},
      {"render x.gltf --sampler sobl", "unknown sampler 'sobl' (did you mean sobol?)"},
      {"render x.gltf --backend embre", "(did you mean embree?)"},
      {"render x.gltf --sample-environment offf", "(did you mean off?)"},
      {"render x.gltf --light-sampler treee",
       "--light-sampler wants auto, tree or power, not 'treee' (did you mean tree?)"},
      {"rendr x.gltf", "unknown command 'rendr' (did you mean render?)"},
      {"converge x.gltf --time-buget 3", "(did you mean --time-budget?)"},
      {"converge x.gltf --max-dept 3", "(did you mean --max-depth?)"},
      {"merge a.exr --alow-gaps", "(did you mean --allow-gaps?)"},
      {"diff a.exr b.exr --jsn", "(did you mean --json?)"},
  };
  for (const Case& c : cases) {
    const Run r = run(dir, c.args);
    INFO(c.args << " → " << r.err);
    CHECK(r.code == 2);
    CHECK(first_line(r).find(c.says) != std::string::npos);
  }
  // Nothing near: no suggestion.
  const Run far = run(dir, "render x.gltf --colour 3");
  CHECK(first_line(far).find("did you mean") == std::string::npos);
}

TEST_CASE("cli conventions: a usage error points to its command's help and exits 2") {
  TempDir dir("cli-pointer");
  const std::pair<const char*, const char*> cases[] = {
      {"render x.gltf --spp 0", "(see dacrt render --help)"},
      {"converge x.gltf --repeats 0", "(see dacrt converge --help)"},
      {"merge a.exr", "(see dacrt merge --help)"},
      {"diff a.exr", "(see dacrt diff --help)"},
      {"info", "(see dacrt info --help)"},
      {"frobnicate", "(see dacrt --help)"},
  };
  for (const auto& [args, says] : cases) {
    const Run r = run(dir, args);
    INFO(args << " → " << r.err);
    CHECK(r.code == 2);
    // One pointer, at the end of the line.
    const std::string line = first_line(r), pointer = says;
    CHECK(line.size() >= pointer.size());
    CHECK(line.compare(line.size() - pointer.size(), pointer.size(), pointer) == 0);
    CHECK(line.find("(see ") == line.size() - pointer.size());
  }
  // A display view that does not exist is the caller's mistake: exit 2, nothing written.
  const Run view = run(dir, "render " + cornell + " --width 8 --height 8 --spp 1 --quiet -o " +
                                (dir / "v.exr") + " --preview " + (dir / "v.png") +
                                " --view ACES");
  CHECK(view.code == 2);
  CHECK(first_line(view).find("no view 'ACES'") != std::string::npos);
  CHECK(first_line(view).find("(see dacrt render --help)") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "v.exr"));
}

TEST_CASE("cli conventions: --version says the version") {
  TempDir dir("cli-version");
  const Run r = run(dir, "--version");
  CHECK(r.code == 0);
  CHECK(r.out == std::string("dacrt ") + version() + "\n");
  CHECK(r.err.empty());
  CHECK(run(dir, "--help").out.find("--version") != std::string::npos);
}
