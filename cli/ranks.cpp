#include "ranks.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <thread>

#ifdef BILLIARDS_MPI
#include <mpi.h>
#endif

namespace billiards::cli {

namespace {
const Ranks* the_ranks = nullptr;

/// Set by Open MPI's and MPICH's (PMI) launchers in every process they start.
bool started_by_mpi_launcher() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(var)) return true;
  return false;
}
}  // namespace

Ranks::Ranks(int& argc, char**& argv) {
#ifdef BILLIARDS_MPI
  if (started_by_mpi_launcher()) {
    int provided = 0;
    // OpenMP threads run particles; only the main thread calls MPI.
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    mpi_ = true;
  }
#else
  // Every process would run the whole job and write the same files.
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (size && std::atoi(size) > 1)
    throw std::runtime_error("this billiard was built without MPI (no libopenmpi-dev at build time); run it without mpirun");
  (void)argc;
  (void)argv;
#endif
  the_ranks = this;
}

Ranks::~Ranks() {
#ifdef BILLIARDS_MPI
  if (mpi_) MPI_Finalize();
#endif
  the_ranks = nullptr;
}

bool Ranks::any(bool flag) const {
#ifdef BILLIARDS_MPI
  if (mpi_) {
    int local = flag, global = 0;
    MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
    return global != 0;
  }
#endif
  return flag;
}

void Ranks::combine(void* bytes, std::size_t count) const {
#ifdef BILLIARDS_MPI
  if (mpi_) {
    auto* p = static_cast<unsigned char*>(bytes);
    constexpr std::size_t block = std::numeric_limits<int>::max() / 2;  // MPI counts are int
    for (std::size_t done = 0; done < count; done += block)
      MPI_Allreduce(MPI_IN_PLACE, p + done, int(std::min(block, count - done)), MPI_BYTE, MPI_BOR, MPI_COMM_WORLD);
  }
#else
  (void)bytes;
  (void)count;
#endif
}

void Ranks::barrier() const {
#ifdef BILLIARDS_MPI
  if (mpi_) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

bool Ranks::fail_together(double seconds) const {
#ifdef BILLIARDS_MPI
  if (mpi_) {
    MPI_Request request;
    MPI_Ibarrier(MPI_COMM_WORLD, &request);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    for (int done = 0;;) {
      MPI_Test(&request, &done, MPI_STATUS_IGNORE);
      if (done) return true;
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
#else
  (void)seconds;
#endif
  return true;
}

void Ranks::abort(int status) const {
#ifdef BILLIARDS_MPI
  if (mpi_) MPI_Abort(MPI_COMM_WORLD, status);
#endif
  std::_Exit(status);
}

const Ranks& ranks() {
  if (!the_ranks) throw std::logic_error("ranks() before main set them up");
  return *the_ranks;
}

}  // namespace billiards::cli
