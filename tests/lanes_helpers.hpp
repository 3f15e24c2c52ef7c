// What the tests of the lock-step searches share (test_lanes.cpp, test_lockstep.cpp).
#pragma once

#include "billiards/dynamics/ensemble.hpp"

#include <catch2/catch.hpp>

#include <cstring>
#include <string>
#include <vector>

/// An ensemble run in lock step with `lockstep` from the states initial(i) equals `simulate`
/// particle by particle (the energies at every record time, bit for bit; collision counts;
/// escapes), on 1, 2 and 3 threads; returns the collisions of the run.
template <class LockstepT, class TableT, class Flight, class Initial>
std::uint64_t check_ensemble_equals_simulate(const LockstepT& lockstep, const TableT& table,
                                             const Flight& flight, const billiards::dynamics::RunOptions& opt,
                                             std::size_t n, const Initial& initial) {
  using namespace billiards;
  const std::size_t m = opt.record_times.size();
  std::vector<double> expected(n * m);
  std::vector<dynamics::ParticleLog> logs(n);
  std::uint64_t collisions = 0;
  for (std::size_t i = 0; i < n; ++i) {
    logs[i] = dynamics::simulate(table, flight, initial(i), opt, &expected[i * m]);
    collisions += logs[i].collisions;
  }
  for (const int threads : {1, 2, 3}) {
    INFO(threads << " threads");
    dynamics::EnsembleResult res;
    res.energies.resize(n * m);
    res.logs.resize(n);
    dynamics::run_in_lockstep(lockstep, table, flight, initial, opt, 0, n, threads, res, {});
    CHECK(std::memcmp(res.energies.data(), expected.data(), n * m * sizeof(double)) == 0);
    for (std::size_t i = 0; i < n; ++i) {
      CHECK(res.logs[i].collisions == logs[i].collisions);
      CHECK(res.logs[i].escaped == logs[i].escaped);
    }
  }
  return collisions;
}

/// The same from microcanonical states.
template <class LockstepT, class TableT, class Flight>
std::uint64_t check_ensemble_equals_simulate(const LockstepT& lockstep, const TableT& table,
                                             const Flight& flight, const billiards::dynamics::RunOptions& opt,
                                             std::size_t n) {
  return check_ensemble_equals_simulate(lockstep, table, flight, opt, n,
                                        billiards::dynamics::microcanonical(table, flight, 1.0, 2021));
}
