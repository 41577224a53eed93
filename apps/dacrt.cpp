// dacrt: the command-line front end. `dacrt render` path-traces a glTF scene to OpenEXR (plus a
// PNG preview), `dacrt info` describes a scene, `dacrt views` lists the preview's display views,
// `dacrt diff` compares two images.
// Exit codes: 0 success, 1 error (one line on stderr naming the file and what is wrong), 2 usage
// error.
#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "studies/converge.h"
#include "apps/convert.h"
#include "apps/completion.h"
#include "apps/diff.h"
#include "apps/info.h"
#include "apps/merge.h"
#include "apps/ranks.h"
#include "apps/render_report.h"
#include "dacrt/util/paths.h"
#include "bench/bench.h"
#include "bench/html_page.h"
#include "dacrt/integrators/integrator.h"
#include "dacrt/io/color.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/film_exr.h"
#include "dacrt/io/gltf.h"
#include "dacrt/render/part_plan.h"
#include "dacrt/render/render_job.h"
#include "dacrt/render/request.h"
#include "dacrt/render/session.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/file_hash.h"
#include "dacrt/util/interrupt.h"
#include "dacrt/util/memory.h"
#include "dacrt/util/paths.h"
#include "dacrt/util/progress.h"
#include "dacrt/util/text.h"

namespace fs = std::filesystem;
using namespace dacrt;

namespace {

// The processes of this run: one, or the ranks of `mpirun -np R dacrt render …` (apps/ranks.h).
Ranks* ranks = nullptr;
// Where a usage error points: the help of the command it was made in.
std::string help_pointer = "dacrt --help";

constexpr const char* main_help = R"(dacrt: a path tracer on divide-and-conquer ray tracing

Usage:
  dacrt render SCENE [options]   render a glTF 2.0 scene (.gltf or .glb) to OpenEXR (or PNG,
                                 JPEG, HDR: -o follows its extension)
  dacrt info SCENE [--scene N] [--animation NAME|INDEX|all]
                                 triangles, meshes, materials, variants, lights, animations,
                                 cameras, bounds
  dacrt views                    the display views a preview can use (`render --view`), from
                                 $OCIO when it is set
  dacrt bench SCENE [options]    every backend on the same rays of each type: build and trace
                                 time, Mrays/s, peak memory (`dacrt bench --help`)
  dacrt converge SCENE [options] run time against error: each configuration (--config
                                 "backend=embree") at 1, 2, 4, ... spp against a reference; a
                                 CSV, a plot, equal-error and equal-time tables
                                 (`dacrt converge --help`)
  dacrt diff A.exr B.exr         how far image A is from B (the reference): RMSE, relMSE,
                                 MAE, SMAPE, max |A-B| per channel; error maps as EXR and
                                 false-colour PNG (`dacrt diff --help`)
  dacrt merge PART.exr... -o OUT  add the parts of one render (`render --samples FIRST:LAST`)
                                 into its image, exactly (`dacrt merge --help`)
  dacrt convert IN.exr OUT       an EXR as PNG, JPEG, HDR or EXR, by OUT's extension, through
                                 the preview's display view (`dacrt convert --help`)
  dacrt completion bash          the bash completion script: `source <(dacrt completion bash)`
  dacrt man                      the manual page dacrt(1) in roff: `dacrt man | man -l -`
  dacrt --help                   this text; `dacrt render --help` lists the render options
  dacrt --version                the version
)";

int render(const std::vector<std::string>& args) {
  const RenderRequest r = parse_render(args);
  if (r.help) return std::fputs(render_help().c_str(), stdout), 0;
  SessionHooks hooks;
  hooks.ranks = ranks;
  // --report: the page and each backend's preview in DIR. The directory is made when its first
  // file is written, and goes again if the render fails; its files can be checked now only when
  // it is there already.
  std::optional<OutputDirectory> report_dir;
  if (!r.report.empty()) {
    report_dir.emplace("--report", r.report);
    hooks.more_outputs.push_back({"--report", HtmlPage::file_in(r.report)});
    for (const std::string& backend : split_list(r.backend))
      hooks.more_outputs.push_back({"--report", report_preview(r.report, backend)});
    if (report_dir->existed())
      for (const NamedFile& out : hooks.more_outputs) check_writable(out.path);
    hooks.rendered = [&](const BackendRun& run, const Film& film) {
      report_dir->make();
      write_preview_png(report_preview(r.report, run.backend), film.resolve(), r.display);
    };
  }
  RenderSession session(r, hooks);
  const int code = session.run();
  if (code != 0 || !ranks->root()) return code;  // stopped; or a rank whose share rank 0 wrote
  if (session.runs().size() > 1) print_comparison(stdout, session.runs());
  if (report_dir) {
    report_dir->make();
    write_render_report(r.report, session.title(), session.runs());
    report_dir->keep();
  }
  return 0;
}

