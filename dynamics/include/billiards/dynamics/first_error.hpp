// Exceptions out of OpenMP parallel regions.  An exception may not leave a parallel region (nor
// an iteration of a parallel loop): the runtime terminates the program.  Each iteration runs
// through FirstError::run, which catches what it throws; the region's caller rethrows after
// the region, so a failure inside one particle (a field the integrator cannot follow, a root
// search that does not converge) reaches the user as the same clean error as anywhere else.
#pragma once

#include <atomic>
#include <cstddef>
#include <exception>
#include <limits>
#include <mutex>

namespace billiards::dynamics {

/// The exception of the lowest-numbered failed iteration of a parallel loop, kept to be
/// rethrown after it.  Once an iteration has failed, later-numbered ones are skipped (`run`
/// returns at once), lower-numbered ones still run: the error reported is the same for any
/// number of threads.
class FirstError {
 public:
  /// Runs fn() as iteration i, unless an iteration numbered below i has failed.
  template <class Fn>
  void run(std::size_t i, Fn&& fn) noexcept {
    if (i > failed_.load(std::memory_order_relaxed)) return;
    try {
      fn();
    } catch (...) {
      const std::lock_guard lock(mutex_);
      if (i < failed_.load(std::memory_order_relaxed)) {
        error_ = std::current_exception();
        failed_.store(i, std::memory_order_relaxed);
      }
    }
  }
  /// Has any iteration failed (a loop that is not split by index stops early on it)?
  bool failed() const { return failed_.load(std::memory_order_relaxed) != none; }
  /// After the region: rethrows the kept exception, if any.
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  static constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
  std::atomic<std::size_t> failed_{none};
  std::mutex mutex_;
  std::exception_ptr error_;
};

}  // namespace billiards::dynamics
