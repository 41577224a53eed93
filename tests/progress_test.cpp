// Progress: the status line's pieces, and what reaches stderr (captured by pointing fd 2 at a
// temporary file, which also makes stderr a non-TTY).
#include "dacrt/util/progress.h"

#include <doctest/doctest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
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

// A clock the test moves and a sink that keeps what is written, for Progress and Activity.
struct FakeOutput {
  double time = 100.0;
  std::string text;
  dacrt::ProgressTimes times = manual();
  // The default times, without the watching thread (the test moves the clock).
  static dacrt::ProgressTimes manual() {
    dacrt::ProgressTimes t;
    t.watch = false;
    return t;
  }
  dacrt::ProgressOutput output(bool terminal) {
    dacrt::ProgressOutput out;
    out.write = [this](const std::string& t) { text += t; };
    out.now = [this] { return time; };
    out.terminal = terminal;
    return out;
  }
};

TEST_CASE("Progress in a log prints at 1 s, every 5 s, every 30 s after 5 min, and at the end") {
  FakeOutput fake;
  {
    // 1600 samples of 8 pixels over 400 s (1 % of the 160000 asked, as with a time limit), an
    // update every 0.25 s, 1 Mrays/s.
    dacrt::Progress progress("render", 160000, true, {}, 8, fake.output(false), fake.times);
    for (int step = 0; step <= 1600; ++step) {
      fake.time = 100.0 + step * 0.25;
      progress.update(uint64_t(step), uint64_t(step) * 250000);
    }
    progress.finish();
  }
  const std::vector<std::string> lines = lines_of(fake.text);
  CHECK(fake.text.find('\r') == std::string::npos);
  // At 1 s, then every 5 s to 296 s (60 lines), every 30 s after 300 s (326, 356, 386), the end.
  REQUIRE(lines.size() == 60 + 3 + 1);
  CHECK(lines[0] == "render: 0%, 0.5/20000 spp, 1.00 Mrays/s, ETA 11:06:39");
  CHECK(lines[1] == "render: 0%, 3/20000 spp, 1.00 Mrays/s, ETA 11:06:34");      // at 6 s
  CHECK(lines[59] == "render: 0%, 148/20000 spp, 1.00 Mrays/s, ETA 11:01:44");   // at 296 s
  CHECK(lines[60].rfind("render: 0%, 163/20000 spp", 0) == 0);                   // at 326 s
  CHECK(lines.back() == "render: 1%, 200/20000 spp, 1.00 Mrays/s, took 6:40");
}

TEST_CASE("Progress in a log prints one line per 10 % step, the last with the time it took") {
  FakeOutput fake;
  {
    dacrt::Progress progress("render", 1000, true, {}, 0, fake.output(false), fake.times);
    for (uint64_t i = 0; i <= 1000; ++i) {
      fake.time += 0.0001;
      progress.update(i, i * 1000);
    }
    progress.update(1000, 1000 * 1000);  // repeated updates at 100 % add nothing
    progress.finish();
  }
  const std::vector<std::string> lines = lines_of(fake.text);
  REQUIRE(lines.size() == 10);
  for (int step = 1; step <= 10; ++step) {
    INFO(lines[step - 1]);
    CHECK(lines[step - 1].rfind("render: " + std::to_string(10 * step) + "%, ", 0) == 0);
    CHECK(lines[step - 1].find("rays/s") != std::string::npos);
  }
  CHECK(lines.back().find("took") != std::string::npos);
}

TEST_CASE("Progress in a log without tenths says nothing of work shorter than a second") {
  FakeOutput fake;
  dacrt::ProgressTimes times = FakeOutput::manual();
  times.tenths = false;
  {
    dacrt::Progress progress("converge", 100, true, {}, 0, fake.output(false), times);
    for (int i = 0; i <= 100; ++i) {
      fake.time = 100.0 + i * 0.009;
      progress.update(uint64_t(i), 0);
    }
  }
  CHECK(fake.text.empty());  // the line that follows says it
}

TEST_CASE("Progress of one part of a whole names it and gives the total ETA") {
  FakeOutput fake;
  dacrt::ProgressPart part;
  part.position = "frame 12 (3 of 5)";
  part.before = 0.4, part.share = 0.2, part.whole_start = 80.0;  // two frames took 20 s
  SUBCASE("in a log") {
    {
      dacrt::Progress progress("render", 100, true, part, 0, fake.output(false), fake.times);
      fake.time = 102.0;
      progress.update(50, 0);  // half of frame 3 in 2 s: 50 % of the whole in 22 s
      fake.time = 104.0;
      progress.update(100, 0);
      progress.finish();
    }
    const std::vector<std::string> lines = lines_of(fake.text);
    REQUIRE(lines.size() == 2);
    CHECK(lines[0] == "render frame 12 (3 of 5): 50%, ETA 0:02, total ETA 0:22");
    CHECK(lines[1] == "render frame 12 (3 of 5): 100%, took 0:04, total ETA 0:16");
  }
  SUBCASE("on a terminal") {
    {
      dacrt::Progress progress("render", 100, true, part, 0, fake.output(true), fake.times);
      fake.time = 102.0;
      progress.update(50, 0);
    }
    CHECK(fake.text ==
          "\rrender frame 12 (3 of 5) [##########----------]  50%  ETA 0:02  total ETA "
          "0:22\033[K\n");
  }
}

