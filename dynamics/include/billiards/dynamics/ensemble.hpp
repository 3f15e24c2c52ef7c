// Ensembles: many independent particles, each with its own random stream, run in parallel.
// Results are stored by particle index and reduced in index order, so they are bit-identical
// for any number of threads.
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/random.hpp"

#include <omp.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <type_traits>
#include <vector>

namespace billiards::dynamics {

/// What happened to one particle.
struct ParticleLog {
  std::uint64_t collisions = 0;
  bool escaped = false;  // left the region: reported as an error, never dropped
};

struct RunOptions {
  std::vector<double> record_times;  // increasing, ≥ 0: energies are recorded at these times
  double mass = 1;
  /// Also test the midpoint of every flight with the independent point-in-region test
  /// (costs about as much as the collision search; on in the test suite).
  bool verify_every_flight = false;
  /// Consecutive collisions at zero flight time before a particle is declared stuck.
  int max_zero_flights = 1000;
};

template <class State>
double kinetic_energy(const State& s, double mass) { return 0.5 * mass * s.v.squaredNorm(); }

/// Runs one particle from `s`, writing its energy at each record time into `energies`
/// (NaN after an escape).  Flights are searched up to the last record time only.
template <class Flight>
ParticleLog simulate(const Table& table, const Flight& flight, typename Flight::State s,
                     const RunOptions& opt, double* energies) {
  ParticleLog log;
  const auto& times = opt.record_times;
  const std::size_t n = times.size();
  const double t_final = times.empty() ? s.t : times.back();
  std::size_t k = 0;
  int zero_flights = 0;
  const double v2 = s.v.squaredNorm();
  auto escape = [&] {
    log.escaped = true;
    for (; k < n; ++k) energies[k] = std::nan("");
    return log;
  };
  // A straight flight costs the same whatever the horizon: search without one, so that a
  // particle that meets no wall at all is caught as an escape at once.
  const double horizon = std::is_same_v<Flight, FreeFlight> ? never : t_final;
  while (k < n) {
    const Hit hit = collision(table, flight, s, horizon);
    const double t_next = hit.found() ? hit.t : never;
    for (; k < n && times[k] <= t_next; ++k) {
      const auto r = flight.advance(s, times[k]);
      if (!table.contains(r.x)) return escape();
      energies[k] = kinetic_energy(r, opt.mass);
    }
    if (k == n) break;
    if (!hit.found()) return escape();  // no wall ahead of a particle that should meet one
    if (opt.verify_every_flight && !table.contains(flight.advance(s, 0.5 * (s.t + hit.t)).x))
      return escape();
    zero_flights = hit.t == s.t ? zero_flights + 1 : 0;
    if (zero_flights > opt.max_zero_flights) return escape();
    bounce(flight, s, hit);
    if constexpr (Flight::conserves_energy) restore_speed(s.v, v2);
    ++log.collisions;
  }
  return log;
}

/// Results of an ensemble run: energies[i * record_times.size() + k] for particle i.
struct EnsembleResult {
  std::vector<double> energies;
  std::vector<ParticleLog> logs;
  std::uint64_t collisions() const;
  std::uint64_t escapes() const;
};

/// Runs particles [first, last) of an ensemble.  `initial(i)` gives particle i's state (it
/// must depend on i only); `progress(done)` is called from one thread now and then.
template <class Flight, class Initial>
void run_particles(const Table& table, const Flight& flight, const Initial& initial,
                   const RunOptions& opt, std::size_t first, std::size_t last, int threads,
                   EnsembleResult& out, const std::function<void(std::size_t)>& progress = {}) {
  const std::size_t m = opt.record_times.size();
  std::atomic<std::size_t> done{0};
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
  for (std::ptrdiff_t i = std::ptrdiff_t(first); i < std::ptrdiff_t(last); ++i) {
    out.logs[i] = simulate(table, flight, initial(std::size_t(i)), opt, &out.energies[std::size_t(i) * m]);
    const std::size_t d = ++done;
    if (progress && omp_get_thread_num() == 0) progress(d);
  }
  if (progress) progress(done);
}

}  // namespace billiards::dynamics
