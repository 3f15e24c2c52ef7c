// The cost of records in the collision loop: energies recorded at every time unit against at
// the end only, one thread, alternated rounds; collisions per second of run_ensemble alone (no
// output, no statistics), medians.  The paper's driven clover (F = 10 along (1,1)/√2, ω = 40π)
// with each flight's midpoint checked, and free flights in the clover, the stadium and the
// Sinai table without, each as `billiard run` runs it.
// Usage: bench_records [particles=2000] [time=500] [rounds=5] [free_time=4000]
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/geometry.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

using namespace billiards;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Collisions per second of n particles from `initial`, recorded at every time unit up to T
/// against at the end only, `rounds` alternated rounds: the medians.
template <class TableT, class Flight, class Initial>
void print_cost(const char* name, const TableT& table, const Flight& flight, const Initial& initial, bool verify,
                std::size_t n, double T, int rounds) {
  auto rate = [&](bool every) {
    dynamics::RunOptions opt;
    opt.verify_every_flight = verify;
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
  fmt::print("{}, {} particles, t = 0..{}: records every time unit {:.3g} collisions/s; at the end only {:.3g}; "
             "cost of the records {:.3f}x\n",
             name, n, T, e, f, f / e);
}

dynamics::Table table_of(const char* shape) {
  return dynamics::Table(geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + shape + ".yaml").region);
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::size_t(std::atol(argv[1])) : 2000;
  const double T = argc > 2 ? std::atof(argv[2]) : 500;
  const int rounds = argc > 3 ? std::atoi(argv[3]) : 5;
  const double T_free = argc > 4 ? std::atof(argv[4]) : 4000;
  fmt::print("one thread, medians of {} rounds\n", rounds);
  const dynamics::Table clover = table_of("clover");
  const dynamics::PeriodicDriveFlight drive{10 / std::sqrt(2.0) * dynamics::Vec2(1, 1), 40 * geometry::pi, 0};
  print_cost("driven clover, every flight checked", clover, drive, dynamics::microcanonical(clover, drive, 1.0, 1), true,
             n, T, rounds);
  for (const char* shape : {"clover", "stadium", "sinai"}) {
    const dynamics::Table table = table_of(shape);
    const dynamics::FreeFlight free;
    print_cost(shape, table, free, dynamics::microcanonical(table, free, 1.0, 1), false, n, T_free, rounds);
  }
}
