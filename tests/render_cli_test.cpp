// `dacrt render` while it runs: real signals sent to a child process (the first stops the render
// and writes what it has, a second ends it at once), --time-limit, --checkpoint files that appear
// while the render goes on, the AOV layers and the header, the integrators by name. The header's
// `spp` is always the count every pixel has, and no temporary file survives.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cli.h"
#include "dacrt/film/film.h"
#include "dacrt/io/exr.h"

using namespace dacrt;
using namespace dacrt::test;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

const std::string cornell = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";

// A render that would take many minutes: 100 000 samples of each of 64 × 64 pixels.
const std::vector<std::string> endless = {"render", cornell, "--width", "64",     "--height",
                                          "64",     "--spp", "100000",  "--quiet"};

std::vector<std::string> operator+(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// `dacrt ARGS` as a child process (fork and exec, stdout and stderr to files in `dir`), so that a
// test can signal it while it renders, and wait for it with a deadline.
class Child {
 public:
  Child(const TempDir& dir, const std::vector<std::string>& args) : dir_(dir) {
    pid_ = fork();
    REQUIRE(pid_ >= 0);
    if (pid_ == 0) {
      // The test runner's handlers and masks are not the CLI's business.
      std::signal(SIGINT, SIG_DFL);
      std::signal(SIGTERM, SIG_DFL);
      sigset_t none;
      sigemptyset(&none);
      sigprocmask(SIG_SETMASK, &none, nullptr);
      const int in = open("/dev/null", O_RDONLY);
      const int out = open((dir / "stdout.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int err = open((dir / "stderr.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(in, 0), dup2(out, 1), dup2(err, 2);
      std::vector<char*> argv = {const_cast<char*>(DACRT_CLI)};
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(DACRT_CLI, argv.data());
      _exit(127);
    }
  }
  ~Child() {
    if (!status_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  pid_t pid() const { return pid_; }
  void signal(int sig) const { REQUIRE(kill(pid_, sig) == 0); }

  // Whether it has ended (then status() says how).
  bool ended() {
    if (status_) return true;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) status_ = status;
    return bool(status_);
  }
  // Waits for it to end, at most `seconds`; after that it is killed and the test fails.
  int wait(double seconds) {
    const auto start = Clock::now();
    while (!ended() && seconds_since(start) < seconds)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!ended()) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
      status_ = -1;
      FAIL("dacrt did not end within " << seconds << " s; stderr: " << err());
    }
    return *status_;
  }
  std::string err() const { return slurp(dir_ / "stderr.txt"); }

 private:
  const TempDir& dir_;
  pid_t pid_ = -1;
  std::optional<int> status_;
};

// Polls `done` every few milliseconds for at most `seconds`; whether it became true.
template <class Done>
bool poll(double seconds, Done done) {
  const auto start = Clock::now();
  while (!done()) {
    if (seconds_since(start) > seconds) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

// Whether signal `sig` is pending for the process as a whole (sent, not yet taken by a thread).
bool pending(pid_t pid, int sig) {
  const std::string status = slurp("/proc/" + std::to_string(pid) + "/status");
  const size_t at = status.find("ShdPnd:");
  if (at == std::string::npos) return false;
  return std::stoull(status.substr(at + 7), nullptr, 16) >> (sig - 1) & 1u;
}

// The files in `dir` whose names say they are temporaries being written.
std::vector<std::string> temporaries(const TempDir& dir) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(dir.path()))
    if (e.path().filename().string().find(".tmp") != std::string::npos)
      found.push_back(e.path().filename().string());
  return found;
}

// A whole EXR, or nothing (a file that is not one fails the test).
std::optional<ExrFile> read_if_whole(const std::string& path) {
  try {
    return read_exr_file(path);
  } catch (const std::exception& e) {
    FAIL_CHECK(path << " is not a valid EXR: " << e.what());
    return std::nullopt;
  }
}

// A header attribute as text, empty when the header has none.
std::string attribute(const ExrFile& f, const std::string& key) {
  const auto it = f.attributes.find(key);
  return it == f.attributes.end() ? std::string() : it->second;
}

int spp_of(const ExrFile& f) {
  REQUIRE(f.attributes.count("spp"));
  return std::stoi(f.attributes.at("spp"));
}

// The header's spp is the count every pixel has: the least of the samples channel when there is
// one, else the count the header says every pixel has.
void check_counts(const ExrFile& f) {
  const int spp = spp_of(f);
  const std::string per_pixel = attribute(f, "samplesPerPixel");
  INFO("spp " << spp << ", samplesPerPixel " << per_pixel);
  if (const Channel* samples = f.find(Film::samples_channel)) {
    REQUIRE(!samples->values.empty());
    CHECK(*std::min_element(samples->values.begin(), samples->values.end()) == float(spp));
  } else {
    CHECK(per_pixel == "every pixel " + std::to_string(spp));
  }
}

// Renders the endless scene with `flags` until its checkpoint file holds at least one pass, then
// sends `sig`: the render stops, writes a whole image of what it has, says why, and exits
// 128 + sig with no temporary left.
void check_stopped_by(int sig, const std::vector<std::string>& flags) {
  TempDir dir("render-cli-signal");
  const std::string out = dir / "out.exr";
  Child child(dir, endless + flags + std::vector<std::string>{"-o", out, "--checkpoint", "0.2"});
  REQUIRE_MESSAGE(poll(15, [&] { return fs::exists(out) || child.ended(); }),
                  "no checkpoint within 15 s");
  REQUIRE_FALSE(child.ended());
  const std::optional<ExrFile> checkpoint = read_if_whole(out);
  REQUIRE(checkpoint);
  child.signal(sig);
  const int status = child.wait(15);
  INFO(child.err());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 128 + sig);
  const std::optional<ExrFile> image = read_if_whole(out);
  REQUIRE(image);
  CHECK(attribute(*image, "stoppedBy") == (sig == SIGINT ? "SIGINT" : "SIGTERM"));
  CHECK(attribute(*image, "sppRequested") == "100000");
  check_counts(*image);
  CHECK(spp_of(*image) >= spp_of(*checkpoint));
  CHECK(spp_of(*image) < 100000);
  CHECK(temporaries(dir).empty());
}

}  // namespace

