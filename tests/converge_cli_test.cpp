// `dacrt converge` as a user runs it, on the Cornell box at a few pixels and tiny budgets: the
// CSV's columns and rows, the plot when gnuplot is there (and the warning when it is not), the
// reference it renders or reads, the error falling with the samples at the rate Monte Carlo
// promises, and bad input: one line, a usage or error exit code, nothing written.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "dacrt/io/exr.h"

using namespace dacrt;
using namespace dacrt::test;
namespace fs = std::filesystem;

namespace {

const std::string cornell = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";
const std::string tiny = cornell + " --width 12 --height 12 --max-depth 4 --quiet";
const std::string header =
    "config,spp,seconds,rmse,relmse,mae,smape,noise,repeats,seconds_low,seconds_high,rmse_low,"
    "rmse_high,relmse_low,relmse_high,mae_low,mae_high,smape_low,smape_high,noise_low,noise_high,"
    "rmse_raw,relmse_raw,reference_mse,reference_relmse";

bool have_gnuplot() {
  return std::system("command -v gnuplot >/dev/null 2>&1") == 0;
}

std::vector<std::string> split(const std::string& text, char by) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, by)) parts.push_back(part);
  if (!text.empty() && text.back() == by) parts.push_back("");
  return parts;
}

struct Row {
  std::string config;
  int spp;
  double seconds;
  std::vector<std::string> metrics;  // rmse, relmse, mae, smape, noise (empty: not measured)
  std::map<std::string, std::string> cells;  // every column after config, by name
  double number(const std::string& column) const {
    REQUIRE_MESSAGE(!cells.at(column).empty(), column);
    return std::stod(cells.at(column));
  }
};

// The CSV's rows, its header checked.
std::vector<Row> read_csv(const std::string& path) {
  std::vector<std::string> lines = split(slurp(path), '\n');
  REQUIRE(!lines.empty());
  CHECK(lines[0] == header);
  const std::vector<std::string> columns = split(header, ',');
  std::vector<Row> rows;
  for (size_t k = 1; k < lines.size(); ++k) {
    if (lines[k].empty()) continue;
    const std::vector<std::string> cells = split(lines[k], ',');
    REQUIRE_MESSAGE(cells.size() == columns.size(), lines[k]);
    REQUIRE(cells[0].size() >= 2);
    CHECK(cells[0].front() == '"');
    Row row{cells[0].substr(1, cells[0].size() - 2),
            std::stoi(cells[1]),
            std::stod(cells[2]),
            std::vector<std::string>(cells.begin() + 3, cells.begin() + 8),
            {}};
    for (size_t c = 1; c < cells.size(); ++c) row.cells[columns[c]] = cells[c];
    rows.push_back(row);
  }
  return rows;
}

std::map<std::string, std::vector<Row>> by_config(const std::vector<Row>& rows) {
  std::map<std::string, std::vector<Row>> m;
  for (const Row& r : rows) m[r.config].push_back(r);
  return m;
}

