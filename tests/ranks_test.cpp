// apps/ranks in one process: how samples are shared among ranks, and that one rank (no launcher)
// leaves films, errors and flags as they are. Over real MPI processes: tests/support/
// mpi_reduce_check.cpp, run by the ctests "mpi: reduce on N ranks".
#include "apps/ranks.h"

#include <doctest/doctest.h>

#include <algorithm>

using namespace dacrt;

TEST_CASE(
    "ranks: the shares of the samples cover the range in rank order, within one of each other") {
  const std::pair<uint32_t, uint32_t> ranges[] = {{0, 0},  {0, 1},     {0, 7},         {3, 5},
                                                  {5, 64}, {10, 1000}, {0, UINT32_MAX}};
  for (const auto& [first, last] : ranges)
    for (int size = 1; size <= 7; ++size) {
      CAPTURE(first);
      CAPTURE(last);
      CAPTURE(size);
      uint32_t at = first, fewest = UINT32_MAX, most = 0;
      for (int rank = 0; rank < size; ++rank) {
        const auto [a, b] = Ranks::share(first, last, rank, size);
        CHECK(a == at);  // contiguous, in rank order
        REQUIRE(b >= a);
        fewest = std::min(fewest, b - a), most = std::max(most, b - a);
        at = b;
      }
      CHECK(at == last);
      CHECK(most - fewest <= 1);
    }
}

TEST_CASE("ranks: without a launcher there is one rank, and the collectives change nothing") {
  int argc = 1;
  char name[] = "dacrt";
  char* args[] = {name, nullptr};
  char** argv = args;
  const Ranks ranks(argc, argv);
  CHECK_FALSE(ranks.mpi());
  CHECK(ranks.size() == 1);
  CHECK(ranks.rank() == 0);
  CHECK(ranks.root());
  CHECK(ranks.share(3, 9) == std::pair<uint32_t, uint32_t>(3, 9));

  Film film(3, 2);
  film.add(4, glm::vec3(1.f, 2.f, 3.f));
  film.set_tallies(5, 6);
  const std::vector<Channel> before = film.channels(true);
  ranks.reduce(film);
  const std::vector<Channel> after = film.channels(true);
  REQUIRE(after.size() == before.size());
  for (size_t c = 0; c < after.size(); ++c) CHECK(after[c].values == before[c].values);
  CHECK(film.total_count() == 1);
  CHECK(film.dropped() == 5);
  CHECK(film.clamped() == 6);

  CHECK(ranks.first_error("").empty());
  CHECK(ranks.first_error("bad") == "bad");  // one rank: no "rank 0: "
  CHECK(ranks.any(true));
  CHECK_FALSE(ranks.any(false));
}