TEST_CASE("render cli: SIGINT stops the render, writes what it has and exits 130") {
  check_stopped_by(SIGINT, {"--pass-spp", "1"});
}

TEST_CASE("render cli: SIGTERM in the middle of a pass writes the samples channel, exits 143") {
  // Passes of 64 samples over wavefronts of 1000 paths: the signal lands inside a pass, so some
  // pixels have one sample more than others.
  check_stopped_by(SIGTERM, {"--pass-spp", "64", "--wavefront", "1000"});
}

TEST_CASE("render cli: a second SIGINT while the outputs are written ends the process at once") {
  TempDir dir("render-cli-twice");
  const std::string out = dir / "out.exr";
  // Large enough that writing the stopped render's image takes a while.
  Child child(dir, {"render", cornell, "--width", "512", "--height", "512", "--spp", "100000",
                    "--pass-spp", "1", "--checkpoint", "0.1", "--quiet", "-o", out, "--aov",
                    "albedo,normal,depth,position,variance,samples"});
  REQUIRE_MESSAGE(poll(15, [&] { return fs::exists(out) || child.ended(); }),
                  "no checkpoint within 15 s");
  REQUIRE_FALSE(child.ended());
  child.signal(SIGINT);
  // Once the first is taken, the next temporary file is the stopped render's image (or a
  // checkpoint's, begun before): the second signal lands while it is written.
  REQUIRE(poll(10, [&] { return !pending(child.pid(), SIGINT) || child.ended(); }));
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const bool writing =
      poll(10, [&] { return !temporaries(dir).empty() || child.ended(); }) && !child.ended();
  const auto second = Clock::now();
  if (writing) child.signal(SIGINT);
  const int status = child.wait(15);
  INFO(child.err());
  if (writing) {
    CHECK(seconds_since(second) < 5);
    CHECK(WIFSIGNALED(status));
    if (WIFSIGNALED(status)) CHECK(WTERMSIG(status) == SIGINT);
  } else {  // it finished before the temporary was seen: the first signal's outcome
    MESSAGE("the stopped render was written before a second signal could be sent");
    CHECK((WIFEXITED(status) && WEXITSTATUS(status) == 130));
  }
  const std::vector<std::string> left = temporaries(dir);
  INFO("writing: " << writing << ", left behind: " << (left.empty() ? "-" : left.front()));
  CHECK(left.empty());
  if (fs::exists(out)) read_if_whole(out);
}

