// Ranks: the processes of one render under an MPI launcher (`mpirun -np R dacrt render …`), or
// the one process without it. Each rank renders a contiguous share of the sample indices into
// its own film; reduce() adds the films into rank 0's with MPI_Reduce. The film's sums are exact
// integers (film/fixed.h), so the reduced film is bit for bit the film of one process rendering
// every sample, for any number of ranks and any reduction tree MPI picks. Built without MPI
// (DACRT_HAVE_MPI undefined) there is always one rank and the collectives do nothing.
//
// Every collective (reduce, first_error, any) must be called by every rank, in the same order,
// from the thread that made the Ranks.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

#include "dacrt/film/film.h"
#include "dacrt/render/session.h"

namespace dacrt {

class Ranks : public RankGroup {
 public:
  // MPI_Init when a launcher started the process (OpenMPI sets OMPI_COMM_WORLD_SIZE, PMIx and
  // Hydra PMIX_RANK or PMI_SIZE), else one rank without MPI: a plain `dacrt render` never
  // starts MPI, which as a singleton would spawn a daemon and look for networks.
  Ranks(int& argc, char**& argv);
  ~Ranks();  // MPI_Finalize
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;

  int rank() const { return rank_; }
  int size() const override { return size_; }
  bool root() const override { return rank_ == 0; }
  bool mpi() const { return mpi_; }  // MPI is in use (size may still be 1)

  // This rank's share of the samples [first, last): contiguous, in rank order, sizes differing by
  // at most one, covering the range exactly (a share is empty when there are more ranks than
  // samples).
  std::pair<uint32_t, uint32_t> share(uint32_t first, uint32_t last) const override {
    return share(first, last, rank_, size_);
  }
  static std::pair<uint32_t, uint32_t> share(uint32_t first, uint32_t last, int rank, int size);

  // Collective. Adds every rank's film into rank 0's: sums, counts, dropped and clamped tallies
  // (the other ranks' films are left as they were). Throws Error on every rank when the films
  // differ in size or outputs. `chunk`: the most elements of an array sent in one MPI_Reduce,
  // which bounds the buffers MPI allocates for the incoming data (a 1080p film with every AOV
  // is ~600 MB) and keeps every count far below INT_MAX.
  static constexpr size_t reduce_chunk = size_t(1) << 20;
  void reduce(Film& film, size_t chunk) const;
  void reduce(Film& film) const override { reduce(film, reduce_chunk); }

  // Collective. Each rank passes "" or its error; each gets back "" when none failed, else the
  // message of the lowest failing rank, prefixed "rank N: " when size() > 1.
  std::string first_error(const std::string& mine) const override;

  // Collective: whether any rank's flag is true (a stop signal seen on one rank, say).
  bool any(bool mine) const override;

  // Collective: rank 0's `text` on every rank (the others' `text` is not read).
  std::string broadcast(const std::string& text) const override;

 private:
  int rank_ = 0, size_ = 1;
  bool mpi_ = false;
};

}  // namespace dacrt
