// `dacrt completion bash` in bash itself: the script is sourced, COMP_WORDS and COMP_CWORD set as
// bash sets them for a line being completed, the completion function called, and COMPREPLY read;
// every option each --help defines is offered for its command. `dacrt man` through groff: no
// warning, every option each --help prints in that command's section, and the page the build
// made beside the CLI is the one the CLI prints.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli.h"
#include "dacrt/tracer/backend.h"
#include "help_text.h"

using namespace dacrt::test;
namespace fs = std::filesystem;

namespace {

// A bash word, single-quoted.
std::string quoted(const std::string& word) {
  std::string q = "'";
  for (char c : word) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Completes `words` in bash (the last one is the word under the cursor, "" for a new one) with
// the script `script`, in `dir`: COMPREPLY, one entry a line, sorted.
std::vector<std::string> complete(const TempDir& dir, const std::string& script,
                                  const std::vector<std::string>& words) {
  std::string line;
  for (const std::string& w : words) line.append(" ").append(quoted(w));
  const std::string program = "cd " + quoted(dir.path().string()) + " && source " +
                              quoted(script) + " && COMP_WORDS=(" + line +
                              ") && COMP_CWORD=$(( ${#COMP_WORDS[@]} - 1 )) && COMPREPLY=() && "
                              "{ _dacrt; printf '%s\\n' \"${COMPREPLY[@]}\" | LC_ALL=C sort; }";
  const std::string out_file = dir / "completed.txt";
  const std::string command =
      "bash -c " + quoted(program) + " >" + quoted(out_file) + " 2>&1 </dev/null";
  const int status = std::system(command.c_str());
  const std::string out = slurp(out_file);
  INFO("bash -c " << program << "\n" << out);
  CHECK(status == 0);
  std::vector<std::string> reply;
  for (const std::string& l : lines_of(out))
    if (!l.empty()) reply.push_back(l);
  return reply;
}

using Words = std::vector<std::string>;

}  // namespace

TEST_CASE("completion: bash completes the commands, options, known values and file names") {
  TempDir dir("completion");
  const std::string script = dir / "dacrt.bash";
  REQUIRE(run(dir, "completion bash", "", script).code == 0);
  for (const char* file : {"a.png", "b.exr", "c.gltf", "d.glb", "e.txt"}) std::ofstream(dir / file);
  fs::create_directory(dir.path() / "f");
  const std::string dacrt = DACRT_CLI;

  CHECK(complete(dir, script, {dacrt, "ren"}) == Words{"render"});
  CHECK(complete(dir, script, {dacrt, "c"}) == Words{"completion", "converge", "convert"});
  CHECK(complete(dir, script, {dacrt, "render", "--sp"}) == Words{"--spp"});
  CHECK(complete(dir, script, {dacrt, "render", "--look"}) == Words{"--look-at", "--look-from"});
  // Values the option table knows; a list's item after its last comma; --opt=value.
  const std::vector<std::string> backends = dacrt::Backend::names();
  if (std::count(backends.begin(), backends.end(), "embree")) {
    CHECK(complete(dir, script, {dacrt, "render", "--backend", "e"}) == Words{"embree"});
    CHECK(complete(dir, script, {dacrt, "render", "--backend", "dacrt,e"}) ==
          Words{"dacrt,embree"});
    CHECK(complete(dir, script, {dacrt, "render", "--backend", "=", "e"}) == Words{"embree"});
  }
  CHECK(complete(dir, script, {dacrt, "render", "--backend", "b"}) == Words{"brute"});
  CHECK(complete(dir, script, {dacrt, "render", "--integrator", "d"}) ==
        Words{"depth", "direct"});
  CHECK(complete(dir, script, {dacrt, "render", "--sampler", ""}) ==
        Words{"independent", "sobol"});
  CHECK(complete(dir, script, {dacrt, "render", "--sample-environment", "o"}) ==
        Words{"off", "on"});
  CHECK(complete(dir, script, {dacrt, "render", "--aov", "albedo,n"}) == Words{"albedo,normal"});
  CHECK(complete(dir, script, {dacrt, "render", "--spp", ""}).empty());  // a number
  // The display views, from `dacrt views` (the first word is the CLI to ask), quoted for bash.
  CHECK(complete(dir, script, {dacrt, "render", "--preview", "p.png", "--view", "sR"}) ==
        Words{"sRGB"});
  CHECK(complete(dir, script, {dacrt, "render", "--view", "ACES\\ 1.0\\ SDR-video\\ (s"}) ==
        Words{"ACES\\ 1.0\\ SDR-video\\ \\(sRGB\\)"});
  CHECK(complete(dir, script, {dacrt, "merge", "--view", "sR"}) == Words{"sRGB"});
  // File names by the extension the option or argument takes, and folders.
  CHECK(complete(dir, script, {dacrt, "render", ""}) == Words{"c.gltf", "d.glb", "f"});
  CHECK(complete(dir, script, {dacrt, "render", "c.gltf", "-o", ""}) == Words{"b.exr", "f"});
  CHECK(complete(dir, script, {dacrt, "render", "c.gltf", "--preview", ""}) == Words{"a.png", "f"});
  CHECK(complete(dir, script, {dacrt, "render", "--environment", ""}) == Words{"b.exr", "f"});
  CHECK(complete(dir, script, {dacrt, "render", "--report", ""}) == Words{"f"});
  CHECK(complete(dir, script, {dacrt, "diff", ""}) == Words{"b.exr", "f"});
  CHECK(complete(dir, script, {dacrt, "info", "--animation", "a"}) == Words{"all"});
  CHECK(complete(dir, script, {dacrt, "bench", "--sweep", ""}) == Words{"rays", "triangles"});
  CHECK(complete(dir, script, {dacrt, "completion", ""}) == Words{"bash"});
  CHECK(complete(dir, script, {dacrt, "views", "--h"}) == Words{"--help"});  // every command's
  // converge: its own options and the render options it takes, not those it does not.
  CHECK(complete(dir, script, {dacrt, "converge", "--time-b"}) == Words{"--time-budget"});
  CHECK(complete(dir, script, {dacrt, "converge", "--look-f"}) == Words{"--look-from"});
  CHECK(complete(dir, script, {dacrt, "converge", "--pre"}).empty());

  // Every option each command's --help defines is offered for that command.
  for (const Help& h : helps()) {
    if (h.command.empty()) continue;
    const std::vector<std::string> offered = complete(dir, script, {dacrt, h.command, "-"});
    const Names defined = defined_options(h.text);
    for (const std::string& option : defined)
      CHECK_MESSAGE(std::count(offered.begin(), offered.end(), option),
                    "dacrt " << h.command << " --help defines " << option
                             << ", which completion does not offer");
  }
  // And every command.
  const Words commands = complete(dir, script, {dacrt, ""});
  for (const std::string& command : listed_commands(run(dir, "--help").out))
    CHECK_MESSAGE(std::count(commands.begin(), commands.end(), command),
                  "completion does not offer the command " << command);
}

TEST_CASE("completion: an unknown shell is a usage error") {
  TempDir dir("completion-usage");
  const Run r = run(dir, "completion zsh");
  CHECK(r.code == 2);
  CHECK(r.err.find("completion knows bash") != std::string::npos);
  CHECK(r.err.find("dacrt completion --help") != std::string::npos);
  CHECK(run(dir, "completion").code == 2);
  CHECK(run(dir, "man extra").code == 2);
}

TEST_CASE("man: the page renders without a warning and has every option of every --help") {
  TempDir dir("man");
  const std::string page = dir / "dacrt.1";
  REQUIRE(run(dir, "man", "", page).code == 0);
  // The page the build made beside the CLI is this one.
  CHECK(slurp(fs::path(DACRT_CLI).parent_path() / "dacrt.1") == slurp(page));
  CHECK(slurp(fs::path(DACRT_CLI).parent_path() / "dacrt.bash") ==
        run(dir, "completion bash").out);
  if (std::system("command -v groff >/dev/null 2>&1") != 0) {
    MESSAGE("skipped the rendering: groff is not installed");
    return;
  }
  // Plain text (no bold or underline), lines long enough not to break an option's name.
  const std::string text = dir / "dacrt.txt", warnings = dir / "warnings.txt";
  const std::string command = "groff -man -Tutf8 -ww -rLL=250n -P -cbou " + page + " >" + text +
                              " 2>" + warnings;
  REQUIRE(std::system(command.c_str()) == 0);
  CHECK(slurp(warnings) == "");
  const std::string shown = slurp(text);
  CHECK(shown.find("dacrt - a path tracer") != std::string::npos);

  // Each command's section (".SS dacrt NAME": "   dacrt NAME" on a line of its own) holds every
  // option that command's --help prints; the description, the top level's.
  const std::vector<Help> all = helps();
  std::vector<std::pair<std::string, size_t>> starts;
  for (const Help& h : all) {
    if (h.command.empty()) continue;
    const size_t at = shown.find("\n   dacrt " + h.command + "\n");
    CHECK_MESSAGE(at != std::string::npos, "the page has no section for dacrt " << h.command);
    starts.push_back({h.command, at});
  }
  for (const Help& h : all) {
    size_t begin = shown.find("\nDESCRIPTION\n"), end = shown.find("\nCOMMANDS\n");
    for (size_t k = 0; k < starts.size(); ++k)
      if (starts[k].first == h.command)
        begin = starts[k].second,
        end = k + 1 < starts.size() ? starts[k + 1].second : shown.find("\nEXIT STATUS\n");
    REQUIRE(begin != std::string::npos);
    const std::string section = shown.substr(begin, end - begin);
    for (const std::string& option : printed_options(h.text))
      CHECK_MESSAGE(has_token(section, option), "dacrt " << h.command << " --help prints "
                                                          << option << ", its section in the "
                                                          << "man page does not");
  }
  // man itself reads it.
  if (std::system("command -v man >/dev/null 2>&1") == 0) {
    const std::string read = "MANWIDTH=200 man -l -P cat " + page + " >" + text + " 2>" + warnings;
    CHECK(std::system(read.c_str()) == 0);
    CHECK(slurp(text).find("--backend-option") != std::string::npos);
  }
}