TEST_CASE("a disabled Progress writes nothing to its output") {
  FakeOutput fake;
  {
    dacrt::Progress progress("render", 100, false, {}, 1, fake.output(false), fake.times);
    for (int i = 0; i <= 100; ++i) {
      fake.time += 1;
      progress.update(uint64_t(i), 5);
    }
  }
  CHECK(fake.text.empty());
}

TEST_CASE("an Activity says nothing when quick, and what it does every few seconds when long") {
  FakeOutput fake;
  {
    dacrt::Activity quick("loading a.glb", true, fake.output(false), fake.times);
    fake.time += 0.5;
    quick.tick();
    quick.done("loaded a.glb in 0.5 s");
  }
  CHECK(fake.text.empty());
  {
    dacrt::Activity slow("loading b.glb (12 MB)", true, fake.output(false), fake.times);
    for (int tenth = 1; tenth <= 120; ++tenth) {
      fake.time += 0.1;
      slow.tick();
    }
    slow.done("loaded b.glb in 12.0 s: reading the file 2.0 s");
  }
  CHECK(fake.text ==
        "loading b.glb (12 MB)\n"
        "loading b.glb (12 MB): 0:06 so far\n"
        "loading b.glb (12 MB): 0:11 so far\n"
        "loaded b.glb in 12.0 s: reading the file 2.0 s\n");
  fake.text.clear();
  {
    dacrt::Activity quiet("loading c.glb", false, fake.output(false), fake.times);
    fake.time += 60;
    quiet.tick();
    quiet.done("loaded");
  }
  CHECK(fake.text.empty());
}

TEST_CASE("an Activity's thread speaks while the step blocks") {
  FakeOutput fake;
  std::mutex mutex;  // the thread writes while this one waits
  dacrt::ProgressOutput out;
  std::string text;
  out.write = [&](const std::string& t) {
    std::lock_guard lock(mutex);
    text += t;
  };
  const auto t0 = std::chrono::steady_clock::now();
  out.now = [t0] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  dacrt::ProgressTimes times;
  times.first = 0.05;
  {
    dacrt::Activity step("building", true, out, times);
    for (int i = 0; i < 100; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      std::lock_guard lock(mutex);
      if (!text.empty()) break;
    }
    step.done("built");
  }
  CHECK(text == "building\nbuilt\n");
}

TEST_CASE("a Progress's thread prints on time while no update comes") {
  std::mutex mutex;  // the thread writes while this one waits
  std::string text;
  dacrt::ProgressOutput out;
  out.write = [&](const std::string& t) {
    std::lock_guard lock(mutex);
    text += t;
  };
  const auto t0 = std::chrono::steady_clock::now();
  out.now = [t0] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  dacrt::ProgressTimes times;
  times.first = 0.05;  // a first wavefront slower than that gives no update
  {
    dacrt::Progress progress("render", 100, true, {}, 0, out, times);
    for (int i = 0; i < 100; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      std::lock_guard lock(mutex);
      if (!text.empty()) break;
    }
    progress.update(100, 0);
  }
  const std::vector<std::string> lines = lines_of(text);
  REQUIRE(lines.size() == 2);
  CHECK(lines[0] == "render: 0%, ETA --:--");
  CHECK(lines[1].rfind("render: 100%, took ", 0) == 0);
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

TEST_CASE("Progress stopped half-way ends its log with where it stopped") {
  FakeOutput fake;
  {
    dacrt::Progress progress("render", 10, true, {}, 0, fake.output(false), fake.times);
    for (uint64_t i = 0; i <= 4; ++i) {
      fake.time += 0.5;
      progress.update(i, 0);
    }
  }
  const std::vector<std::string> lines = lines_of(fake.text);
  REQUIRE(lines.size() == 5);
  CHECK(lines[0] == "render: 10%, ETA 0:09");  // at 1 s, the 10 % step
  CHECK(lines[3] == "render: 40%, ETA 0:04");
  CHECK(lines[4] == "render: 40%, took 0:03");
  CHECK(lines.back().find("rays/s") == std::string::npos);  // no rays counted: no rate
}
