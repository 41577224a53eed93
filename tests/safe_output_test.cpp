// Outputs that are safe to write, and messages that hold (issue 31's second round of hostile
// input): temporary files that cannot be planted, an interrupt that keeps the previous image,
// inputs no output may overwrite ($OCIO's files, a benchmark's scene files), output errors found
// before the render, a closed stderr, names that are not UTF-8, one-line messages of bounded
// length, and options aimed at no backend.
#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_scene.h"
#include "ocio_config.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/text.h"

using namespace dacrt;
using namespace dacrt::test;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Sets the umask for one scope.
struct ScopedUmask {
  mode_t saved;
  explicit ScopedUmask(mode_t mask) : saved(::umask(mask)) {}
  ~ScopedUmask() { ::umask(saved); }
};

}  // namespace

TEST_CASE(
    "safe outputs: a link planted at the old temporary name is neither followed nor replaced") {
  TempDir dir("planted");
  const std::string out = dir / "out.exr", victim = dir / "victim.txt";
  { std::ofstream(victim) << "precious"; }
  // The name the temporary file had before: OUT.tmp-PID, predictable by anyone.
  const fs::path planted = out + ".tmp-" + std::to_string(::getpid());
  fs::create_symlink(victim, planted);
  write_atomically(out, "test", [](std::ostream& s) { s << "image"; });
  CHECK(slurp(victim) == "precious");
  CHECK(fs::is_symlink(fs::symlink_status(planted)));
  CHECK(!fs::is_symlink(fs::symlink_status(out)));
  CHECK(slurp(out) == "image");
}

TEST_CASE("safe outputs: the temporary file is new, unpredictable, and gets the umask's mode") {
  TempDir dir("temporary");
  const std::string out = dir / "out.txt";
  const ScopedUmask mask(027);
  std::string seen;
  struct stat during {};
  write_atomically(out, "test", [&](std::ostream& s) {
    for (const std::string& name : names_in(dir.path())) seen = name;
    ::lstat((dir / seen).c_str(), &during);
    s << "x";
  });
  CHECK(seen.rfind("out.txt.tmp-", 0) == 0);
  CHECK(seen != "out.txt.tmp-" + std::to_string(::getpid()));
  CHECK(S_ISREG(during.st_mode));
  struct stat after {};
  REQUIRE(::stat(out.c_str(), &after) == 0);
  CHECK((after.st_mode & 0777) == 0640);
  CHECK(names_in(dir.path()) == std::vector<std::string>{"out.txt"});
}

TEST_CASE("safe outputs: an interrupt before the first sample keeps the previous output") {
  TempDir dir("interrupt-early");
  const std::string scene = small_scene(dir);
  const std::string out = dir / "out.exr", stats = dir / "out.json";
  const std::string render =
      "render " + scene + " --spp 4 --width 8 --height 8 --quiet -o " + out + " --stats " + stats;
  REQUIRE(run(dir, render).code == 0);
  const std::string image = slurp(out), json = slurp(stats);
  // SIGINT arrives as the render installs its handler: after the load, before any sample.
  const std::string preload =
      std::string("ASAN_OPTIONS=verify_asan_link_order=0 LD_PRELOAD=") + DACRT_INTERRUPT_ON_INSTALL;
  for (const char* backends : {"dacrt", "dacrt,brute"}) {
    INFO(backends);
    const Run r = run(dir, render + " --seed 7 --backend " + std::string(backends), preload);
    CHECK(r.code == 130);
    CHECK(slurp(out) == image);
    CHECK(slurp(stats) == json);
    CHECK(names_in(dir.path()) == std::vector<std::string>{"out.exr", "out.json", "s.gltf"});
  }
}

