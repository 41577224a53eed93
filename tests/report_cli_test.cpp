// `dacrt render --backend a,b --report DIR`: the page holds every backend's image and the table,
// needs nothing from elsewhere, and renders in a browser (headless Chromium, when installed:
// `make test` installs it) without errors and not blank.
#include <doctest/doctest.h>
#include <stb_image.h>

#include <cstdlib>
#include <memory>

#include "bench/html_page.h"
#include "cli.h"
#include "gltf_writer.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

const std::string cornell = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";

// Headless Chromium's screenshot of a page, its log beside it. Empty when Chromium is missing.
std::string screenshot(const TempDir& dir, const std::string& page, std::string& log) {
  const char* chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) return "";
  const std::string png = dir / "screenshot.png";
  const std::string cmd = std::string(chromium) +
                          " --headless=new --no-sandbox --disable-gpu --no-first-run"
                          " --user-data-dir=" + (dir / "profile") +
                          " --enable-logging=stderr --v=0 --window-size=1100,1600"
                          " --screenshot=" + png + " file://" + page + " >" + (dir / "log.txt") +
                          " 2>&1 </dev/null";
  const int status = std::system(("timeout 120 " + cmd).c_str());
  log = slurp(dir / "log.txt");
  REQUIRE_MESSAGE(WIFEXITED(status), log);
  REQUIRE_MESSAGE(WEXITSTATUS(status) == 0, log);
  return png;
}

// A page that a browser shows without a console or load error, and not blank.
void check_in_browser(const TempDir& dir, const std::string& page) {
  std::string log;
  const std::string shot = screenshot(dir, page, log);
  if (shot.empty()) {
    MESSAGE("skipped the browser check: /usr/bin/chromium is not installed (`make test` installs it)");
    return;
  }
  for (const char* error : {"ERROR:CONSOLE", "Uncaught", "Failed to load", "net::ERR"})
    CHECK_MESSAGE(log.find(error) == std::string::npos, log);
  int w = 0, h = 0, n = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> pixels(stbi_load(shot.c_str(), &w, &h, &n, 3),
                                                         stbi_image_free);
  REQUIRE(pixels);
  CHECK(w == 1100);
  // Not blank: the page's images and plots put many colours on the white.
  size_t coloured = 0;
  for (int i = 0; i < w * h; ++i) {
    const unsigned char* p = pixels.get() + 3 * i;
    coloured += !(p[0] == p[1] && p[1] == p[2]);
  }
  CHECK(coloured > size_t(w * h / 500));
}

// HTML Tidy (Debian `tidy`, which `make test` installs) finds nothing to say about the page: no
// error (exit status 2) and no warning (1: a tag left open or closed twice, an attribute it does
// not know).
void check_valid(const TempDir& dir, const std::string& page) {
  if (!fs::exists("/usr/bin/tidy")) {
    MESSAGE("skipped the HTML check: /usr/bin/tidy is not installed (`make test` installs it)");
    return;
  }
  const int status = std::system(("/usr/bin/tidy -errors -q " + page + " >" + (dir / "tidy.txt") +
                                  " 2>&1").c_str());
  INFO(slurp(dir / "tidy.txt"));
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
}

void check_self_contained(const std::string& html) {
  for (const char* remote : {"<script", "<link", "@import", "url(", "src=\"http"})
    CHECK_MESSAGE(html.find(remote) == std::string::npos, remote);
  // Links only inside the page (gnuplot's SVG reuses its point symbols: href='#gpPt4').
  for (size_t at = html.find("href="); at != std::string::npos; at = html.find("href=", at + 1))
    CHECK_MESSAGE(html.compare(at + 6, 1, "#") == 0, html.substr(at, 40));
}

// The page needs nothing from elsewhere, Tidy finds nothing in it, and a browser shows it.
void check_page(const TempDir& dir, const std::string& page) {
  check_self_contained(slurp(page));
  check_valid(dir, page);
  check_in_browser(dir, page);
}

// `command --report DIR` with a DIR that cannot be made: exit 1, the line names it.
void check_uncreatable(const TempDir& dir, const std::string& command, const std::string& report) {
  const Run r = run(dir, command + " --report " + report);
  CHECK(r.code == 1);
  CHECK(r.err.find(fs::path(report).filename().string()) != std::string::npos);
}

// `command`, which must succeed, and the page it wrote into `dir`.
struct Report {
  Run run;
  std::string html;
};
Report report_of(const TempDir& temp, const std::string& command, const std::string& dir) {
  Report r{run(temp, command), ""};
  REQUIRE_MESSAGE(r.run.code == 0, r.run.err);
  r.html = slurp(fs::path(dir) / "index.html");
  return r;
}

}  // namespace

