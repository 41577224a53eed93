// `dacrt converge` given hostile input: a reference that is not finite, configurations that cannot
// run, outputs that would replace an input or cannot be written, names that would break the
// script, and a run killed between configurations. Each is refused in one line before any render,
// or keeps every point measured so far.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli.h"
#include "gltf_writer.h"
#include "dacrt/io/exr.h"
#include "dacrt/util/memory.h"

using namespace dacrt;
using namespace dacrt::test;
namespace fs = std::filesystem;

namespace {

const std::string cornell = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";
const std::string tiny = " --width 12 --height 12 --max-depth 2 --quiet --time-budget 0.02 ";

void check_refused(const Run& r, int code, const std::vector<std::string>& words) {
  INFO(r.err);
  CHECK(r.code == code);
  CHECK(lines(r.err) == 1);
  for (const std::string& w : words) CHECK_MESSAGE(r.err.find(w) != std::string::npos, w);
}

bool have_gnuplot() {
  return std::system("command -v gnuplot >/dev/null 2>&1") == 0;
}

}  // namespace

TEST_CASE("converge untrusted: a reference with a NaN or an infinite pixel is refused first") {
  TempDir dir("converge-nan");
  const std::string out = dir / "out";
  for (const float bad : {NAN, INFINITY, -INFINITY}) {
    INFO(bad);
    Image image(12, 12);
    for (float& v : image.rgb) v = 0.5f;
    image.pixel(5, 7)[1] = bad;  // x 5, y 7, channel G
    const std::string ref = dir / "ref.exr";
    write_exr(ref, image, {});
    const Run r = run(dir, "converge " + cornell + tiny + "--reference " + ref + " -o " + out);
    check_refused(r, 1, {ref, "(5, 7)", "channel G", std::isnan(bad) ? "NaN" : "infinite"});
    CHECK(!fs::exists(out));  // nothing rendered, nothing written
  }
}

TEST_CASE(
    "converge untrusted: a reference's own MSE that is not a non-negative number is refused") {
  TempDir dir("converge-reference-mse");
  const std::string out = dir / "out", ref = dir / "ref.exr";
  Image image(12, 12);
  for (float& v : image.rgb) v = 0.5f;
  for (const char* bad : {"nan", "-1e-5", "inf", "0.1x", ""}) {
    INFO(bad);
    ExrMetadata meta;
    meta.extra = {{"referenceMse", bad}, {"referenceRelmse", "0.001"}};
    write_exr(ref, image, meta);
    const Run r = run(dir, "converge " + cornell + tiny + "--reference " + ref + " -o " + out);
    check_refused(r, 1, {ref, "referenceMse", "not a non-negative number"});
    CHECK(!fs::exists(out));
  }
}

TEST_CASE(
    "converge untrusted: a configuration that cannot run is a usage error before any render") {
  TempDir dir("converge-config");
  const std::string out = dir / "out";
  const std::string base = "converge " + cornell + tiny + "--reference-spp 4 -o " + out;
  struct Case {
    std::string args;
    std::vector<std::string> words;
  };
  std::vector<Case> cases = {
      // An unknown backend prefix, which every backend would drop without a word.
      {"--config '' --config 'backend-option=dacr.bins=4'", {"dacr", "not a backend"}},
      {"--config '' --config 'backend-option=.bins=4'", {".bins=4", "not a backend"}},
      {"--backend-option dacr.bins=4 --config ''", {"dacr", "not a backend"}},
      // A key no backend knows, a value that is no number: found by the backend's own parser.
      {"--config '' --config 'backend-option=dacrt.nokey=1'", {"nokey", "--config"}},
      {"--config '' --config 'backend-option=dacrt.bins=abc'", {"bins=abc", "--config"}},
      {"--config '' --config 'backend=brute backend-option=bins=4'", {"brute", "bins"}},
      // The shared options the reference is rendered with.
      {"--backend-option nokey=1 --config 'backend=dacrt-naive backend-option=dacrt-naive.bins=4'",
       {"the reference", "nokey"}},
      {"--config '' --config 'backend=nosuch'", {"nosuch"}},
      {"--config '' --config 'integrator=nosuch'", {"nosuch"}},
  };
  // A configuration of 5000 characters is quoted in part: the message stays short.
  cases.push_back({"--config 'seed=3 " + std::string(5000, 'x') + "'", {"is not KEY=VALUE"}});
  cases.push_back(
      {"--config 'seed=3' --config 'seed=3 --" + std::string(5000, 'x') + "=1'", {"unknown key"}});
  for (const Case& c : cases) {
    INFO(c.args.substr(0, 300));
    const Run r = run(dir, base + " " + c.args);
    check_refused(r, 2, c.words);
    CHECK(r.err.size() < 1000);
    CHECK(!fs::exists(out));  // not even the reference
  }
  // The same options, well formed, run.
  const Run ok = run(dir, base + " --config 'backend-option=dacrt.bins=8'");
  INFO(ok.err);
  CHECK(ok.code == 0);
}

