// Speed against error (issue 6): the toolkit's exact driven flight against the baseline a user
// would otherwise write — Boost.Odeint's Dormand–Prince 5(4) with dense output, the wall
// distances monitored after every step and the crossing located by bisection on the dense
// output — on the same initial conditions, so that differences are the methods' errors and
// not sampling noise.  The toolkit itself is checked against a 100-bit MPFR evaluation of
// Appendix B's closed form along its own collision sequence.
#pragma once

#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/table.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace billiards::analysis {

using dynamics::PeriodicDriveFlight;
using dynamics::Table;
using dynamics::Vec2;

/// A collision as a method reports it: when, which wall, where.
struct Bounce {
  double t;
  dynamics::WallId wall;
  Vec2 x;
};

/// One particle run from its initial state to t_end.
struct Run {
  dynamics::State end;  // the state at t_end
  std::vector<Bounce> bounces;
  bool escaped = false;  // outside the table at t_end (a missed collision)
};

/// The toolkit's exact flight: certified collision times, closed-form flights.
Run exact_run(const Table& table, const PeriodicDriveFlight& flight, const dynamics::State& s0, double t_end);

/// The baseline: dopri5 with absolute and relative tolerance `tolerance`, events by sign
/// change of the signed distance to each wall between steps, bisection on the dense output,
/// specular reflection.  Not certified: a step may jump over a collision.
Run odeint_run(const Table& table, const PeriodicDriveFlight& flight, const dynamics::State& s0, double t_end,
               double tolerance);

/// The exact run re-evaluated in 100-bit MPFR: closed-form flights, each collision time
/// re-solved by bisection in a bracket around the toolkit's, reflection in MPFR.
struct MpfrCheck {
  bool confirmed = false;  // every collision bracketed by a sign change of its wall's distance
  Vec2 first_collision;    // where the first collision is (one flight: no chaotic amplification)
  Vec2 x;                  // position at t_end
  double energy = 0;       // kinetic energy at t_end
};
MpfrCheck mpfr_check(const Table& table, const PeriodicDriveFlight& flight, const dynamics::State& s0,
                     const Run& exact, double t_end, double mass);

struct SpeedErrorOptions {
  std::vector<double> tolerances;  // of the Odeint baseline
  std::size_t particles = 100;     // for every method, the same initial conditions
  std::size_t mpfr_particles = 20; // checked in MPFR (the toolkit's error)
  double t_end = 20;
  double mass = 1;
  double energy = 0.5;  // E0 of the microcanonical start
  std::uint64_t seed = 1;
};

/// One method at one setting (a row of speed-error.csv; columns documented in BENCHMARKS.md).
struct SpeedErrorRow {
  std::string method;  // "exact" or "odeint"
  double omega = 0, tolerance = 0;
  std::size_t particles = 0, escapes = 0;
  std::size_t unconfirmed = 0;      // exact runs whose MPFR re-evaluation lost a collision
  double cpu_seconds_per_time = 0;  // CPU seconds per simulated time unit per particle
  double var_dE = 0;                // of the particles that did not escape
  double var_dE_error = 0;          // |Var(dE) − reference| on the same particles
  double var_dE_se = 0;             // sampling SE of the reference Var(dE), for context
  double median_position_error = 0; // median |x(t_end) − reference|: chaos amplifies it
  double median_first_collision_error = 0;  // median distance between first collision points
  double collisions_per_particle = 0;
};

/// The exact flight (its error against MPFR on `mpfr_particles` particles), then the Odeint
/// baseline at each tolerance (its error against the exact flight).
std::vector<SpeedErrorRow> speed_error(const Table& table, const PeriodicDriveFlight& flight,
                                       const SpeedErrorOptions& options);

/// Odeint's CPU time over the exact flight's, at equal error in Var(dE):
///   `equal`: the cheapest Odeint setting whose error is at most the exact flight's (and has
///            no escapes), or null when none is;
///   `within_se`: the cheapest whose error is below the sampling SE of Var(dE) — the accuracy
///            an ensemble of this size can resolve — or null;
///   `cheapest`: the cheapest setting of all.
struct SpeedRatios {
  const SpeedErrorRow* exact = nullptr;
  const SpeedErrorRow *equal = nullptr, *within_se = nullptr, *cheapest = nullptr;
  double ratio(const SpeedErrorRow* baseline) const {
    return baseline->cpu_seconds_per_time / exact->cpu_seconds_per_time;
  }
};
SpeedRatios speed_ratios(const std::vector<SpeedErrorRow>& rows);

}  // namespace billiards::analysis
