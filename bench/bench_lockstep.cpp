// The lock-step search alone: driven clover collisions found sixteen at a time
// (LockstepTable::collisions: packing, the kernel, the hits' states, hand-backs) for each SIMD
// target this processor runs (BILLIARDS_SIMD set: that one only) against the scalar
// `collision` on the same states, in the same process.  The states are recorded along
// real trajectories first (an ensemble's flights as `billiard run` meets them, with its horizon),
// so that only the search is timed, not the rest of a run.  Every hit is checked bit for bit
// against the scalar one before timing.
// Usage: bench_lockstep [batches per frequency, default 20000] [repeats, default 5]
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/lockstep.hpp"
#include "billiards/geometry.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using namespace billiards;
using dynamics::DrivenState;
using dynamics::FlightHit;
using dynamics::PeriodicDriveFlight;
using dynamics::Vec2;

namespace {

constexpr int lanes = dynamics::lockstep::lanes;

/// A flight to search: the state after a bounce (or a start) and the end of its search.
struct Flight {
  DrivenState state;
  double t_end;
};

/// `batches`·lanes flights along trajectories of the scene's ensemble (E0 = 1/2, record times
/// 0, 1, ..., 1000 as the benchmark command of BENCHMARKS.md has them), particle after particle.
std::vector<Flight> record(const dynamics::Table& table, const PeriodicDriveFlight& flight, std::size_t count) {
  dynamics::RunOptions opt;
  for (int k = 0; k <= 1000; ++k) opt.record_times.push_back(k);
  std::vector<double> energies(opt.record_times.size());
  const auto initial = dynamics::microcanonical(table, flight, 1.0, 1);
  const dynamics::RecordMarks<PeriodicDriveFlight> marks(flight, opt.record_times);
  std::vector<Flight> flights;
  for (std::size_t particle = 0; flights.size() < count; ++particle) {
    dynamics::Trajectory<PeriodicDriveFlight> run(table, flight, initial(particle), opt, marks, energies.data());
    while (flights.size() < count && !run.done()) {
      flights.push_back({run.state(), run.horizon()});
      if (!run.step()) break;
    }
  }
  return flights;
}

bool same(const FlightHit<PeriodicDriveFlight>& a, const FlightHit<PeriodicDriveFlight>& b) {
  auto bits = [](const auto& x, const auto& y) { return std::memcmp(&x, &y, sizeof x) == 0; };
  return a.wall == b.wall && bits(a.t, b.t) && bits(a.point, b.point) && bits(a.normal, b.normal) &&
         bits(a.state.x, b.state.x) && bits(a.state.v, b.state.v) && bits(a.state.phase, b.state.phase) &&
         bits(a.state.sin_phase, b.state.sin_phase) && bits(a.state.cos_phase, b.state.cos_phase);
}

/// Best time of `repeats` passes of fn over all batches, in ns per collision.
template <class Fn>
double best_ns(std::size_t collisions, int repeats, Fn fn) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best / double(collisions) * 1e9;
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t batches = argc > 1 ? std::size_t(std::atof(argv[1])) : 20000;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
  const dynamics::Table table(shape.region);
  std::vector<dynamics::simd::Target> targets;
  if (const char* env = std::getenv("BILLIARDS_SIMD"); env && std::string(env) != "auto")
    targets.push_back({env, dynamics::simd::target_for(env), false});
  else
    for (const auto& t : dynamics::simd::runnable_targets())
      if (!(t.bit & dynamics::simd::generic)) targets.push_back(t);
  fmt::print("driven clover, {} batches of {} flights per frequency, best of {}; ns per collision (M/s)\n", batches,
             lanes, repeats);
  fmt::print("{:>8} {:>16}", "omega", "scalar");
  for (const auto& t : targets) fmt::print(" {:>16} {:>6}", t.name, "ratio");
  fmt::print("\n");
  for (const double w : {10.0, 40.0, 320.0, 2560.0}) {
    const PeriodicDriveFlight flight{10 / std::sqrt(2.0) * Vec2(1, 1), w * geometry::pi, 0};
    const auto flights = record(table, flight, batches * lanes);
    // Hits go to a batch's worth of storage, as in an ensemble (all of them at once would be
    // 50 MB of writes that the search never makes); their times are summed so that none is
    // optimized away.
    FlightHit<PeriodicDriveFlight> scalar[lanes], lock[lanes];
    double sum = 0;
    auto batch = [&](std::size_t b, auto search) {
      const DrivenState* states[lanes];
      double t_end[lanes];
      for (int i = 0; i < lanes; ++i) states[i] = &flights[b + i].state, t_end[i] = flights[b + i].t_end;
      search(states, t_end);
    };
    auto all = [&](auto search) {
      return [&, search] {
        for (std::size_t b = 0; b < flights.size(); b += lanes) batch(b, search);
      };
    };
    auto search_scalar = [&](const DrivenState* const* states, const double* t_end) {
      for (int i = 0; i < lanes; ++i) sum += (scalar[i] = dynamics::collision(table, flight, *states[i], t_end[i])).t;
    };
    const double ns_scalar = best_ns(flights.size(), repeats, all(search_scalar));
    fmt::print("{:>6}pi {:>8.1f} ({:>5.2f})", w, ns_scalar, 1e3 / ns_scalar);
    for (const auto& target : targets) {
      const dynamics::LockstepTable lockstep(table, flight, dynamics::lockstep::kernel_of(target.bit));
      auto search_lockstep = [&](const DrivenState* const* states, const double* t_end) {
        lockstep.collisions(states, t_end, lanes, lock);
        for (int i = 0; i < lanes; ++i) sum += lock[i].t;
      };
      std::size_t differ = 0;
      for (std::size_t b = 0; b < flights.size(); b += lanes) {
        batch(b, search_scalar);
        batch(b, search_lockstep);
        for (int i = 0; i < lanes; ++i) differ += !same(lock[i], scalar[i]);
      }
      if (differ) {
        fmt::print("\nomega {}pi, {}: {} hits differ from the scalar search\n", w, target.name, differ);
        return 1;
      }
      const double ns_lock = best_ns(flights.size(), repeats, all(search_lockstep));
      fmt::print(" {:>8.1f} ({:>5.2f}) {:>5.2f}x", ns_lock, 1e3 / ns_lock, ns_scalar / ns_lock);
    }
    if (!(sum > 0)) return 1;
    fmt::print("\n");
  }
}
