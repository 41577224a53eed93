// mpi_reduce_check: apps/ranks over real MPI processes, run by the ctests "mpi: reduce on N
// ranks" as `mpirun -np N mpi-reduce-check`. Each rank renders its share of the samples of
// lit_scene with every AOV, Ranks::reduce adds the films into rank 0's, and rank 0 compares the
// result bit for bit (sums, counts, tallies, channels) with one process rendering every sample:
// for shares of 7 samples and of 2 (a rank without samples when N > 2), in one MPI_Reduce per
// array and in chunks of 7 elements. Then films of different sizes (every rank throws),
// first_error and any. Exit 0 when every check held on every rank, else 1 (each failure printed
// by the rank that saw it).
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "apps/ranks.h"
#include "lit_scene.h"
#include "dacrt/util/error.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

int failures = 0;

void check(const Ranks& ranks, bool ok, const std::string& what) {
  if (ok) return;
  ++failures;
  std::fprintf(stderr, "rank %d of %d: %s\n", ranks.rank(), ranks.size(), what.c_str());
}

// A film's whole state, exactly: the fixed-point sums, the counts, the tallies.
struct State {
  std::vector<Fixed> sums;
  std::vector<uint32_t> counts;
  uint64_t dropped, clamped;
  bool operator==(const State&) const = default;
};
State state(Film& film) {
  State s{film.sums(), {}, film.dropped(), film.clamped()};
  for (size_t p = 0; p < film.pixels(); ++p)
    for (int i = 0; i < film.counts_per_pixel(); ++i) s.counts.push_back(film.count_value(p, i));
  return s;
}

bool same_channels(const Film& a, const Film& b) {
  const std::vector<Channel> x = a.channels(), y = b.channels();
  if (x.size() != y.size()) return false;
  for (size_t c = 0; c < x.size(); ++c)
    if (x[c].name != y[c].name || x[c].values.size() != y[c].values.size() ||
        std::memcmp(x[c].values.data(), y[c].values.data(), x[c].values.size() * sizeof(float)))
      return false;
  return true;
}

// Every rank renders its share of [0, spp), reduced in chunks of `chunk`; rank 0 against one
// render of all of them.
void check_reduce(const Ranks& ranks, uint32_t spp, size_t chunk) {
  const Scene scene = lit_scene();
  RenderSettings s = lit_settings();
  s.width = 24, s.height = 16, s.spp = int(spp), s.seed = 2;
  s.aovs = AovSet::parse("albedo,normal,depth,position,variance,samples");
  auto backend = Backend::create("dacrt", scene.geometry);
  RenderJob job(scene, *backend, s);
  Progress quiet("test", 1, false);
  Film part = job.film();
  const auto [first, last] = ranks.share(0, spp);
  job.run(part, first, last, quiet);
  // Tallies as the dropped (not finite) and clamped samples of a render would leave them.
  part.set_tallies(uint64_t(ranks.rank()) + 1, uint64_t(10 * ranks.rank()) + 3);
  ranks.reduce(part, chunk);
  if (!ranks.root()) return;
  Film whole = job.film();
  job.run(whole, 0, spp, quiet);
  const uint64_t r = uint64_t(ranks.size());
  whole.set_tallies(r * (r + 1) / 2, 10 * r * (r - 1) / 2 + 3 * r);
  const std::string what = std::to_string(spp) + " samples in chunks of " + std::to_string(chunk);
  check(ranks, part.total_count() == uint64_t(spp) * part.pixels(), what + ": every sample once");
  check(ranks, state(part) == state(whole), what + ": the reduced film's state is not the whole's");
  check(ranks, same_channels(part, whole), what + ": the reduced film's channels differ");
}

// One rank's film a pixel wider than the others': every rank throws, none waits forever.
void check_mismatch(const Ranks& ranks) {
  Film film(ranks.rank() == ranks.size() - 1 ? 5 : 4, 4);
  bool threw = false;
  try {
    ranks.reduce(film);
  } catch (const Error& e) {
    threw = std::string(e.what()).find("differ") != std::string::npos;
  }
  check(ranks, threw, "films of different sizes: no error");
}

void check_first_error(const Ranks& ranks) {
  const int last = ranks.size() - 1;
  const std::string mine = "broke at " + std::to_string(ranks.rank());
  check(ranks, ranks.first_error("").empty(), "no rank failed, yet an error");
  check(ranks, ranks.first_error(ranks.rank() == 1 ? mine : "") == "rank 1: broke at 1",
        "rank 1 failed: not its message");
  check(ranks,
        ranks.first_error(ranks.rank() == last ? mine : "") ==
            "rank " + std::to_string(last) + ": broke at " + std::to_string(last),
        "the last rank failed: not its message");
  check(ranks, ranks.first_error(mine) == "rank 0: broke at 0",
        "every rank failed: not the lowest one's message");
  check(ranks, ranks.first_error(ranks.rank() > 0 ? mine : "") == "rank 1: broke at 1",
        "every rank but 0 failed: not rank 1's message");
}

void check_any(const Ranks& ranks) {
  check(ranks, !ranks.any(false), "any of none");
  check(ranks, ranks.any(ranks.rank() == ranks.size() - 1), "any of the last rank");
  check(ranks, ranks.any(ranks.root()), "any of rank 0");
  check(ranks, ranks.any(true), "any of all");
}

}  // namespace

int main(int argc, char** argv) {
  Ranks ranks(argc, argv);
  if (!ranks.mpi() || ranks.size() < 2) {
    if (ranks.root()) std::fprintf(stderr, "mpi-reduce-check: run it with mpirun -np 2 or more\n");
    return 1;
  }
  for (uint32_t spp : {7u, 2u})
    for (size_t chunk : {Ranks::reduce_chunk, size_t(7)}) check_reduce(ranks, spp, chunk);
  check_mismatch(ranks);
  check_first_error(ranks);
  check_any(ranks);
  const bool failed = ranks.any(failures > 0);
  if (ranks.root())
    std::printf("mpi-reduce-check on %d ranks: %s\n", ranks.size(), failed ? "FAILED" : "ok");
  return failed ? 1 : 0;
}