TEST_CASE("render --report: one self-contained page with each backend's image, and a browser shows it") {
  TempDir dir("report");
  const std::string report = dir / "study";
  const std::string html = report_of(dir,
                                     "render " + cornell + " --width 48 --height 32 --spp 2 "
                                     "--quiet -o " + (dir / "cb.exr") +
                                         " --backend dacrt,brute --report " + report,
                                     report)
                               .html;
  for (const char* backend : {"dacrt", "brute"}) {
    const std::string png = slurp(fs::path(report) / (std::string(backend) + ".png"));
    REQUIRE(png.size() > 8);
    const std::string embedded =
        base64({reinterpret_cast<const uint8_t*>(png.data()), png.size()});
    CHECK_MESSAGE(html.find("src=\"data:image/png;base64," + embedded + "\"") != std::string::npos,
                  backend);
  }
  CHECK(html.find("cornell-box.gltf, 48×32, 2 spp") != std::string::npos);
  CHECK(html.find("<td>triangle tests</td>") != std::string::npos);
  CHECK(html.find("Mrays/s per ray type") != std::string::npos);
  CHECK(html.find("Bounce rays per depth") != std::string::npos);

  // --report is an output: refused with --frames, and a directory that cannot be made is named.
  const Run frames = run(dir, "render " + cornell + " --spp 1 --frames 0:1 --report " + report);
  CHECK(frames.code == 2);
  CHECK(frames.err.find("--report") != std::string::npos);
  check_uncreatable(dir, "render " + cornell + " --spp 1 -o " + (dir / "x.exr"),
                    dir / "cb.dacrt.exr/sub");
  check_page(dir, fs::path(report) / "index.html");
}

TEST_CASE("bench --report: the table and the Mrays/s with their intervals, on one page") {
  TempDir dir("bench-report");
  const std::string report = dir / "bench";
  const std::string html = report_of(dir,
                                     "bench " + cornell + " --width 16 --height 16 --rays "
                                     "primary,bounce --repeat 3 --backends dacrt,brute --quiet "
                                     "--report " + report,
                                     report)
                               .html;
  CHECK(html.find("Mrays/s per ray type") != std::string::npos);
  CHECK(html.find("after 1 discarded warm-up run") != std::string::npos);
  // Four bars (two ray types, two backends), each with its interval's whisker.
  size_t whiskers = 0;
  for (size_t at = html.find("<path"); at != std::string::npos; at = html.find("<path", at + 1))
    ++whiskers;
  CHECK(whiskers == 4);
  for (const char* cell : {"<td>primary</td>", "<td>bounce</td>", "<td>dacrt</td>", "<td>brute</td>"})
    CHECK_MESSAGE(html.find(cell) != std::string::npos, cell);
  check_uncreatable(dir, "bench " + cornell + " --width 16 --height 16",
                    dir / "bench/index.html/x");
  check_page(dir, fs::path(report) / "index.html");
}

TEST_CASE("converge -o DIR: the plot, the tables and every point with its band on one page") {
  TempDir dir("converge-report");
  const std::string out = dir / "study";
  const auto [r, html] = report_of(dir,
                                   "converge " + cornell + " --width 12 --height 12 "
                                   "--reference-spp 16 --max-spp 4 --repeats 2 --config \"\" "
                                   "--config sampler=independent --quiet -o " + out,
                                   out);
  // The summary printed on stdout is in the page as it is.
  const size_t equal_time = r.out.find("equal time:");
  REQUIRE(equal_time != std::string::npos);
  CHECK(html.find(html_escape(r.out.substr(equal_time, 40))) != std::string::npos);
  CHECK(html.find("<td>sampler=independent</td><td>4</td><td>2</td>") != std::string::npos);
  CHECK(html.find("[95 % band]") != std::string::npos);
  if (fs::exists(fs::path(out) / "convergence.svg"))
    CHECK(html.find("<svg") != std::string::npos);
  else
    CHECK(html.find("No plot: gnuplot was not found") != std::string::npos);
  check_page(dir, fs::path(out) / "index.html");
}

TEST_CASE("--report: a command that fails leaves no directory behind, not even an empty one") {
  TempDir dir("report-failed");
  write_text(dir / "bad.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": 7}");
  const std::string missing = dir / "missing.gltf", bad = dir / "bad.gltf";
  const std::string unwritable = " -o " + (dir / "no-such-directory/x.exr");
  struct Case {
    std::string command;
    int code;
  };
  const std::vector<Case> cases = {
      {"render " + missing + " --spp 1 -o " + (dir / "x.exr"), 1},
      {"render " + bad + " --spp 1 -o " + (dir / "x.exr"), 1},
      {"render " + cornell + " --spp 1" + unwritable, 1},
      {"render " + cornell + " --spp 1 --nope -o " + (dir / "x.exr"), 2},
      {"bench " + missing + " --width 8 --height 8", 1},
      {"bench " + bad + " --width 8 --height 8", 1},
  };
  for (const Case& c : cases) {
    for (const std::string& report : {dir / "r", dir / "a/b/c"}) {
      CAPTURE(c.command);
      CAPTURE(report);
      const Run r = run(dir, c.command + " --report " + report);
      CHECK(r.code == c.code);
      CHECK(lines(r.err) == 1);
      CHECK(!fs::exists(dir / "r"));
      CHECK(!fs::exists(dir / "a"));
    }
  }
  // A directory that was there stays, with what was in it.
  fs::create_directories(dir / "kept");
  write_text(dir / "kept/notes.txt", "mine");
  const Run r = run(dir, "render " + missing + " --spp 1 -o " + (dir / "x.exr") + " --report " +
                             (dir / "kept"));
  CHECK(r.code == 1);
  CHECK(slurp(dir / "kept/notes.txt") == "mine");
  CHECK(std::distance(fs::directory_iterator(dir / "kept"), fs::directory_iterator()) == 1);
}
