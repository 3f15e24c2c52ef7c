// The processes of a run: one, or the ranks of an MPI job (`mpirun -np K billiard run ...`).
// Particles are independent and each depends on (seed, index) only, so ranks split the chunks
// of particles among themselves and combine the results bit for bit: every entry of the result
// is written by exactly one rank, and the others hold zero bytes there, so a bitwise OR is
// exact and independent of the order of the reduction.
#pragma once

#include <cstddef>

namespace billiards::cli {

class Ranks {
 public:
  /// Joins the MPI job if the program was started by an MPI launcher and built with MPI;
  /// otherwise a single process.  (A plain `billiard` run never initializes MPI, which would
  /// start a daemon.)
  Ranks(int& argc, char**& argv);
  ~Ranks();
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }

  /// True on every rank if `flag` is true on any.
  bool any(bool flag) const;
  /// Bitwise OR of `bytes` over all ranks, on every rank.
  void combine(void* bytes, std::size_t count) const;
  void barrier() const;
  /// On the way out with an error: waits up to `seconds` for every rank to come here too (a bad
  /// input fails them all at once), and says whether they did.  Nonblocking, so that a rank
  /// failing alone, the others still at work, is not held forever.
  bool fail_together(double seconds) const;
  /// Ends the whole job with `status` (a rank that failed alone).
  [[noreturn]] void abort(int status) const;

 private:
  int rank_ = 0, size_ = 1;
  bool mpi_ = false;
};

/// The processes of this program (set up in main).
const Ranks& ranks();

}  // namespace billiards::cli
