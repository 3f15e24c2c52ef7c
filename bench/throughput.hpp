// Collisions per second of an ensemble on one thread, the code path of `billiard run`.
#pragma once

#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry.hpp"

#include <chrono>
#include <cstdint>
#include <utility>

namespace bench {

/// Collisions per second on one thread (64 particles, interleaved as in ensembles) over about
/// `collisions` collisions, and the escapes; a 2-D or 3-D region (the flight's dimension).
template <class Region, class Flight>
std::pair<double, std::uint64_t> throughput(const Region& region, const Flight& flight, double collisions) {
  using namespace billiards;
  const dynamics::BasicTable<double, Flight::State::dimension> table(region);
  dynamics::RunOptions opt;
  const std::size_t particles = 64;
  // At speed 1 a particle meets a wall every λ on average (in a magnetic field too: Santaló).
  opt.record_times = {collisions / double(particles) * geometry::mean_free_path(measures_of(region))};
  const auto initial = dynamics::microcanonical(table, flight, 1.0, 1);
  const auto start = std::chrono::steady_clock::now();
  const auto res = dynamics::run_ensemble(table, flight, initial, opt, particles, 1);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {double(res.collisions()) / seconds, res.escapes()};
}

}  // namespace bench