TEST_CASE("render cli: --time-limit stops after the pass that crosses it, with whole passes") {
  TempDir dir("render-cli-time");
  const std::string out = dir / "out.exr";
  const auto start = Clock::now();
  Child child(
      dir, endless + std::vector<std::string>{"--time-limit", "1", "--pass-spp", "1", "-o", out});
  const int status = child.wait(15);
  INFO(child.err());
  CHECK(seconds_since(start) < 10);
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
  const std::optional<ExrFile> image = read_if_whole(out);
  REQUIRE(image);
  CHECK(attribute(*image, "stoppedBy") == "the time limit");
  CHECK(attribute(*image, "sppRequested") == "100000");
  CHECK(spp_of(*image) >= 1);
  CHECK(spp_of(*image) < 100000);
  // Whole passes: every pixel has the same count.
  CHECK(image->find(Film::samples_channel) == nullptr);
  check_counts(*image);
  CHECK(temporaries(dir).empty());
}

TEST_CASE("render cli: in a log, a long render prints progress in its first seconds") {
  TempDir dir("render-cli-progress");
  // Not --quiet, stderr a file: a CI log. 10 % of each frame would take many minutes.
  Child child(dir, {"render", cornell, "--width", "64", "--height", "64", "--spp", "100000",
                    "--frames", "0:1", "-o", dir / "out.exr"});
  const std::string first = "render frame 0 (1 of 2): 0%, ";
  const auto start = Clock::now();
  const bool seen =
      poll(20, [&] { return child.err().find(first) != std::string::npos || child.ended(); });
  const double seconds = seconds_since(start);
  if (!child.ended()) child.signal(SIGINT);
  const int status = child.wait(30);
  const std::string err = child.err();
  INFO(err);
  CHECK(WIFEXITED(status));
  REQUIRE(seen);
  CHECK(seconds < 15);  // 1 s after the render began, on an idle machine
  const size_t line = err.find(first);
  REQUIRE(line != std::string::npos);
  CHECK(err.find('\r') == std::string::npos);
  // "0%, DONE/100000 spp, RATE, ETA h:mm:ss, total ETA h:mm:ss" (or "ETA --:--" before the
  // first wavefront ends).
  const std::string text = err.substr(line, err.find('\n', line) - line);
  CHECK(text.find("/100000 spp, ") != std::string::npos);
  CHECK(text.find("ETA ") != std::string::npos);
}

TEST_CASE("render cli: in a log, --frames says frame k of n and the total ETA") {
  TempDir dir("render-cli-frames-log");
  const Run r = run(dir, "render " + cornell + " --width 64 --height 64 --spp 100000 --frames " +
                             "0:1 --time-limit 1.5 -o " + (dir / "out.exr"));
  INFO(r.err);
  REQUIRE(r.code == 0);
  for (const char* text :
       {"render frame 0 (1 of 2): ", "render frame 1 (2 of 2): ", ", total ETA ",
        "frame 0 (1 of 2, t = 0 s): ", "; total ETA ", "frame 1 (2 of 2, t = "}) {
    INFO(text);
    CHECK(r.err.find(text) != std::string::npos);
  }
  // Each frame's last line: 100 % when the limit ended it.
  CHECK(r.err.find("render frame 1 (2 of 2): 100%, ") != std::string::npos);
}