TEST_CASE("safe outputs: no output overwrites $OCIO's config or a LUT it reads") {
  TempDir dir("ocio-inputs");
  const std::string scene = small_scene(dir);
  const std::string config = dir / "config.ocio", lut = dir / "curve.spi1d";
  { std::ofstream(lut) << "Version 1\nFrom 0.0 1.0\nLength 2\nComponents 1\n{\n0.0\n1.0\n}\n"; }
  {
    std::ofstream c(config);
    c << ocio_test_config
      << "  - !<ColorSpace>\n    name: curved\n    from_scene_reference: !<FileTransform> "
         "{src: curve.spi1d, interpolation: linear}\n";
  }
  const std::string config_text = slurp(config), lut_text = slurp(lut);
  const std::string render = "render " + scene + " --spp 1 --width 4 --height 4 --quiet -o " +
                             (dir / "o.exr") + " --preview " + (dir / "o.png");
  const std::string env = "OCIO=" + config;
  check_refused(run(dir, render + " --stats " + config, env), 1,
                {"--stats", "config.ocio", "display configuration"});
  check_refused(run(dir, render + " --stats " + lut, env), 1,
                {"--stats", "curve.spi1d", "display configuration"});
  CHECK(slurp(config) == config_text);
  CHECK(slurp(lut) == lut_text);
  // Without $OCIO the same files are just files.
  CHECK(run(dir, render + " --stats " + lut).code == 0);
}

TEST_CASE(
    "safe outputs: OpenColorIO's warnings are one line each, said once, and --quiet drops them") {
  TempDir dir("ocio-warnings");
  const std::string scene = small_scene(dir);
  const std::string config = dir / "config.ocio";
  { std::ofstream(config) << "unknown_key: 1\n" << ocio_test_config; }
  const std::string render = "render " + scene + " --spp 1 --width 4 --height 4 -o " +
                             (dir / "o.exr") + " --preview " + (dir / "o.png");
  Run r = run(dir, render + " --quiet", "OCIO=" + config);
  CHECK(r.code == 0);
  CHECK(r.err.empty());
  r = run(dir, render, "OCIO=" + config);
  CHECK(r.code == 0);
  const std::string warning = "dacrt: warning: OpenColorIO: [OpenColorIO Warning]: Unknown key";
  CHECK(r.err.find(warning) != std::string::npos);
  CHECK(r.err.find(warning) == r.err.rfind(warning));
}

TEST_CASE("safe outputs: bench --json may not overwrite a file the scene reads") {
  TempDir dir("bench-inputs");
  GltfWriter w;
  w.add_triangles({{-1, -1, -3}, {1, -1, -3}, {0, 1, -3}});
  const std::string scene = dir / "ext.gltf", buffer = dir / "ext.bin";
  w.write_gltf(scene, false);
  const std::string bytes = slurp(buffer);
  check_refused(run(dir, "bench " + scene + " --count 16 --repeat 1 --quiet --json " + buffer), 1,
                {"--json", "ext.bin", "external file"});
  CHECK(slurp(buffer) == bytes);
}

TEST_CASE("safe outputs: an output that cannot be created is an error before the scene is read") {
  TempDir dir("before-render");
  // A scene that does not load: were the outputs checked after it, its error would come first.
  const std::string broken = dir / "broken.gltf";
  { std::ofstream(broken) << "{ not json"; }
  const std::string render = "render " + broken + " --spp 1 --quiet -o ";
  // A dangling link into a directory that does not exist.
  fs::create_symlink(dir / "missing/dir/x.exr", dir.path() / "dangling.exr");
  check_refused(run(dir, render + (dir / "dangling.exr")), 1, {"dangling.exr", "does not exist"});
  // A link that loops.
  fs::create_symlink("loop-b.exr", dir.path() / "loop-a.exr");
  fs::create_symlink("loop-a.exr", dir.path() / "loop-b.exr");
  check_refused(run(dir, render + (dir / "loop-a.exr")), 1, {"loop-a.exr", "loops"});
  // A place where no file can be made, root or not.
  check_refused(run(dir, render + "/proc/self/out.exr"), 1, {"/proc/self/out.exr", "cannot write"});
  check_refused(run(dir, render + (dir / "o.exr") + " --stats /proc/version"), 1,
                {"/proc/version", "cannot write"});
}

