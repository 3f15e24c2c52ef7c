// A scene's ensemble, as `billiard run` and the Python module run it: the flight model of its
// force, its run options and its initial states.  Every caller that runs a scene goes through
// these, so that the same scene and seed give the same numbers everywhere.
#pragma once

#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/scene.hpp"

#include <cmath>
#include <type_traits>

namespace billiards::dynamics {

/// Calls run(flight) with the flight model the scene's force needs, chosen at compile time for
/// the whole ensemble (a free scene runs the straight-line kernels with no drive code in them).
template <class Run>
auto with_flight(const Scene& scene, Run&& run) {
  const Vec2 accel = scene.force.amplitude / scene.mass;
  switch (scene.force.kind) {
    case Force::Kind::constant: return run(ConstantForceFlight{accel});
    case Force::Kind::periodic: return run(PeriodicDriveFlight{accel, scene.force.omega, scene.force.phase});
    case Force::Kind::none: break;
  }
  return run(FreeFlight{});
}

/// The scene's record times and mass.  A forced flight costs ~10 containment tests, so every
/// flight of a forced run is checked (12% measured); free flights are 2× slower checked, so
/// there only when `verify` asks for it.
template <class Flight>
RunOptions run_options(const Scene& scene, bool verify) {
  RunOptions opt;
  opt.record_times = scene.record_times;
  opt.mass = scene.mass;
  opt.verify_every_flight = verify || !std::is_same_v<Flight, FreeFlight>;
  return opt;
}

/// Particle i's initial state: row i of the scene's initial-condition file, or its draw from the
/// microcanonical ensemble at the scene's energy with ParticleRng(seed, i).  `table` must outlive
/// the returned function.
template <class Flight>
auto initial_states(const Scene& scene, const Table& table, const Flight& flight) {
  const auto sampled = microcanonical(table, flight, std::sqrt(2 * scene.energy / scene.mass), scene.seed);
  return [&scene, sampled, flight](std::size_t i) {
    return scene.initial_states.empty() ? sampled(i) : flight.start(scene.initial_states[i]);
  };
}

}  // namespace billiards::dynamics
