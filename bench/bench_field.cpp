// Flights in general fields (FieldFlight) beside the closed-form flights, one thread:
//  1. a weak harmonic bowl U = k|x|²/2 (k = 0.1) in the stadium, F = 0: collisions/s and the
//     energy error |E(T) − E(0)| against the integrator's tolerance, beside the free stadium;
//  2. the paper's uniform drive in the clover (F = 10 along (1,1)/√2) through FieldFlight and
//     through the closed-form PeriodicDriveFlight, same initial conditions: collisions/s and
//     their ratio, at ω = 40π and 320π.
// Usage: bench_field [particles=200] [time=50]
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/field_flight.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/geometry.hpp"

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <cstdlib>

using namespace billiards;
using dynamics::Vec2;

namespace {

struct Timing {
  double collisions_per_second;
  dynamics::EnsembleResult result;
};

template <class Flight, class Initial>
Timing time_run(const dynamics::Table& table, const Flight& flight, const Initial& initial, std::size_t n, double T) {
  dynamics::RunOptions opt;
  opt.record_times = {0, T};
  const auto start = std::chrono::steady_clock::now();
  auto res = dynamics::run_ensemble(table, flight, initial, opt, n, 1);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (res.escapes()) fmt::print("  WARNING: {} escapes\n", res.escapes());
  return {double(res.collisions()) / s, std::move(res)};
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::size_t(std::atol(argv[1])) : 200;
  const double T = argc > 2 ? std::atof(argv[2]) : 50;

  {
    const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/stadium.yaml");
    const dynamics::Table table(shape.region);
    Expressions params;
    params.define("k", "0.1", "bench", 1);
    dynamics::Potential bowl;
    bowl.U = CoordinateFunction("0.5*k*(x^2 + y^2)", params, "bench", 1);
    bowl.gradient = {bowl.U.derivative(0), bowl.U.derivative(1)};
    const dynamics::FreeFlight free;
    const auto reference = time_run(table, free, dynamics::microcanonical(table, free, 1.0, 1), n, T);
    fmt::print("harmonic bowl (k = 0.1) in the stadium, F = 0, E = 1/2, {} particles, t = 0..{}, 1 thread\n", n, T);
    fmt::print("{:>10} {:>14} {:>12} {:>14} {:>14}\n", "tolerance", "collisions/s", "vs free", "max|dE|/E", "rms|dE|/E");
    for (const double tol : {1e-6, 1e-8, 1e-10, 1e-12}) {
      const dynamics::FieldFlight flight(dynamics::Force{}, bowl, 1.0, table, tol);
      const auto t = time_run(table, flight, dynamics::microcanonical(table, flight, 1.0, 1), n, T);
      double worst = 0, sum2 = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const double d = std::abs(t.result.energies[2 * i + 1] - t.result.energies[2 * i]) / 0.5;
        worst = std::max(worst, d);
        sum2 += d * d;
      }
      fmt::print("{:>10.0e} {:>14.4g} {:>11.3g}x {:>14.3g} {:>14.3g}\n", tol, t.collisions_per_second,
                 t.collisions_per_second / reference.collisions_per_second, worst, std::sqrt(sum2 / double(n)));
    }
    fmt::print("free stadium (closed form): {:.4g} collisions/s\n\n", reference.collisions_per_second);
  }

  {
    const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
    const dynamics::Table table(shape.region);
    const Vec2 F = 10 / std::sqrt(2.0) * Vec2(1, 1);
    const std::size_t m = std::max<std::size_t>(1, n / 4);
    const double Tm = T / 5;
    fmt::print("uniform drive F = 10 in the clover, {} particles, t = 0..{}, 1 thread: FieldFlight vs the closed form\n",
               m, Tm);
    fmt::print("{:>8} {:>10} {:>16} {:>18} {:>8}\n", "omega", "tolerance", "field coll/s", "closed-form coll/s",
               "ratio");
    for (const double omega : {40 * geometry::pi, 320 * geometry::pi}) {
      const dynamics::PeriodicDriveFlight exact{F, omega, 0};
      const auto e = time_run(table, exact, dynamics::microcanonical(table, exact, 1.0, 3), m, Tm);
      dynamics::Force force;
      force.kind = dynamics::Force::Kind::periodic;
      force.amplitude = F;
      force.omega = omega;
      for (const double tol : {1e-8, 1e-10}) {
        const dynamics::FieldFlight field(force, std::nullopt, 1.0, table, tol);
        const auto f = time_run(table, field, dynamics::microcanonical(table, field, 1.0, 3), m, Tm);
        fmt::print("{:>6.0f}pi {:>10.0e} {:>16.4g} {:>18.4g} {:>7.0f}x\n", omega / geometry::pi, tol,
                   f.collisions_per_second, e.collisions_per_second,
                   e.collisions_per_second / f.collisions_per_second);
      }
    }
  }
}