namespace {

// The statistics of a render with `flags` stopped by --time-limit `limit`: every render's (each
// backend's, each frame's) seconds end within a pass of the limit.
void check_time_limit(const std::string& name, double limit, const std::string& flags,
                      size_t renders) {
  TempDir dir(name);
  const std::string stats = dir / "stats.json";
  char limit_text[32];
  std::snprintf(limit_text, sizeof limit_text, "%g", limit);
  const auto start = Clock::now();
  const Run r = run(dir, "render " + cornell + " --width 96 --height 96 --spp 100000 --quiet" +
                             " --time-limit " + limit_text + " -o " + (dir / "out.exr") +
                             " --stats " + stats + " " + flags);
  const double wall = seconds_since(start);
  INFO(r.err);
  REQUIRE(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(slurp(stats));
  std::vector<nlohmann::json> done;
  auto add = [&](const nlohmann::json& frame) {
    if (frame.contains("backends"))
      for (const auto& b : frame["backends"]) done.push_back(b);
    else
      done.push_back(frame);
  };
  if (j.contains("frames"))
    for (const auto& frame : j["frames"]) add(frame);
  else
    add(j);
  REQUIRE(done.size() == renders);
  for (const nlohmann::json& d : done) {
    INFO(d.dump());
    const double seconds = d["render_seconds"].get<double>();
    const uint32_t spp = d["spp"].get<uint32_t>(), passes = d["passes"].get<uint32_t>();
    CHECK(d["stopped_by"] == "the time limit");
    CHECK(d["time_limit"].get<double>() == limit);
    REQUIRE(spp >= 1);
    // Each render had the whole limit (per backend, per frame) and crossed it (render_seconds
    // is read off another clock than the limit's, a moment apart: 0.999 s was seen for 1 s)...
    CHECK(seconds >= 0.98 * limit);
    // ... by one pass: the first of 1 spp, later ones sized by the time left, so the last
    // costs about a sample per pixel (the bound leaves room for a busy 2-core machine).
    CHECK(passes >= 2);
    CHECK(seconds < limit + 1.0 + 4.0 * seconds / spp);
  }
  CHECK(wall < 60);
}

}  // namespace

TEST_CASE("render cli: --time-limit ends within a pass of it") {
  check_time_limit("render-cli-limit", 2, "", 1);
}

TEST_CASE("render cli: --time-limit holds for each backend, each frame and adaptive sampling") {
  SUBCASE("each backend") {
    check_time_limit("render-cli-limit-b", 1, "--backend dacrt,brute", 2);
  }
  SUBCASE("each frame") { check_time_limit("render-cli-limit-f", 1, "--frames 0:1", 2); }
  SUBCASE("adaptive") {
    check_time_limit("render-cli-limit-a", 1, "--adaptive 0.001 --adaptive-min 4", 1);
  }
}

TEST_CASE("render cli: --checkpoint writes a whole image while the render goes on") {
  TempDir dir("render-cli-checkpoint");
  const std::string out = dir / "out.exr";
  Child child(dir, endless + std::vector<std::string>{"--checkpoint", "0.5", "--pass-spp", "1",
                                                      "--time-limit", "5", "-o", out});
  REQUIRE_MESSAGE(poll(15, [&] { return fs::exists(out) || child.ended(); }),
                  "no checkpoint within 15 s");
  const std::optional<ExrFile> checkpoint = read_if_whole(out);
  CHECK_FALSE(child.ended());  // the file was there, whole, before the process ended
  REQUIRE(checkpoint);
  CHECK(attribute(*checkpoint, "stoppedBy").empty());
  check_counts(*checkpoint);
  const int status = child.wait(20);
  INFO(child.err());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  const std::optional<ExrFile> image = read_if_whole(out);
  REQUIRE(image);
  CHECK(spp_of(*checkpoint) >= 1);
  CHECK(spp_of(*checkpoint) < spp_of(*image));  // a pass follows every checkpoint
  CHECK(temporaries(dir).empty());
}

TEST_CASE("render cli: --aov writes every layer asked, and the header says how it was made") {
  TempDir dir("render-cli-aov");
  const std::string out = dir / "out.exr";
  Run r = run(dir, "render " + cornell + " --width 16 --height 12 --spp 2 --quiet --seed 7" +
                       " --look-from 0.25,1,3.5 -o " + out +
                       " --aov albedo,normal,depth,position,variance,samples");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const ExrFile f = read_exr_file(out);
  CHECK(f.width == 16);
  CHECK(f.height == 12);
  std::set<std::string> names;
  for (const Channel& c : f.channels) names.insert(c.name);
  CHECK(names == std::set<std::string>{"R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "N.X",
                                       "N.Y", "N.Z", "Z", "P.X", "P.Y", "P.Z", "variance.R",
                                       "variance.G", "variance.B", "samples.X"});
  const Channel* samples = f.find(Film::samples_channel);
  REQUIRE(samples);
  for (float n : samples->values) CHECK(n == 2.f);
  check_counts(f);
  for (const char* key : {"spp", "backend", "integrator", "sampler", "seed", "renderSeconds",
                          "scene", "camera", "dacrtVersion"})
    CHECK_MESSAGE(f.attributes.count(key), "missing attribute " << key);
  CHECK(attribute(f, "spp") == "2");
  CHECK(attribute(f, "backend") == "dacrt");
  CHECK(attribute(f, "integrator") == "path");
  CHECK(attribute(f, "seed") == "7");
  CHECK(attribute(f, "scene") == cornell);
  CHECK(attribute(f, "camera").find("--look-from 0.25,1,3.5") != std::string::npos);
  CHECK(attribute(f, "stoppedBy").empty());
  // An AOV it does not know is a usage error naming it, before anything is written.
  Run bad = run(
      dir, "render " + cornell + " --spp 1 --quiet -o " + (dir / "bad.exr") + " --aov albedo,nope");
  CHECK(bad.code == 2);
  CHECK(lines(bad.err) == 1);
  CHECK(bad.err.find("nope") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "bad.exr"));
}

