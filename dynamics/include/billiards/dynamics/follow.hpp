// A trajectory as a stream: one particle followed bounce by bounce, and sampled at uniform times
// between the bounces, each bounce and each sample handed to a callback and none stored, so a
// run of 10⁹ collisions needs the memory of one state.  Samples come from the flight's own
// `advance`, so a curved flight (constant force, periodic drive, quivering walls, a field) is
// reported along its true path, not as the chord between its bounces.
#pragma once

#include "billiards/dynamics/collision.hpp"

#include <cstddef>
#include <limits>
#include <utility>

namespace billiards::dynamics {

/// Sample times t0 + k dt, k = 0, 1, ...; each is computed from k, so rounding does not
/// accumulate over a long run, and the last of K frames falls exactly on `time(K − 1)`.
struct SampleClock {
  double t0 = 0;
  double dt = 0;       // 0: no samples
  std::size_t k = 0;   // the next sample's index
  double time(std::size_t i) const { return t0 + double(i) * dt; }
  /// Is the next sample due at or before t?
  bool due_by(double t) const { return dt > 0 && time(k) <= t; }
};

/// Reports the flight from `s` (its time on the flight's own clock, which started at the run's
/// time `run`) at every sample time of `clock` up to `t` (inclusive; times absolute) as
/// on_sample(state), its time absolute, and moves the clock past them.
template <class Flight, class OnSample>
void sample_flight(const Flight& flight, const typename Flight::State& s, const Clock& run, double t,
                   SampleClock& clock, OnSample&& on_sample) {
  for (; clock.due_by(t); ++clock.k) {
    const double at = clock.time(clock.k);
    auto r = flight.advance(s, run.until(at));
    r.t = at;
    on_sample(std::as_const(r));
  }
}

/// Where a stream ends: after `collisions` bounces or at time `t_end`, whichever comes first.
struct FollowLimits {
  std::size_t collisions = std::numeric_limits<std::size_t>::max();
  double t_end = never;
  /// Consecutive bounces at zero flight time before the particle is declared stuck (as
  /// RunOptions's), which ends the stream as an escape instead of looping in a corner forever.
  int max_zero_flights = 1000;
};

struct FollowResult {
  std::size_t collisions = 0;
  bool escaped = false;  // met no wall where it must, or stuck
  bool trapped = false;  // on a closed orbit that meets no wall: it circles inside forever
};

/// Follows the particle from `s`: on_bounce(hit, state) with the state just after each bounce,
/// on_sample(state) at each time of `clock` (the state before a bounce that falls on one), up to
/// the limits.  A flight that meets no wall is an escape for a straight flight (searched with no
/// horizon, as Trajectory does) or when there is no end time (a closed orbit then is trapped,
/// not escaped); a curved flight searched up to t_end meets none when it reaches t_end first.
/// A particle stuck in a corner is an escape too.  Energy-conserving flights restore the speed
/// after every bounce, and each flight runs on its own clock, as in `evolve`, so both give the
/// same states bit for bit (times absolute in what they report).
template <class TableT, class Flight, class OnBounce, class OnSample>
FollowResult follow(const TableT& table, const Flight& flight, typename Flight::State s, const FollowLimits& limits,
                    SampleClock clock, OnBounce&& on_bounce, OnSample&& on_sample) {
  const auto v2 = s.v.squaredNorm();
  Clock run;
  restart_clock(flight, s, run);
  FollowResult result;
  int zero_flights = 0;
  while (result.collisions < limits.collisions) {
    const double horizon = is_straight<Flight> ? never : run.until(limits.t_end);
    const auto hit = collision(table, flight, s, horizon);
    if (!hit.found() && horizon == never) {
      // A closed orbit (`closes_orbit`: a magnetic one without drift along the field) that
      // meets no wall at all circles where it is, inside the table; any other leaves it.
      if constexpr (requires { flight.closes_orbit(s); }) (flight.closes_orbit(s) ? result.trapped : result.escaped) = true;
      else result.escaped = true;
      break;
    }
    const double t_hit = hit.found() ? run.after(hit.t) : never;
    const bool ends = t_hit > limits.t_end;
    sample_flight(flight, s, run, ends ? limits.t_end : t_hit, clock, on_sample);
    if (ends) break;
    zero_flights = hit.t == s.t ? zero_flights + 1 : 0;
    if (zero_flights > limits.max_zero_flights) {
      result.escaped = true;
      break;
    }
    bounce(flight, s, hit);
    if constexpr (Flight::conserves_energy) restore_speed(s.v, v2);
    ++result.collisions;
    on_bounce(on_clock(hit, run), on_clock(s, run));
    restart_clock(flight, s, run);
  }
  return result;
}

}  // namespace billiards::dynamics