TEST_CASE("safe outputs: another user's file or link in a sticky directory") {
  // As a user without root's override: the rename cannot replace another user's file in a
  // directory with the sticky bit (/tmp), and a link another user planted there is not followed.
  if (::geteuid() != 0 || std::system("command -v setpriv >/dev/null") != 0) {
    MESSAGE("skipped: needs root and setpriv to act as two users");
    return;
  }
  TempDir dir("sticky");
  ::chmod(dir.path().c_str(), 01777);
  const std::string scene = small_scene(dir);
  ::chmod(scene.c_str(), 0644);
  const std::string owned = dir / "owned.exr";
  { std::ofstream(owned) << "root's"; }
  ::chmod(owned.c_str(), 0666);  // writable by anyone, yet not replaceable by rename
  const std::string as_nobody = "setpriv --reuid=65534 --regid=65534 --clear-groups";
  const std::string render = "render " + scene + " --spp 1 --width 4 --height 4 --quiet -o ";
  // The test binary's directory must be reachable by nobody: skip where it is not.
  if (run(dir, "--help", as_nobody).code != 0) {
    MESSAGE("skipped: the dacrt binary is not executable by uid 65534 here");
    return;
  }
  check_refused(run(dir, render + owned, as_nobody), 1, {"owned.exr", "another user", "sticky"});
  CHECK(slurp(owned) == "root's");
  const std::string victim = dir / "victim.exr";
  { std::ofstream(victim) << "nobody's"; }
  ::chown(victim.c_str(), 65534, 65534);
  // A third user's link in the shared directory (the directory's owner's links are trusted).
  fs::create_symlink(victim, dir.path() / "planted.exr");
  ::lchown((dir / "planted.exr").c_str(), 12345, 12345);
  check_refused(run(dir, render + (dir / "planted.exr"), as_nobody), 1,
                {"planted.exr", "symbolic link owned by another user", "not followed"});
  CHECK(slurp(victim) == "nobody's");
}

TEST_CASE("safe outputs: a closed stderr does not stop the render from writing its outputs") {
  TempDir dir("closed-stderr");
  const std::string scene = small_scene(dir);
  const std::string out = dir / "out.exr";
  // Progress lines and the summary go to a pipe that `head` closes after ten bytes.
  const std::string cmd = "bash -c '" + std::string(DACRT_CLI) + " render " + scene +
                          " --spp 64 --pass-spp 1 --width 16 --height 16 -o " + out +
                          " 2>&1 | head -c 10 >/dev/null; exit ${PIPESTATUS[0]}'";
  const int status = std::system(cmd.c_str());
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  CHECK(fs::is_regular_file(out));
}

TEST_CASE("safe outputs: names that are not UTF-8 are written escaped into JSON") {
  CHECK(valid_utf8("plain ascii") == "plain ascii");
  CHECK(valid_utf8("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x8E\xA8") ==
        "caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x8E\xA8");
  CHECK(valid_utf8("a\xFF"
                   "b") == "a\\xFFb");
  CHECK(valid_utf8("\xC0\xAF") == "\\xC0\\xAF");                    // overlong
  CHECK(valid_utf8("\xED\xA0\x80") == "\\xED\\xA0\\x80");           // a surrogate
  CHECK(valid_utf8("\xF4\x90\x80\x80") == "\\xF4\\x90\\x80\\x80");  // above U+10FFFF
  CHECK(valid_utf8("cut \xE2\x82") == "cut \\xE2\\x82");            // truncated at the end

  TempDir dir("not-utf8");
  const std::string scene = small_scene(dir, 0.0, "sc\xFF\xFE.gltf");
  const std::string stats = dir / "s.json", bench = dir / "b.json";
  Run r = run(dir, "render '" + scene + "' --spp 1 --width 4 --height 4 --quiet -o " +
                       (dir / "o.exr") + " --stats " + stats);
  INFO(r.err);
  REQUIRE(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(slurp(stats));
  CHECK(j["scene"].get<std::string>().find("sc\\xFF\\xFE.gltf") != std::string::npos);
  r = run(dir, "bench '" + scene + "' --count 16 --repeat 1 --quiet --json " + bench);
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(slurp(bench))["scene"].get<std::string>().find("\\xFF") !=
        std::string::npos);
}