constexpr const char* views_help = R"help(Usage: dacrt views

Lists the display views `dacrt render --preview OUT.png --view NAME` can use, one a line, the
default marked " (default)". With $OCIO set: every DISPLAY/VIEW of that config, from its
scene_linear role (a view of its default display may also be named VIEW alone). Without it: views
built from OpenColorIO's built-in transforms, for an sRGB and a Rec.1886 (gamma 2.4, HD video)
display, each without tone mapping (sRGB, the default, and Rec.1886) and through the ACES 1.0
output transform for SDR video (ACES 1.0 SDR-video (sRGB), ...).
)help";

int views(const std::vector<std::string>& args) {
  if (args.size() == 1 && (args[0] == "-h" || args[0] == "--help"))
    return std::fputs(views_help, stdout), 0;
  if (!args.empty()) throw UsageError("views takes no arguments");
  set_color_warnings(true);  // OpenColorIO's warnings as our one-line messages
  const DisplayViews views = display_views();
  for (const std::string& name : views.names)
    std::printf("%s%s\n", name.c_str(), name == views.default_name ? " (default)" : "");
  return 0;
}

constexpr const char* completion_help = R"help(Usage: dacrt completion bash

Prints the bash completion script: commands, each command's options, the values the options know
(backends, integrators, samplers, AOVs, display views) and file names by the extension each
option takes (a scene: .gltf and .glb). Load it with
  source <(dacrt completion bash)
in ~/.bashrc, or save it as ~/.local/share/bash-completion/completions/dacrt (`cmake --install`
puts it in PREFIX/share/bash-completion/completions).
)help";

constexpr const char* man_help = R"help(Usage: dacrt man

Prints the manual page dacrt(1) in roff, made of every command's --help: read it with
`dacrt man | man -l -`. `cmake --install` puts it in PREFIX/share/man/man1/dacrt.1.
)help";

int completion(const std::vector<std::string>& args);
int man(const std::vector<std::string>& args);

// Each command and what runs it.
using CommandMain = int (*)(const std::vector<std::string>&);
constexpr std::pair<const char*, CommandMain> commands[] = {
    {"render", render},         {"info", info_main}, {"views", views},       {"bench", bench_main},
    {"converge", converge_main}, {"diff", diff_main}, {"merge", merge_main}, {"completion", completion},
    {"man", man},               {"convert", convert_main}};

// What `main({"--help"})` prints on stdout: the command's help, as its users read it.
std::string help_of(CommandMain main) {
  std::cout.flush();
  std::fflush(stdout);
  std::FILE* captured = std::tmpfile();
  if (!captured) throw Error(std::string("cannot make a temporary file: ") + std::strerror(errno));
  const int saved = dup(STDOUT_FILENO);
  dup2(fileno(captured), STDOUT_FILENO);
  main({"--help"});
  std::cout.flush();
  std::fflush(stdout);
  dup2(saved, STDOUT_FILENO);
  close(saved);
  std::string text;
  std::rewind(captured);
  for (int c; (c = std::fgetc(captured)) != EOF;) text += char(c);
  std::fclose(captured);
  return text;
}

std::vector<CommandHelp> command_helps() {
  std::vector<CommandHelp> helps;
  for (const auto& [name, main] : commands) helps.push_back({name, help_of(main)});
  return helps;
}

int completion(const std::vector<std::string>& args) {
  if (args.size() == 1 && (args[0] == "-h" || args[0] == "--help"))
    return std::fputs(completion_help, stdout), 0;
  if (args.size() != 1 || args[0] != "bash")
    throw UsageError(args.empty() ? "completion needs a shell: bash"
                                  : "completion knows bash, not '" + args[0] + "'" +
                                        did_you_mean(args[0], {"bash"}));
  const std::string script = bash_completion(command_helps());
  std::fputs(script.c_str(), stdout);
  return 0;
}

