// `mpirun -np R dacrt render …`: the ranks split the samples and their films add up on rank 0,
// bit for bit the image of one process for any R; progress and errors come from rank 0; a rank
// that fails fails the job with its message and nothing is written. Skipped (with a message)
// where OpenMPI's mpirun is not installed; `make test` installs it.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli.h"
#include "mpirun.h"
#include "dacrt/io/exr.h"
#include "same_image.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

const std::string scenes = DACRT_SOURCE_DIR "/scenes";
const std::string options = " --width 24 --height 16 --spp 7 --seed 3 " + every_aov;

}  // namespace

TEST_CASE("mpirun: render on 1, 2, 3 and 9 ranks is one process's render bit for bit") {
  if (!have_mpirun()) {
    MESSAGE("skipped: no mpirun (apt-get install openmpi-bin libopenmpi-dev)");
    return;
  }
  TempDir dir("mpi");
  const std::string scene = scenes + "/cornell-box.gltf";
  const Run one = run(dir, "render " + scene + options + " --quiet -o " + (dir / "one.exr"));
  REQUIRE_MESSAGE(one.code == 0, one.err);
  for (int ranks : {1, 2, 3, 9}) {  // 9 ranks for 7 samples: two ranks render none
    CAPTURE(ranks);
    std::string name = "r";  // (built up: GCC 12 warns falsely on "r" + std::to_string)
    name += std::to_string(ranks) + ".exr";
    const std::string out = dir / name;
    const Run r = run(dir, "render " + scene + options + " -o " + out, mpirun(ranks));
    REQUIRE_MESSAGE(r.code == 0, r.err);
    check_same_image(out, dir / "one.exr");
    const ExrHeader h = read_exr_header(out);
    CHECK(h.attributes.at("sampleRange") == "0:7");
    CHECK(!has_sums(out));
    // One summary, from rank 0.
    size_t summaries = 0;
    for (size_t at = r.err.find(out + ": 24×16"); at != std::string::npos;
         at = r.err.find(out + ": 24×16", at + 1))
      ++summaries;
    CHECK_MESSAGE(summaries == 1, r.err);
  }
  // A part rendered by ranks is the part of one process, and merges.
  const Run part =
      run(dir, "render " + scene + options + " --quiet --samples 2:7 -o " + (dir / "tail.exr"),
          mpirun(2));
  REQUIRE_MESSAGE(part.code == 0, part.err);
  CHECK(has_sums(dir / "tail.exr"));
  REQUIRE(run(dir, "render " + scene + options + " --quiet --samples 0:2 -o " + (dir / "head.exr"))
              .code == 0);
  const Run merged = run(dir, "merge --quiet " + (dir / "head.exr") + " " + (dir / "tail.exr") +
                                  " -o " + (dir / "merged.exr"));
  REQUIRE_MESSAGE(merged.code == 0, merged.err);
  check_same_image(dir / "merged.exr", dir / "one.exr");
}

TEST_CASE("mpirun: a rank that fails fails the job with its message, usage errors once") {
  if (!have_mpirun()) {
    MESSAGE("skipped: no mpirun (apt-get install openmpi-bin libopenmpi-dev)");
    return;
  }
  TempDir dir("mpi-fail");
  const std::string out = dir / "out.exr";
  // Rank 1 runs where the scene's relative path finds nothing (a machine without the file).
  const std::string args = "render cornell-box.gltf" + options + " -o " + out;
  // (run() puts the CLI and `args` after `before`: the second of mpirun's two app contexts.)
  const Run r = run(dir, args,
                    mpirun(1) + " --wdir " + scenes + " " + DACRT_CLI + " " + args +
                        " : -np 1 --wdir " + dir.path().string());
  CHECK(r.code != 0);
  CHECK_MESSAGE(r.err.find("rank 1: dacrt: error: cornell-box.gltf") != std::string::npos, r.err);
  CHECK(!fs::exists(out));
  // A usage error is every rank's: said once, exit 2.
  for (const char* bad : {" --time-limit 5", " --resume", " --frames 0:1", " --backend dacrt,brute"}) {
    CAPTURE(bad);
    const Run u = run(dir, "render " + scenes + "/cornell-box.gltf" + options + bad + " -o " + out,
                      mpirun(2));
    CHECK(u.code == 2);
    CHECK_MESSAGE(lines(u.err) == 1, u.err);
  }
  CHECK(!fs::exists(out));
}

TEST_CASE("mpirun: ranks whose scenes or options differ fail the job, naming the rank and the key") {
  if (!have_mpirun()) {
    MESSAGE("skipped: no mpirun (apt-get install openmpi-bin libopenmpi-dev)");
    return;
  }
  // Two machines' copies of one scene, the second stale: one material colour differs. Each rank
  // runs in its own directory and renders "cornell-box.gltf" there.
  TempDir dir("mpi-agree");
  const std::string original = slurp(scenes + "/cornell-box.gltf");
  std::string stale = original;
  const size_t at = stale.find("0.725");
  REQUIRE(at != std::string::npos);
  stale.replace(at, 5, "0.724");
  for (const auto& [folder, text] : {std::pair{"a", original}, {"b", original}, {"c", stale}}) {
    fs::create_directories(dir / folder);
    std::ofstream(dir / (std::string(folder) + "/cornell-box.gltf"), std::ios::binary) << text;
  }
  const std::string out = dir / "out.exr";
  auto two_ranks = [&](const std::string& second, const std::string& extra) {
    const std::string args = "render cornell-box.gltf" + options + " -o " + out;
    return run(dir, args,
               mpirun(1) + " --wdir " + (dir / "a") + " " + DACRT_CLI + " " + args + extra +
                   " : -np 1 --wdir " + (dir / second));
  };
  // Identical copies in different directories agree: the image of one process.
  const Run same = two_ranks("b", "");
  REQUIRE_MESSAGE(same.code == 0, same.err);
  const Run one = run(dir, "render " + (dir / "a/cornell-box.gltf") + options + " --quiet -o " +
                               (dir / "one.exr"));
  REQUIRE_MESSAGE(one.code == 0, one.err);
  check_same_image(out, dir / "one.exr");
  fs::remove(out);
  // The stale copy: one line naming rank 1 and the inputs' fingerprint, nothing written.
  const Run stale_run = two_ranks("c", "");
  CHECK(stale_run.code == 1);
  CHECK_MESSAGE(lines(stale_run.err) == 1, stale_run.err);
  CHECK_MESSAGE(stale_run.err.find("rank 1: ") == 0, stale_run.err);
  CHECK_MESSAGE(stale_run.err.find("match.inputs is fnv1a64w:") != std::string::npos,
                stale_run.err);
  CHECK(!fs::exists(out));
  // The same files but another option on rank 0 (the seed): the key is named.
  const Run seed = two_ranks("b", " --seed 4");
  CHECK(seed.code == 1);
  CHECK_MESSAGE(seed.err.find("rank 1: ") == 0, seed.err);
  CHECK_MESSAGE(seed.err.find("match.seed is 3 here, 4 on rank 0") != std::string::npos, seed.err);
  CHECK(!fs::exists(out));
}
