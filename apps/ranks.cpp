#include "apps/ranks.h"

#include <algorithm>
#include <climits>
#include <cstdlib>

#ifdef DACRT_HAVE_MPI
#include <mpi.h>

#include <array>
#include <cstring>

#include "dacrt/util/error.h"
#endif

namespace dacrt {

std::pair<uint32_t, uint32_t> Ranks::share(uint32_t first, uint32_t last, int rank, int size) {
  const uint64_t n = last > first ? last - first : 0, r = uint64_t(rank), k = uint64_t(size);
  // The first n % k ranks take one sample more than the others.
  const uint64_t base = n / k, extra = n % k;
  const uint64_t begin = first + r * base + std::min(r, extra);
  return {uint32_t(begin), uint32_t(begin + base + (r < extra))};
}

#ifndef DACRT_HAVE_MPI

Ranks::Ranks(int&, char**&) {}
Ranks::~Ranks() = default;
void Ranks::reduce(Film&, size_t) const {}
std::string Ranks::first_error(const std::string& mine) const {
  return mine;
}
bool Ranks::any(bool mine) const {
  return mine;
}
std::string Ranks::broadcast(const std::string& text) const {
  return text;
}

#else

namespace {

// Whether a launcher started this process: OpenMPI's mpirun, or a PMIx or PMI (Hydra, Slurm) one.
bool launched() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

// MPI_User_function: inout[i] += in[i] for 128-bit fixed-point sums, added as unsigned words (the
// two's complement bits of the signed sum, without signed overflow's undefined behaviour). Read
// and written with memcpy: MPI's temporary buffers need not be 16-byte aligned.
static_assert(sizeof(Fixed) == 16);
void add_fixed(void* in, void* inout, int* len, MPI_Datatype*) {
  __extension__ using Word = unsigned __int128;
  const auto* from = static_cast<const unsigned char*>(in);
  auto* to = static_cast<unsigned char*>(inout);
  for (int i = 0; i < *len; ++i, from += sizeof(Word), to += sizeof(Word)) {
    Word a, b;
    std::memcpy(&a, from, sizeof(Word));
    std::memcpy(&b, to, sizeof(Word));
    b += a;
    std::memcpy(to, &b, sizeof(Word));
  }
}

// The 16-byte type and the commutative sum reduce() sends the fixed-point arrays with, freed
// when the reduction ends.
struct FixedSum {
  MPI_Datatype type;
  MPI_Op op;
  FixedSum() {
    MPI_Type_contiguous(2, MPI_UINT64_T, &type);
    MPI_Type_commit(&type);
    MPI_Op_create(add_fixed, /*commute=*/1, &op);
  }
  ~FixedSum() {
    MPI_Op_free(&op);
    MPI_Type_free(&type);
  }
  FixedSum(const FixedSum&) = delete;
  FixedSum& operator=(const FixedSum&) = delete;
};

// Adds n elements at `data` over the ranks into rank 0's, `chunk` elements per MPI_Reduce.
template <class T>
void reduce_array(T* data, size_t n, MPI_Datatype type, MPI_Op op, size_t chunk, bool root) {
  for (size_t at = 0; at < n; at += chunk) {
    const int count = int(std::min(chunk, n - at));
    MPI_Reduce(root ? MPI_IN_PLACE : data + at, root ? data + at : nullptr, count, type, op, 0,
               MPI_COMM_WORLD);
  }
}

}  // namespace

Ranks::Ranks(int& argc, char**& argv) {
  if (!launched()) return;
  // Funneled: the render's worker threads never call MPI, only the thread that made the Ranks.
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  mpi_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

Ranks::~Ranks() {
  if (mpi_) MPI_Finalize();
}

void Ranks::reduce(Film& film, size_t chunk) const {
  if (!mpi_ || size_ == 1) return;
  const size_t per_pixel = size_t(film.sums_per_pixel());
  const size_t counts_per_pixel = size_t(film.counts_per_pixel());
  // Every rank must send arrays of the same lengths, or the reduction would mix up pixels or
  // wait forever: first the films' shapes, their largest and (as the largest of the bitwise
  // complements) smallest values over the ranks, so that all ranks agree and all throw.
  const size_t count_size = counts_per_pixel * film.pixels();
  constexpr int fields = 6;
  const std::array<uint64_t, fields> shape = {uint64_t(film.width()),
                                              uint64_t(film.height()),
                                              uint64_t(film.sums_per_pixel()),
                                              counts_per_pixel,
                                              per_pixel * film.pixels(),
                                              count_size};
  std::array<uint64_t, 2 * fields> most;
  for (int i = 0; i < fields; ++i) most[i] = shape[i], most[fields + i] = ~shape[i];
  MPI_Allreduce(MPI_IN_PLACE, most.data(), 2 * fields, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD);
  for (int i = 0; i < fields; ++i)
    if (most[i] != ~most[fields + i])
      throw Error("the ranks' films differ in size or outputs (" + std::to_string(~most[fields]) +
                  " x " + std::to_string(~most[fields + 1]) + " to " + std::to_string(most[0]) +
                  " x " + std::to_string(most[1]) + ")");

  chunk = std::clamp<size_t>(chunk, 1, INT_MAX);
  const FixedSum fixed;
  // The sums as 128-bit words (the film keeps some in 96 bits) and the counts as 32-bit ones
  // (the film keeps them packed), a chunk of pixels at a time. Rank 0 sets the reduced sums and
  // counts back; one that does not fit (more samples than a film can hold) throws there, after
  // every rank took part in every reduction.
  const size_t pixels_per_chunk = std::max<size_t>(1, chunk / per_pixel);
  std::vector<Fixed> sums(std::min(pixels_per_chunk, film.pixels()) * per_pixel);
  std::vector<uint32_t> pixel_counts(std::min(pixels_per_chunk, film.pixels()) * counts_per_pixel);
  size_t wrapped = film.pixels(), full = film.pixels();
  for (size_t first = 0; first < film.pixels(); first += pixels_per_chunk) {
    const size_t n = std::min(pixels_per_chunk, film.pixels() - first);
    for (size_t p = 0; p < n; ++p) {
      film.pixel_sums(first + p, &sums[per_pixel * p]);
      for (size_t i = 0; i < counts_per_pixel; ++i)
        pixel_counts[counts_per_pixel * p + i] = film.count_value(first + p, int(i));
    }
    reduce_array(sums.data(), n * per_pixel, fixed.type, fixed.op, chunk, root());
    reduce_array(pixel_counts.data(), n * counts_per_pixel, MPI_UINT32_T, MPI_SUM, chunk, root());
    if (root())
      for (size_t p = 0; p < n; ++p) {
        for (size_t k = 0; k < per_pixel; ++k)
          if (!film.set_sum(first + p, int(k), sums[per_pixel * p + k])) wrapped = first + p;
        if (!film.set_counts(first + p, &pixel_counts[counts_per_pixel * p])) full = first + p;
      }
  }
  uint64_t tallies[2] = {film.dropped(), film.clamped()};
  reduce_array(tallies, 2, MPI_UINT64_T, MPI_SUM, chunk, root());
  if (root()) film.set_tallies(tallies[0], tallies[1]);
  if (full != film.pixels())
    throw Error("the ranks' films count more than " + std::to_string(Film::count_limit) +
                " samples at pixel " + std::to_string(full));
  if (wrapped != film.pixels())
    throw Error("the ranks' films add up to more albedo or normal at pixel " +
                std::to_string(wrapped) + " than " + std::to_string(max_samples) +
                " samples can");
}

std::string Ranks::first_error(const std::string& mine) const {
  if (!mpi_ || size_ == 1) return mine;
  int failing = mine.empty() ? size_ : rank_;
  MPI_Allreduce(MPI_IN_PLACE, &failing, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (failing == size_) return "";
  // The failing rank's message, cut to a length any count can hold.
  std::string message = rank_ == failing ? mine.substr(0, 1 << 16) : "";
  int length = int(message.size());
  MPI_Bcast(&length, 1, MPI_INT, failing, MPI_COMM_WORLD);
  message.resize(size_t(length));
  MPI_Bcast(message.data(), length, MPI_CHAR, failing, MPI_COMM_WORLD);
  return "rank " + std::to_string(failing) + ": " + message;
}

bool Ranks::any(bool mine) const {
  if (!mpi_ || size_ == 1) return mine;
  int flag = mine;
  MPI_Allreduce(MPI_IN_PLACE, &flag, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
  return flag != 0;
}

std::string Ranks::broadcast(const std::string& text) const {
  if (!mpi_ || size_ == 1) return text;
  uint64_t length = root() ? text.size() : 0;
  MPI_Bcast(&length, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  std::string out = root() ? text : std::string(size_t(length), '\0');
  // In pieces whose count an int holds.
  for (uint64_t at = 0; at < length; at += INT_MAX)
    MPI_Bcast(out.data() + at, int(std::min<uint64_t>(INT_MAX, length - at)), MPI_CHAR, 0,
              MPI_COMM_WORLD);
  return out;
}

#endif

}  // namespace dacrt