TEST_CASE("render cli: --integrator picks one by name, an unknown one is refused before loading") {
  TempDir dir("render-cli-integrator");
  // The scene does not exist: the integrator is refused first, with the names it knows.
  Run bad =
      run(dir, "render " + (dir / "missing.gltf") + " --integrator nope -o " + (dir / "bad.exr"));
  INFO(bad.err);
  CHECK(bad.code == 2);
  CHECK(lines(bad.err) == 1);
  for (const char* word : {"'nope'", "path", "direct", "ao", "albedo", "normal", "depth"})
    CHECK_MESSAGE(bad.err.find(word) != std::string::npos, word);
  CHECK(bad.err.find("missing.gltf") == std::string::npos);
  // So is an unknown backend: a usage error (exit 2), with the names of the known ones.
  Run backend =
      run(dir, "render " + (dir / "missing.gltf") + " --backend embre -o " + (dir / "bad.exr"));
  INFO(backend.err);
  CHECK(backend.code == 2);
  CHECK(lines(backend.err) == 1);
  CHECK(backend.err.find("'embre'") != std::string::npos);
  CHECK(backend.err.find("dacrt-naive") != std::string::npos);
  for (const std::string name : {"path", "direct", "ao", "albedo", "normal", "depth"}) {
    const std::string out = dir / (name + ".exr");
    Run r = run(dir, "render " + cornell + " --width 8 --height 8 --spp 1 --quiet --integrator " +
                         name + " -o " + out);
    INFO(name << ": " << r.err);
    CHECK(r.code == 0);
    if (fs::exists(out)) CHECK(attribute(read_exr_file(out), "integrator") == name);
  }
  // --ao-distance: occluders farther than it do not count, so a short one is brighter.
  auto ao_sum = [&](const std::string& flags) {
    const std::string out = dir / "ao.exr";
    Run r = run(dir, "render " + cornell + " --width 16 --height 16 --spp 4 --quiet" +
                         " --integrator ao -o " + out + flags);
    REQUIRE(r.code == 0);
    double sum = 0.0;
    for (float v : read_exr(out).rgb) sum += v;
    return sum;
  };
  CHECK(ao_sum(" --ao-distance 0.01") > 1.2 * ao_sum(""));
}

TEST_CASE("render cli: a signal during the first of several backends writes its image only") {
  TempDir dir("render-cli-backends");
  const std::string out = dir / "out.exr", json = dir / "out.json";
  Child child(
      dir, endless + std::vector<std::string>{"--backend", "dacrt,brute", "--pass-spp", "1",
                                              "--checkpoint", "0.2", "-o", out, "--stats", json});
  // dacrt's checkpoint: it renders (its 100 000 samples would take minutes).
  REQUIRE_MESSAGE(poll(15, [&] { return fs::exists(dir / "out.dacrt.exr") || child.ended(); }),
                  "no checkpoint within 15 s");
  REQUIRE_FALSE(child.ended());
  child.signal(SIGINT);
  const int status = child.wait(15);
  INFO(child.err());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  const std::optional<ExrFile> image = read_if_whole(dir / "out.dacrt.exr");
  REQUIRE(image);
  CHECK(attribute(*image, "backend") == "dacrt");
  CHECK(attribute(*image, "stoppedBy") == "SIGINT");
  check_counts(*image);
  CHECK_FALSE(fs::exists(dir / "out.brute.exr"));
  CHECK_FALSE(fs::exists(out));
  CHECK(temporaries(dir).empty());
  // The statistics hold the backend that rendered, not the one that never began.
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  REQUIRE(j.contains("backends"));
  REQUIRE(j["backends"].size() == 1);
  CHECK(j["backends"][0]["backend"] == "dacrt");
  CHECK(j["backends"][0]["stopped_by"] == "SIGINT");
}

