// Progress: the status line's pieces, and what reaches stderr (captured by pointing fd 2 at a
// temporary file, which also makes stderr a non-TTY).
#include "dacrt/util/progress.h"

#include <doctest/doctest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "tests/captured_stderr.h"
#include "dacrt/util/progress_format.h"

using dacrt::test::CapturedStderr;

namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

}  // namespace

TEST_CASE("format_rate picks rays/s, krays/s or Mrays/s with three digits") {
  CHECK(dacrt::format_rate(0) == "0 rays/s");
  CHECK(dacrt::format_rate(-5) == "0 rays/s");
  CHECK(dacrt::format_rate(std::nan("")) == "0 rays/s");
  CHECK(dacrt::format_rate(std::numeric_limits<double>::infinity()) == "0 rays/s");
  CHECK(dacrt::format_rate(7) == "7 rays/s");
  CHECK(dacrt::format_rate(850.4) == "850 rays/s");
  CHECK(dacrt::format_rate(999.4) == "999 rays/s");
  CHECK(dacrt::format_rate(999.6) == "1.00 krays/s");
  CHECK(dacrt::format_rate(1234) == "1.23 krays/s");
  CHECK(dacrt::format_rate(45678) == "45.7 krays/s");
  CHECK(dacrt::format_rate(456789) == "457 krays/s");
  CHECK(dacrt::format_rate(999700) == "1.00 Mrays/s");
  CHECK(dacrt::format_rate(12.3e6) == "12.3 Mrays/s");
  CHECK(dacrt::format_rate(4.56e6) == "4.56 Mrays/s");
  CHECK(dacrt::format_rate(2.5e9) == "2500 Mrays/s");
}

TEST_CASE("format_duration prints m:ss or h:mm:ss") {
  CHECK(dacrt::format_duration(0) == "0:00");
  CHECK(dacrt::format_duration(0.4) == "0:00");
  CHECK(dacrt::format_duration(7) == "0:07");
  CHECK(dacrt::format_duration(13.2) == "0:13");
  CHECK(dacrt::format_duration(59.6) == "1:00");
  CHECK(dacrt::format_duration(754) == "12:34");
  CHECK(dacrt::format_duration(3599) == "59:59");
  CHECK(dacrt::format_duration(3723) == "1:02:03");
  CHECK(dacrt::format_duration(359999) == "99:59:59");
  CHECK(dacrt::format_duration(1e12) == ">99:59:59");
  CHECK(dacrt::format_duration(-1) == "--:--");
  CHECK(dacrt::format_duration(std::nan("")) == "--:--");
  CHECK(dacrt::format_duration(std::numeric_limits<double>::infinity()) == "--:--");
}

TEST_CASE("format_bar fills a fraction of its cells") {
  CHECK(dacrt::format_bar(0) == "[--------------------]");
  CHECK(dacrt::format_bar(0.42) == "[########------------]");
  CHECK(dacrt::format_bar(0.999) == "[###################-]");
  CHECK(dacrt::format_bar(1) == "[####################]");
  CHECK(dacrt::format_bar(2) == "[####################]");
  CHECK(dacrt::format_bar(-1) == "[--------------------]");
  CHECK(dacrt::format_bar(std::nan("")) == "[--------------------]");
  CHECK(dacrt::format_bar(0.5, 4) == "[##--]");
  CHECK(dacrt::format_bar(0.5, 0) == "[]");
}

TEST_CASE("format_progress_line shows percent, rate and ETA") {
  CHECK(dacrt::format_progress_line("render", 0.42, 12.3e6, 9.4) ==
        "render [########------------]  42%  12.3 Mrays/s  ETA 0:13");
  CHECK(dacrt::format_progress_line("render", 0, 0, 0) ==
        "render [--------------------]   0%  0 rays/s  ETA --:--");
  CHECK(dacrt::format_progress_line("bvh", 0.5, -1, 3) ==
        "bvh [##########----------]  50%  ETA 0:03");
  CHECK(dacrt::format_progress_line("render", 0.9999, 1500, 100) ==
        "render [###################-]  99%  1.50 krays/s  ETA 0:00");
  CHECK(dacrt::format_progress_line("render", 1, 2e6, 83) ==
        "render [####################] 100%  2.00 Mrays/s  took 1:23");
}

TEST_CASE("a disabled Progress prints nothing") {
  CapturedStderr captured;
  {
    dacrt::Progress progress("render", 100, false);
    for (uint64_t i = 0; i <= 100; ++i) progress.update(i, i * 1000);
    progress.finish();
  }
  { dacrt::Progress unfinished("render", 0, false); }
  CHECK(captured.text().empty());
}

TEST_CASE("Progress in a log prints one line per 10 % step") {
  CapturedStderr captured;
  {
    dacrt::Progress progress("render", 1000, true);
    for (uint64_t i = 0; i <= 1000; ++i) progress.update(i, i * 1000);
    progress.update(1000, 1000 * 1000);  // repeated updates at 100 % add nothing
    progress.finish();
  }
  const std::string text = captured.text();
  CHECK(text.find('\r') == std::string::npos);
  const std::vector<std::string> lines = lines_of(text);
  REQUIRE(lines.size() == 10);
  for (int step = 1; step <= 10; ++step) {
    INFO(lines[step - 1]);
    char percent[8];
    std::snprintf(percent, sizeof percent, "%3d%%", 10 * step);
    CHECK(lines[step - 1].rfind("render [", 0) == 0);
    CHECK(lines[step - 1].find(percent) != std::string::npos);
    CHECK(lines[step - 1].find("rays/s") != std::string::npos);
  }
  CHECK(lines.back().find("took") != std::string::npos);
}

TEST_CASE("Progress with nothing to do prints 100 % once, from finish or the destructor") {
  {
    CapturedStderr captured;
    { dacrt::Progress progress("empty", 0, true); }  // the destructor finishes
    const std::vector<std::string> lines = lines_of(captured.text());
    REQUIRE(lines.size() == 1);
    CHECK(lines[0].find("100%") != std::string::npos);
  }
  {
    CapturedStderr captured;
    dacrt::Progress progress("empty", 0, true);
    progress.update(0, 0);
    progress.finish();
    progress.finish();
    const std::vector<std::string> lines = lines_of(captured.text());
    REQUIRE(lines.size() == 1);
    CHECK(lines[0].find("100%") != std::string::npos);
  }
}

TEST_CASE("Progress abandoned half-way prints only the steps reached") {
  CapturedStderr captured;
  {
    dacrt::Progress progress("render", 10, true);
    for (uint64_t i = 0; i <= 4; ++i) progress.update(i, 0);
  }
  const std::vector<std::string> lines = lines_of(captured.text());
  REQUIRE(lines.size() == 4);
  CHECK(lines.back().find(" 40%") != std::string::npos);
  CHECK(lines.back().find("rays/s") == std::string::npos);  // no rays counted: no rate
}