// Every file in `dir`, by name.
std::vector<std::string> files(const fs::path& dir) {
  std::vector<std::string> names;
  if (!fs::exists(dir)) return names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST_CASE("converge: a tiny run writes the CSV, the script, the reference and the plot") {
  TempDir dir("converge-cli");
  const std::string out = dir / "out";
  const Run r = run(dir, "converge " + tiny + " --time-budget 0.02 --reference-spp 16 --noise -o " +
                             out + " --config '' --config 'sampler=independent max-depth=2'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  // --quiet: no progress, only the warnings that these runs are too short to time.
  CHECK(lines(r.err) == 2);
  CHECK(r.err.find("warning: --config \"default\" ran ") != std::string::npos);
  const auto configs = by_config(read_csv(out + "/convergence.csv"));
  REQUIRE(configs.size() == 2);
  for (const char* label : {"default", "sampler=independent max-depth=2"}) {
    INFO(label);
    REQUIRE(configs.count(label));
    const std::vector<Row>& rows = configs.at(label);
    REQUIRE(rows.size() >= 2);  // 1 and 2 spp at least, whatever the budget
    for (size_t k = 0; k < rows.size(); ++k) {
      CHECK(rows[k].spp == 1 << k);
      CHECK(rows[k].seconds > 0);
      if (k) CHECK(rows[k].seconds > rows[k - 1].seconds);
      for (size_t m = 0; m < rows[k].metrics.size(); ++m) {
        CHECK(!rows[k].metrics[m].empty());
        // RMSE and relMSE less the 16-spp reference's own error reach 0 (clamped) once the
        // render is as good as the reference.
        CHECK(std::stod(rows[k].metrics[m]) >= (m < 2 ? 0 : 1e-12));
      }
      // One repeat: no band.
      CHECK(rows[k].cells.at("repeats") == "1");
      CHECK(rows[k].cells.at("rmse_low").empty());
      CHECK(rows[k].cells.at("noise_high").empty());
    }
  }
  const ExrFile reference = read_exr_file(out + "/reference.exr");
  CHECK(reference.width == 12);
  CHECK(reference.attributes.at("spp") == "16");
  const std::string script = slurp(out + "/convergence.gp");
  CHECK(script.find("'default: slope ") != std::string::npos);
  CHECK(script.find("set logscale xy") != std::string::npos);
  CHECK(r.out.find("equal error: RMSE") != std::string::npos);
  CHECK(r.out.find("equal time: ") != std::string::npos);
  std::vector<std::string> expected = {"convergence.csv", "convergence.gp", "index.html",
                                       "reference.exr"};
  if (have_gnuplot()) {
    const std::string svg = slurp(out + "/convergence.svg"), png = slurp(out + "/convergence.png");
    CHECK(svg.find("<svg") != std::string::npos);
    CHECK(svg.find("sampler=independent max-depth=2: slope") != std::string::npos);
    REQUIRE(png.size() > 8);
    CHECK(png.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
    expected = {"convergence.csv", "convergence.gp", "convergence.png", "convergence.svg",
                "index.html", "reference.exr"};
  } else {
    MESSAGE("gnuplot is not installed: the plot is not checked");
  }
  CHECK(files(out) == expected);  // and no temporary left
}

TEST_CASE("converge: the error against a reference falls as 1/sqrt(spp)") {
  TempDir dir("converge-cli-slope");
  const std::string ref = dir / "ref.exr";
  // A view of the box below the light: with the light in 144 pixels, the few on its edges (whose
  // coverage is a coin of value ~17) carry most of the squared error, and one run's RMSE then
  // wanders by more than the halving checked here (8 spp 0.06, 16 spp 0.10, 64 spp 0.08).
  const std::string view = tiny + " --look-at 0.278,0.2,0.28 --fov 25";
  REQUIRE(run(dir, "render " + view + " --spp 4096 --seed 7 -o " + ref).code == 0);
  const Run r = run(dir, "converge " + view + " --reference " + ref +
                             " --time-budget 1000 --max-spp 64 --no-plot -o " + (dir / "out") +
                             " --config sampler=independent");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::vector<Row> rows = read_csv(dir / "out/convergence.csv");
  REQUIRE(rows.size() == 7);  // 1, 2, …, 64: --max-spp stops it, not the budget
  std::vector<double> rmse;
  for (const Row& row : rows) {
    rmse.push_back(std::stod(row.metrics[0]));
    CHECK(row.metrics[4].empty());  // no noise asked
  }
  for (size_t k = 2; k < rmse.size(); ++k) CHECK(rmse[k] < rmse[k - 2]);
  // 64 times the samples: 1/8 of the error, give or take the estimate's own noise.
  CHECK(rmse[6] / rmse[0] > 0.125 / 1.6);
  CHECK(rmse[6] / rmse[0] < 0.125 * 1.6);
  // The table's fitted slope against spp.
  const size_t at = r.out.find("sampler=independent ");
  REQUIRE(at != std::string::npos);
  std::istringstream line(r.out.substr(at + 20));
  int points = 0, spp = 0;
  double seconds = 0, last = 0, slope = 0;
  line >> points >> spp >> seconds >> last >> slope;
  CHECK(points == 7);
  CHECK(spp == 64);
  CHECK(std::abs(last / rmse[6] - 1) < 0.01);
  CHECK(slope > -0.65);
  CHECK(slope < -0.35);
}

TEST_CASE("converge: without a reference, the noise between two seeds is the error") {
  TempDir dir("converge-cli-noise");
  const Run r = run(dir, "converge " + tiny + " --no-reference --time-budget 0.02 --no-plot -o " +
                             (dir / "out") + " --config backend=brute");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::vector<Row> rows = read_csv(dir / "out/convergence.csv");
  REQUIRE(rows.size() >= 2);
  for (const Row& row : rows) {
    CHECK(row.config == "backend=brute");
    for (int m = 0; m < 4; ++m) CHECK(row.metrics[m].empty());
    CHECK(std::stod(row.metrics[4]) > 0);
  }
  CHECK(std::stod(rows[1].metrics[4]) < std::stod(rows[0].metrics[4]));
  CHECK(r.out.find("equal error: noise") != std::string::npos);
  CHECK(files(dir / "out") == std::vector<std::string>{"convergence.csv", "convergence.gp", "index.html"});
}

TEST_CASE("converge: without gnuplot the CSV and the script are written, with a warning") {
  TempDir dir("converge-cli-no-gnuplot");
  const Run r = run(dir,
                    "converge " + tiny + " --no-reference --time-budget 0.02 -o " + (dir / "out") +
                        " --config ''",
                    "PATH=/nonexistent");
  CHECK(r.code == 0);
  CHECK(r.err.find("warning: gnuplot is not on PATH") != std::string::npos);
  CHECK(r.err.find("gnuplot convergence.gp") != std::string::npos);
  CHECK(files(dir / "out") == std::vector<std::string>{"convergence.csv", "convergence.gp", "index.html"});
}

TEST_CASE("converge: bad input is one line, a non-zero exit, and nothing written") {
  TempDir dir("converge-cli-errors");
  {
    std::ofstream(dir / "not.exr") << "not an EXR\n";
    std::ofstream(dir / "file") << "a file\n";
  }
  const std::string small_ref = dir / "small.exr";
  REQUIRE(run(dir, "render " + cornell + " --width 6 --height 6 --spp 1 --quiet -o " + small_ref)
              .code == 0);
  const std::string out = " -o " + (dir / "out");
  struct Case {
    std::string args;
    int code;
    std::string says;
  };
  const std::vector<Case> cases = {
      {"--config 'bogus=1'" + out, 2, "unknown key 'bogus'"},
      {"--config 'max-depth=x'" + out, 2, "--max-depth wants an integer"},
      {"--config 'sampler'" + out, 2, "'sampler' is not KEY=VALUE"},
      {"--config 'width=8'" + out, 2, "width changes the image"},
      {"--config 'spp=8'" + out, 2, "spp does not apply"},
      {"--config 'quiet=1'" + out, 2, "unknown key 'quiet'"},
      {"--config 'backend=dacrt,embree'" + out, 2, "one backend"},
      {"--config 'integrator=nope'" + out, 2, "unknown integrator 'nope'"},
      {"--config '' --config ' '" + out, 2, "given twice"},
      {"--spp 4" + out, 2, "--spp does not apply"},
      // The option table says where an option is taken: --frames is render's alone.
      {"--frames 0:1" + out, 2, "--frames does not apply"},
      {"--config 'frames=0:1'" + out, 2, "frames does not apply"},
      {"--config 'look-from=0,1,2'" + out, 2, "look-from changes the image"},
      {"--metric rms" + out, 2, "--metric wants"},
      {"--time-budget 0" + out, 2, "--time-budget wants a positive number"},
      {"--repeats 0" + out, 2, "--repeats"},
      {"--repeats 2.5" + out, 2, "--repeats"},
      {"--reference-spp 1" + out, 2, "--reference-spp"},
      {"--reference " + (dir / "missing.exr") + out, 1, "missing.exr"},
      {"--reference " + (dir / "not.exr") + out, 1, "not.exr"},
      {"--reference " + small_ref + out, 1, "the reference is 6 x 6, the renders are 12 x 12"},
      {"--reference " + small_ref + " --no-reference" + out, 2, "exclude each other"},
      {"-o " + (dir / "no/such/dir"), 1, "does not exist"},
      {"-o " + (dir / "file"), 1, "it is not a directory"},
  };
  for (const Case& c : cases) {
    INFO(c.args);
    const Run r = run(dir, "converge " + tiny + " --time-budget 0.01 " + c.args);
    CHECK(r.code == c.code);
    CHECK(lines(r.err) == 1);
    CHECK_MESSAGE(r.err.find(c.says) != std::string::npos, r.err);
    CHECK(r.out.empty());
    CHECK(files(dir.path()) == std::vector<std::string>{"file", "not.exr", "small.exr"});
  }
}

TEST_CASE("converge: --help lists the options") {
  TempDir dir("converge-cli-help");
  const Run r = run(dir, "converge --help");
  CHECK(r.code == 0);
  for (const char* option :
       {"--config", "--reference", "--reference-spp", "--time-budget", "--noise", "--no-reference",
        "--metric", "--quiet", "-o, --output", "--repeats"})
    CHECK_MESSAGE(r.out.find(option) != std::string::npos, option);
  CHECK(run(dir, "--help").out.find("dacrt converge SCENE") != std::string::npos);
}

TEST_CASE("converge: SIGTERM stops at the next wavefront and writes the points finished") {
  TempDir dir("converge-cli-signal");
  const std::string out = dir / "out", err = dir / "err.txt", rc = dir / "rc.txt";
  // (The run is a shell script: a background job, polled, signalled, waited for.)
  // A budget of minutes; the signal comes once stderr shows the 4-spp point.
  const std::string script =
      std::string(DACRT_CLI) + " converge " + cornell +
      " --width 32 --height 32 --no-reference --time-budget 600 --no-plot --config '' -o " + out +
      " >/dev/null 2>" + err + " & pid=$!; for i in $(seq 300); do grep -q ' 4 spp' " + err +
      " && break; sleep 0.05; done; kill -TERM $pid; wait $pid; echo $? >" + rc;
  std::ofstream(dir / "run.sh") << script << "\n";
  REQUIRE(std::system(("bash " + (dir / "run.sh")).c_str()) == 0);
  INFO(slurp(err));
  CHECK(slurp(rc) == "143\n");
  const std::vector<Row> rows = read_csv(out + "/convergence.csv");
  CHECK(rows.size() >= 3);
  CHECK(rows.size() < 16);  // stopped long before the budget
  CHECK(files(out) == std::vector<std::string>{"convergence.csv", "convergence.gp", "index.html"});
}

TEST_CASE("converge: --adaptive is a configuration's flag, compared with uniform sampling") {
  TempDir dir("converge-cli-adaptive");
  const std::string out = dir / "out";
  const Run r = run(dir, "converge " + tiny + " --max-spp 8 --reference-spp 16 -o " + out +
                             " --no-plot --config '' --config 'adaptive=0.2 adaptive-min=2'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto configs = by_config(read_csv(out + "/convergence.csv"));
  REQUIRE(configs.count("default"));
  REQUIRE(configs.count("adaptive=0.2 adaptive-min=2"));
  CHECK(configs.at("adaptive=0.2 adaptive-min=2").size() == 4);  // 1, 2, 4, 8 spp
  CHECK(r.out.find("equal time: ") != std::string::npos);
  // A bad value is refused before anything renders, naming the configuration.
  const Run bad = run(dir, "converge " + tiny + " -o " + (dir / "bad") + " --config 'adaptive=2'");
  CHECK(bad.code == 2);
  CHECK(lines(bad.err) == 1);
  CHECK(bad.err.find("--adaptive") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "bad"));
}

TEST_CASE("converge: --repeats gives every point a mean and a 95 % band") {
  TempDir dir("converge-cli-repeats");
  const std::string out = dir / "out";
  const Run r = run(dir, "converge " + tiny +
                             " --repeats 3 --max-spp 4 --reference-spp 16 "
                             "--noise -o " +
                             out + " --config 'sampler=independent'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::vector<Row> rows = read_csv(out + "/convergence.csv");
  REQUIRE(rows.size() == 3);  // 1, 2, 4 spp: the first repeat's points, which the others render
  for (const Row& row : rows) {
    INFO(row.spp);
    CHECK(row.cells.at("repeats") == "3");
    for (const char* key : {"seconds", "rmse", "relmse", "mae", "smape", "noise"}) {
      INFO(key);
      // Three seeds, three different errors: a band of some width around the mean.
      CHECK(row.number(std::string(key) + "_low") < row.number(key));
      CHECK(row.number(key) < row.number(std::string(key) + "_high"));
    }
  }
  if (have_gnuplot()) CHECK(slurp(out + "/convergence.svg").find("<svg") != std::string::npos);
  CHECK(slurp(out + "/convergence.gp").find("using 1:4:5 with filledcurves") != std::string::npos);
  CHECK(r.out.find("95 % confidence interval") != std::string::npos);
  // The configuration's line in the summary, the equal-error and the equal-time tables, each
  // with its "[low, high]".
  for (const char* table : {"config ", "equal error: ", "equal time: "}) {
    INFO(table);
    const size_t from = r.out.find(table);
    REQUIRE(from != std::string::npos);
    const size_t row = r.out.find("sampler=independent  ", from);
    REQUIRE(row != std::string::npos);
    const std::string line = r.out.substr(row, r.out.find('\n', row) - row);
    CHECK_MESSAGE(line.find(" [") != std::string::npos, line);
    CHECK_MESSAGE(line.find("]") != std::string::npos, line);
  }
}

TEST_CASE("converge: the reference's own MSE, from its halves, is subtracted and kept") {
  TempDir dir("converge-cli-reference-error");
  const std::string out = dir / "out";
  const Run r = run(dir, "converge " + tiny + " --max-spp 16 --reference-spp 8 --no-plot -o " +
                             out + " --config 'sampler=independent'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const ExrFile reference = read_exr_file(out + "/reference.exr");
  const double mse = std::stod(reference.attributes.at("referenceMse"));
  CHECK(mse > 0);
  CHECK(std::stod(reference.attributes.at("referenceRelmse")) > 0);
  CHECK(r.out.find("its own MSE") != std::string::npos);
  const std::vector<Row> rows = read_csv(out + "/convergence.csv");
  REQUIRE(rows.size() == 5);
  for (const Row& row : rows) {
    INFO(row.spp);
    CHECK(row.number("reference_mse") == doctest::Approx(mse).epsilon(1e-6).scale(0));
    const double raw = row.number("rmse_raw"), rmse = row.number("rmse");
    // RMSE² = raw RMSE² − the reference's MSE, clamped at 0: an 8-spp reference is as noisy as
    // the 8-spp render, and past it the render's error is mostly the reference's.
    if (raw * raw <= mse)  // clamped: exactly 0 (a relative Approx of 0 can never hold)
      CHECK(rmse == 0.0);
    else
      CHECK(rmse * rmse == doctest::Approx(raw * raw - mse).epsilon(1e-5).scale(0));
    CHECK(row.number("relmse") <= row.number("relmse_raw"));
  }
  CHECK(rows[0].number("rmse") > 0);
  CHECK(rows[0].number("rmse") < rows[0].number("rmse_raw"));
  // Reused with --reference it is subtracted again; a reference without the attribute is not.
  const Run again = run(dir, "converge " + tiny + " --max-spp 2 --no-plot --reference " + out +
                                 "/reference.exr -o " + (dir / "again") + " --config ''");
  REQUIRE(again.code == 0);
  CHECK(read_csv(dir / "again/convergence.csv")[0].number("reference_mse") ==
        doctest::Approx(mse).epsilon(1e-6).scale(0));
  const std::string plain = dir / "plain.exr";
  REQUIRE(run(dir, "render " + tiny + " --spp 8 -o " + plain).code == 0);
  const Run other = run(dir, "converge " + tiny + " --max-spp 2 --no-plot --reference " + plain +
                                 " -o " + (dir / "other") + " --config ''");
  REQUIRE(other.code == 0);
  CHECK(other.out.find("not subtracted") != std::string::npos);
  for (const Row& row : read_csv(dir / "other/convergence.csv")) {
    CHECK(row.cells.at("reference_mse").empty());
    CHECK(row.cells.at("rmse") == row.cells.at("rmse_raw"));
  }
}

TEST_CASE("converge: a configuration that ran under 0.1 s gets a warning, a longer one none") {
  TempDir dir("converge-cli-short");
  const Run r = run(dir, "converge " + tiny + " --max-spp 2 --no-reference --no-plot -o " +
                             (dir / "short") + " --config 'max-depth=2'");
  REQUIRE(r.code == 0);
  CHECK(lines(r.err) == 1);
  CHECK(r.err.find("warning: --config \"max-depth=2\" ran ") != std::string::npos);
  CHECK(r.err.find("times under 0.1 s are noisy") != std::string::npos);
  // The budget stops doubling once the next point would end past 0.4 s: the last point is past
  // 0.2 s (doubling costs what the samples so far cost).
  const Run longer = run(dir, "converge " + cornell +
                                  " --width 16 --height 16 --quiet "
                                  "--threads 1 --no-reference --no-plot --time-budget 0.4 -o " +
                                  (dir / "long") + " --config ''");
  INFO(longer.err);
  REQUIRE(longer.code == 0);
  CHECK(longer.err.empty());
}