TEST_CASE("render cli: --adaptive stops converged pixels, the samples, header and stats say so") {
  TempDir dir("render-cli-adaptive");
  const std::string out = dir / "out.exr", stats = dir / "stats.json";
  Run r = run(dir, "render " + cornell + " --width 24 --height 24 --spp 48 --quiet --seed 2" +
                       " --adaptive 0.2 --adaptive-min 8 -o " + out + " --stats " + stats);
  INFO(r.err);
  REQUIRE(r.code == 0);
  const ExrFile f = read_exr_file(out);
  // Counts that differ: the samples channel is written without being asked.
  const Channel* samples = f.find(Film::samples_channel);
  REQUIRE(samples);
  const auto [least, most] = std::minmax_element(samples->values.begin(), samples->values.end());
  CHECK(*least == 8.f);
  CHECK(*most == 48.f);
  double total = 0.0;
  for (float n : samples->values) total += n;
  check_counts(f);
  CHECK(attribute(f, "adaptiveTarget") == "0.2");
  CHECK(attribute(f, "adaptiveMinSpp") == "8");
  CHECK(attribute(f, "adaptiveSampling") == "on: relative error 0.2, at least 8 spp, at most 48");
  CHECK(attribute(f, "samplesPerPixel") == "from 8 to 48 (the samples.X channel)");
  const nlohmann::json j = nlohmann::json::parse(slurp(stats));
  REQUIRE(j.contains("adaptive"));
  CHECK(j["adaptive"]["target"] == 0.2);
  CHECK(j["adaptive"]["min_spp"] == 8);
  CHECK(j["adaptive"]["least_spp"] == 8);
  CHECK(j["adaptive"]["most_spp"] == 48);
  CHECK(j["adaptive"]["mean_spp"].get<double>() == doctest::Approx(total / (24 * 24)));
  // Every path rendered is a sample counted (the Cornell box drops none).
  CHECK(j["paths"].get<double>() == total);
  CHECK(j["dropped_samples"] == 0);
  // Without --adaptive the header and the statistics say nothing of it.
  const std::string plain = dir / "plain.exr", plain_stats = dir / "plain.json";
  REQUIRE(run(dir, "render " + cornell + " --width 8 --height 8 --spp 2 --quiet -o " + plain +
                       " --stats " + plain_stats)
              .code == 0);
  const ExrFile g = read_exr_file(plain);
  CHECK(attribute(g, "adaptiveSampling").empty());
  CHECK_FALSE(nlohmann::json::parse(slurp(plain_stats)).contains("adaptive"));
}

TEST_CASE("render cli: a bad --adaptive or --adaptive-min is one line naming it, exit 2") {
  TempDir dir("render-cli-adaptive-bad");
  const std::string out = dir / "out.exr";
  auto refused = [&](const std::string& flags, const std::string& named) {
    INFO(flags);
    const Run r = run(dir, "render " + cornell + " --spp 2 --quiet -o " + out + " " + flags);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
    CHECK(r.err.find(named) != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  };
  for (const char* bad : {"0", "1", "-0.1", "1.5", "nan", "inf", "-inf", "0.01x", "abc", "''"})
    refused("--adaptive " + std::string(bad), "--adaptive");
  refused("--adaptive", "--adaptive needs a value");
  for (const char* bad : {"1", "0", "-3", "x", "16.5"})
    refused("--adaptive 0.01 --adaptive-min " + std::string(bad), "--adaptive-min");
  refused("--adaptive-min 16", "--adaptive-min needs --adaptive");
}