TEST_CASE("converge untrusted: a run killed in a configuration keeps the points of those before") {
  TempDir dir("converge-kill");
  const std::string out = dir / "out", csv = out + "/convergence.csv", seen = dir / "seen.csv";
  // Two configurations of about 1.5 s each: once the CSV appears it is copied, and the run is
  // killed (no handler runs) while the second configuration renders.
  const std::string script =
      std::string(DACRT_CLI) + " converge " + cornell +
      " --width 16 --height 16 --max-depth 2 --quiet --no-reference --no-plot --time-budget 1.5 "
      "--max-spp 1048576 --config 'integrator=direct' --config 'seed=5' -o " +
      out + " >/dev/null 2>&1 & pid=$!; for i in $(seq 1200); do [ -e " + csv +
      " ] && break; sleep 0.05; done; cp " + csv + " " + seen + "; kill -KILL $pid; wait $pid";
  std::ofstream(dir / "run.sh") << script << "\n";
  std::system(("bash " + (dir / "run.sh") + " 2>/dev/null").c_str());
  REQUIRE(fs::exists(seen));
  const std::string text = slurp(seen);
  INFO(text);
  CHECK(text.find("\"integrator=direct\",1,") != std::string::npos);
  CHECK(text.find("\"integrator=direct\",2,") != std::string::npos);
  CHECK(text.find("seed=5") == std::string::npos);  // written before the second one ended
  // The script beside it holds the same points.
  CHECK(slurp(out + "/convergence.gp").find("integrator=direct: slope") != std::string::npos);
}

TEST_CASE("converge untrusted: names with line breaks, quotes and markup break no output") {
  TempDir dir("converge-names");
  const std::string out = dir / "out";
  // A line break separates KEY=VALUE words, so it would pass into the label: refused. (The odd
  // text reaches the command through the environment, which the shell passes on untouched.)
  for (const char* config : {"seed=3\nmax-depth=1", "seed=3\rmax-depth=1", "seed=3\vmax-depth=1"}) {
    ::setenv("DACRT_TEST_CONFIG", config, 1);
    const Run r = run(dir, "converge " + cornell + tiny + "--no-reference -o " + out +
                               " --config \"$DACRT_TEST_CONFIG\"");
    check_refused(r, 2, {"control character"});
    CHECK(!fs::exists(out));
  }
  // A tab is a separator like a space, and harmless in every output.
  ::setenv("DACRT_TEST_CONFIG", "seed=3\tmax-depth=1", 1);
  CHECK(run(dir, "converge " + cornell + tiny + "--no-reference --no-plot -o " + out +
                     " --config \"$DACRT_TEST_CONFIG\"")
            .code == 0);
  ::unsetenv("DACRT_TEST_CONFIG");
  fs::remove_all(out);
  // The scene's file name goes into the plot's title: quotes, a backslash, a line break, markup.
  const std::string scene = dir / "a&b<c>'q\"\\\nz.gltf";
  fs::copy_file(cornell, scene);
  ::setenv("DACRT_TEST_SCENE", scene.c_str(), 1);
  const Run r = run(dir, "converge \"$DACRT_TEST_SCENE\"" + tiny + "--no-reference -o " + out +
                             " --config seed=3");
  ::unsetenv("DACRT_TEST_SCENE");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::string gp = slurp(out + "/convergence.gp");
  const size_t title = gp.find("set title '");
  REQUIRE(title != std::string::npos);
  const std::string line = gp.substr(title, gp.find('\n', title) - title);
  CHECK(line == "set title 'a&b<c>''q\"\\ z.gltf, 12 x 12: noise against time'");
  if (have_gnuplot()) {
    const std::string svg = slurp(out + "/convergence.svg");
    CHECK(svg.find("a&amp;b&lt;c") != std::string::npos);
    CHECK(svg.find("a&b") == std::string::npos);
    CHECK(svg.find("'q") != std::string::npos);
    CHECK(fs::file_size(out + "/convergence.png") > 0);
  }
  // Nothing but the outputs: gnuplot's temporary directory is gone.
  for (const auto& e : fs::directory_iterator(out))
    CHECK_MESSAGE((e.path().filename().string().rfind("convergence.", 0) == 0 ||
                   e.path().filename() == "index.html"),
                  "left behind: " << e.path());
}