int man(const std::vector<std::string>& args) {
  if (args.size() == 1 && (args[0] == "-h" || args[0] == "--help"))
    return std::fputs(man_help, stdout), 0;
  if (!args.empty()) throw UsageError("man takes no arguments");
  const std::string page = man_page(main_help, command_helps(), version());
  std::fputs(page.c_str(), stdout);
  return 0;
}

}  // namespace

// A command's exit code, once what it wrote to stdout has reached the file (a full disk, a closed
// pipe, /dev/full: the output is lost, and that is an error).
int flushed(int code) {
  errno = 0;
  std::cout.flush();
  if (std::fflush(stdout) == 0 && !std::ferror(stdout) && std::cout.good()) return code;
  const int err = errno;
  throw Error(std::string("cannot write to standard output") +
              (err ? ": " + std::generic_category().message(err) : std::string()));
}

int run(std::vector<std::string> args) {
  if (args.empty()) {
    std::fputs(main_help, stderr);
    return 2;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  if (command == "-h" || command == "--help" || command == "help") {
    std::fputs(main_help, stdout);
    return 0;
  }
  if (command == "--version" || command == "-V") {
    std::printf("dacrt %s\n", version());
    return 0;
  }
  std::vector<std::string> names;
  for (const auto& [name, main] : commands) {
    if (command != name) {
      names.push_back(name);
      continue;
    }
    help_pointer = "dacrt " + command + " --help";
    // Only render's ranks work together; under mpirun any other command runs in every rank alone.
    ranks->collectives_over = command != "render";
    return main(args);
  }
  throw UsageError("unknown command '" + command + "'" + did_you_mean(command, names));
}

// A message on stderr: one line of at most 1000 characters, whatever it quotes.
int fail(int code, const std::string& prefix, const std::string& what, const std::string& suffix) {
  print_message(prefix + what + suffix);
  return code;
}

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) makes a write fail with EFBIG, reported as an error, instead of
  // killing the process with SIGXFSZ halfway through a file. Messages and progress on a closed
  // pipe (`dacrt render … 2>&1 | head`) are lost, not fatal: the render goes on and writes its
  // outputs; a lost standard output is reported by flushed().
  std::signal(SIGXFSZ, SIG_IGN);
  std::signal(SIGPIPE, SIG_IGN);
  // Under an MPI launcher: MPI_Init (and MPI_Finalize when main returns); else one process.
  std::optional<Ranks> world;
  try {
    world.emplace(argc, argv);
  } catch (const std::exception& e) {
    return fail(1, "dacrt: error: ", e.what(), "");
  }
  ranks = &*world;
  int code = 0;
  std::string message;
  try {
    return flushed(run(std::vector<std::string>(argv + 1, argv + argc)));
  } catch (const RanksFailed& e) {  // agreed by every rank already
    if (ranks->root()) print_message(e.message);
    return e.code;
  } catch (const UsageError& e) {
    code = 2, message = "dacrt: " + std::string(e.what()) + " (see " + help_pointer + ")";
  } catch (const std::invalid_argument& e) {  // usage errors of `dacrt bench`
    code = 2, message = "dacrt bench: " + std::string(e.what()) + " (see dacrt bench --help)";
  } catch (const SettingError& e) {  // a view, variant or camera the request cannot have
    code = 2, message = "dacrt: " + std::string(e.what()) + " (see " + help_pointer + ")";
  } catch (const Error& e) {
    code = 1, message = "dacrt: error: " + std::string(e.what());
  } catch (const std::bad_alloc&) {
    code = 1, message = "dacrt: error: out of memory";
  } catch (const std::exception& e) {
    code = 1, message = "dacrt: error: " + std::string(e.what());
  }
  // Under mpirun a failure before the films are gathered is the whole job's: every other rank is
  // waiting in the session's first collective after rendering, which this one joins; rank 0 prints the failure
  // of the lowest failing rank.
  if (ranks->size() > 1 && !ranks->collectives_over) {
    const std::string first = ranks->first_error(message);
    if (ranks->root()) print_message(first);
    return code;
  }
  print_message(message);
  return code;
}
