// Ensembles of independent particles for the phase-space diagnostics (boundary map, sections,
// Lyapunov exponents): each particle's result is computed from its index alone (its initial
// state is `initial(i)`, one random stream per particle) and stored at that index, so the
// results are bit-identical for any number of threads, as for `billiard run`.
#pragma once

#include "billiards/dynamics/first_error.hpp"

#include <omp.h>

#include <atomic>
#include <cstddef>
#include <functional>
#include <vector>

namespace billiards::analysis {

/// results[i] = work(i) for i in [0, n), on `threads` threads (0: all); `progress(done)` is
/// called from one thread now and then.  An exception thrown by work(i) is rethrown after the
/// loop (the lowest i's).
template <class Work>
auto for_each_particle(std::size_t n, int threads, Work&& work,
                       const std::function<void(std::size_t)>& progress = {}) {
  std::vector<decltype(work(std::size_t(0)))> results(n);
  std::atomic<std::size_t> done{0};
  if (threads <= 0) threads = omp_get_max_threads();
  dynamics::FirstError error;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) {
    error.run(std::size_t(i), [&] {
      results[std::size_t(i)] = work(std::size_t(i));
      const std::size_t d = ++done;
      if (progress && omp_get_thread_num() == 0) progress(d);
    });
  }
  error.rethrow();
  if (progress) progress(n);
  return results;
}

/// The rows of every particle, particle 0 first: the layout of the .npy and CSV outputs.
inline std::vector<double> concatenate(const std::vector<std::vector<double>>& parts) {
  std::size_t size = 0;
  for (const auto& p : parts) size += p.size();
  std::vector<double> all;
  all.reserve(size);
  for (const auto& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}

}  // namespace billiards::analysis