TEST_CASE("converge untrusted: no output may replace the scene's files or the environment map") {
  TempDir dir("converge-inputs");
  const std::string out = dir / "out";
  fs::create_directory(out);
  GltfWriter w;
  w.add_triangles({{-1, -1, -3}, {1, -1, -3}, {0, 1, -3}});
  const std::string scene = dir / "ext.gltf";
  w.write_gltf(scene, false);  // the buffer in ext.bin beside it
  // The buffer moved to where the CSV goes.
  const std::string buffer = out + "/convergence.csv";
  fs::rename(dir / "ext.bin", buffer);
  std::string json = slurp(scene);
  json.replace(json.find("ext.bin"), 7, "out/convergence.csv");
  write_text(scene, json);
  const std::string bytes = slurp(buffer);
  check_refused(run(dir, "converge " + scene + tiny + "--no-reference -o " + out), 1,
                {"convergence.csv", "the scene's external file"});
  CHECK(slurp(buffer) == bytes);
  CHECK(fs::exists(out + "/convergence.csv"));
  // The environment map where the reference is written.
  const std::string env = out + "/reference.exr";
  Image sky(4, 2);
  for (float& v : sky.rgb) v = 1.0f;
  write_exr(env, sky, {});
  const std::string env_bytes = slurp(env);
  check_refused(run(dir, "converge " + cornell + tiny + "--reference-spp 4 --environment " + env +
                             " -o " + out),
                1, {"reference.exr", "--environment"});
  CHECK(slurp(env) == env_bytes);
}

TEST_CASE("converge untrusted: an output that cannot be written is found before any render") {
  TempDir dir("converge-unwritable");
  const std::string out = dir / "out";
  fs::create_directories(out + "/reference.exr");  // a directory where the reference goes
  // Not --quiet: the only line on stderr is the refusal, no render was begun.
  const Run r =
      run(dir, "converge " + cornell +
                   " --width 12 --height 12 --time-budget 0.02 --reference-spp 4 -o " + out);
  check_refused(r, 1, {"reference.exr"});
  CHECK(r.err.find("rendering") == std::string::npos);
  CHECK(!fs::exists(out + "/convergence.csv"));  // refused before the renders
  // -o naming a file.
  const std::string file = dir / "file";
  write_text(file, "x");
  check_refused(run(dir, "converge " + cornell + tiny + "--no-reference -o " + file), 1,
                {"not a directory"});
  CHECK(slurp(file) == "x");
  // -o a dangling symbolic link: creating the directory would fail after the renders.
  const std::string link = dir / "link";
  fs::create_symlink(dir / "nowhere", link);
  const Run l =
      run(dir, "converge " + cornell +
                   " --width 12 --height 12 --time-budget 0.02 --no-reference -o " + link);
  check_refused(l, 1, {"link", "symbolic link", "does not exist"});
  CHECK(l.err.find("converge default") == std::string::npos);  // no point was rendered
}

TEST_CASE("converge untrusted: renders that cannot fit in memory are refused before any") {
  TempDir dir("converge-memory");
  const std::string out = dir / "out";
  // 32768 x 32768 pixels: a film of 36 GiB before anything else. (Not under `ulimit -v`, which
  // AddressSanitizer's shadow memory cannot run under.)
  if (dacrt::available_memory() > (uint64_t(64) << 30)) {
    MESSAGE("skipped: this machine has over 64 GiB available, a 32768² render could start");
    return;
  }
  const Run r = run(dir,
                    "converge " + cornell +
                        " --width 32768 --height 32768 --quiet --no-reference --no-plot -o " + out,
                    "timeout 120");
  check_refused(r, 1, {"32768 x 32768", "memory available"});
  CHECK(!fs::exists(out));
}
