// The cost of records in the collision loop: the paper's driven clover (F = 10 along (1,1)/√2,
// ω = 40π) with its energies recorded at every time unit against at the end only, each
// flight's midpoint checked as `billiard run` checks it, one thread, alternated rounds;
// collisions per second of run_ensemble alone (no output, no statistics), medians.
// Usage: bench_records [particles=2000] [time=500] [rounds=5]
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/geometry.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <vector>

using namespace billiards;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::size_t(std::atol(argv[1])) : 2000;
  const double T = argc > 2 ? std::atof(argv[2]) : 500;
  const int rounds = argc > 3 ? std::atoi(argv[3]) : 5;
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
  const dynamics::Table table(shape.region);
  const dynamics::PeriodicDriveFlight flight{10 / std::sqrt(2.0) * dynamics::Vec2(1, 1), 40 * geometry::pi, 0};
  const auto initial = dynamics::microcanonical(table, flight, 1.0, 1);
  auto rate = [&](bool every) {
    dynamics::RunOptions opt;
    opt.verify_every_flight = true;
    opt.record_times = {0};
    for (double t = 1; every && t < T; ++t) opt.record_times.push_back(t);
    opt.record_times.push_back(T);
    const auto start = std::chrono::steady_clock::now();
    const auto res = dynamics::run_ensemble(table, flight, initial, opt, n, 1);
    return double(res.collisions()) / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  rate(true);  // (warm-up)
  std::vector<double> every, end;
  for (int r = 0; r < rounds; ++r) {
    every.push_back(rate(true));
    end.push_back(rate(false));
  }
  const double e = median(every), f = median(end);
  fmt::print("driven clover, {} particles, t = 0..{}, 1 thread, medians of {} rounds\n", n, T, rounds);
  fmt::print("records every time unit: {:.3g} collisions/s; at the end only: {:.3g}; cost of the records {:.3f}x\n",
             e, f, f / e);
}