TEST_CASE("safe outputs: every message is one line of at most 1000 characters") {
  CHECK(message_line("a\nb\r\tc") == "a b  c");
  const std::string tail = ": what is wrong";
  const std::string long_line = message_line(std::string(5000, 'x') + tail);
  CHECK(long_line.size() <= 999);
  CHECK(long_line.find(tail) != std::string::npos);

  TempDir dir("one-line");
  // A newline in a path, and a path of 5000 characters.
  check_refused(run(dir, "render '" + (dir / "no\nsuch.gltf") + "' --quiet"), 1,
                {"no such.gltf", "does not exist"});
  const std::string huge = dir / (std::string(200, 'd') + "/" + std::string(200, 'd') + "/" +
                                  std::string(200, 'd') + "/" + std::string(4000, 'e') + ".gltf");
  Run r = run(dir, "render '" + huge + "' --quiet -o " + (dir / "o.exr"));
  INFO(r.err);
  CHECK(r.code == 1);
  CHECK(lines(r.err) == 1);
  CHECK(r.err.size() <= 1001);
  CHECK(r.err.find("does not exist") != std::string::npos);
  // The summary names the output in one line, whatever its name holds.
  const std::string scene = small_scene(dir);
  r = run(dir, "render " + scene + " --spp 1 --width 4 --height 4 -o '" + (dir / "two\nlines.exr") +
                   "'");
  CHECK(r.code == 0);
  CHECK(r.err.find("two lines.exr: 4×4, 1 spp") != std::string::npos);
  CHECK(r.err.find("\nlines.exr") == std::string::npos);
  r = run(dir, "render s.gltf --width '" + std::string(3000, '9') + "'");
  CHECK(r.code == 2);
  CHECK(lines(r.err) == 1);
  CHECK(r.err.size() <= 1001);
}

TEST_CASE("safe outputs: options for no backend, unknown info flags and benches that cannot fit") {
  TempDir dir("usage");
  const std::string scene = small_scene(dir);
  const std::string render =
      "render " + scene + " --spp 1 --width 4 --height 4 --quiet -o " + (dir / "o.exr");
  check_refused(run(dir, render + " --backend-option dacr.bins=4"), 2,
                {"dacr.bins=4", "not one of the backends"});
  check_refused(run(dir, render + " --backend-option .bins=4"), 2, {".bins=4", "no backend"});
  check_refused(run(dir, render + " --backend dacrt --backend-option dacrt-naive.bins=4"), 2,
                {"dacrt-naive.bins=4"});
  // A key the second backend does not know is found before the first renders.
  check_refused(run(dir, render + " --backend dacrt,dacrt-naive --backend-option "
                                  "dacrt-naive.no_such_key=1"),
                2, {"no_such_key"});
  CHECK(!fs::exists(dir / "o.dacrt.exr"));
  CHECK(run(dir, render + " --backend dacrt,dacrt-naive --backend-option dacrt.bins=4").code == 0);
  check_refused(run(dir, "info -x"), 2, {"-x"});
  check_refused(run(dir, "info " + scene + " -x"), 2, {"-x"});
  check_refused(run(dir, "bench " + scene + " --width 32768 --height 32768 --quiet"), 2,
                {"--width/--height", "32768 x 32768", "memory available"});
}

TEST_CASE("safe outputs: a camera far away renders, and --up is blamed only for --up") {
  TempDir dir("far-camera");
  const std::string scene = small_scene(dir);
  const std::string render =
      "render " + scene + " --spp 1 --width 4 --height 4 --quiet -o " + (dir / "o.exr");
  Run r = run(dir, render + " --look-from 0,0,1e20");
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK(r.err.find("--up") == std::string::npos);
  check_refused(run(dir, render + " --look-from 0,0,5 --look-at 0,0,0 --up 0,0,1"), 2,
                {"--up", "parallel"});
}
