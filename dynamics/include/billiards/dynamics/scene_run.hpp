// A scene's ensemble, as `billiard run` and the Python module run it: the flight model of its
// force, its table, its run options and its initial states, in 2-D or 3-D.  Every caller that
// runs a scene goes through these, so that the same scene and seed give the same numbers
// everywhere.
#pragma once

#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/field_flight.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/magnetic_flight.hpp"
#include "billiards/dynamics/scene.hpp"
#include "billiards/dynamics/table3.hpp"

#include <cmath>
#include <type_traits>

namespace billiards::dynamics {

/// Calls run(flight) with the flight model the scene needs, chosen at compile time for the
/// whole ensemble (a free scene runs the straight-line kernels with no drive code in them).
template <class Run>
auto with_flight(const Scene& scene, Run&& run) {
  if (scene.dimension() == 3) {  // (the scene file refuses forces that 3-D has no flight for)
    const Vec3 accel = scene.force.amplitude / scene.mass;
    if (scene.magnetic()) {
      const Vec3 omega_c = scene.cyclotron_vector();
      if (scene.force.kind == Force::Kind::constant) return run(MagneticDriveFlight3{omega_c, accel});
      if (scene.force.kind == Force::Kind::periodic)
        return run(MagneticDriveFlight3{omega_c, accel, scene.force.omega, scene.force.phase});
      return run(MagneticFlight3{omega_c});
    }
    if (scene.force.kind == Force::Kind::periodic)
      return run(PeriodicDriveFlight3{accel, scene.force.omega, scene.force.phase});
    return run(FreeFlight3{});
  }
  // Closed forms where they exist; the integrator only for a position-dependent drive or a
  // potential.
  if (scene.integrated())
    return run(FieldFlight(scene.force, scene.potential, scene.mass, Table(scene.shape<2>().region),
                           scene.integrator_tolerance));
  const Vec2 accel = scene.force.amplitude / scene.mass;
  if (scene.magnetic()) {  // (the scene file refuses the rest)
    const double omega_c = scene.cyclotron_frequency();
    if (scene.force.kind == Force::Kind::constant) return run(MagneticDriveFlight{omega_c, accel});
    if (scene.force.kind == Force::Kind::periodic)
      return run(MagneticDriveFlight{omega_c, accel, scene.force.omega, scene.force.phase});
    return run(MagneticFlight{omega_c});
  }
  switch (scene.force.kind) {
    case Force::Kind::constant: return run(ConstantForceFlight{accel});
    case Force::Kind::periodic:
      if (scene.force.quivering_walls) return run(QuiveringWallFlight{accel, scene.force.omega, scene.force.phase});
      return run(PeriodicDriveFlight{accel, scene.force.omega, scene.force.phase});
    case Force::Kind::field:  // (handled above)
    case Force::Kind::none: break;
  }
  return run(FreeFlight{});
}

/// Is the flight model a 3-D one?
template <class Flight>
constexpr bool is_3d = Flight::State::dimension == 3;

/// The table of the flight's dimension.
template <class Flight>
using TableFor = BasicTable<double, Flight::State::dimension>;

/// The scene's table for `Flight`.
template <class Flight>
TableFor<Flight> table_of(const Scene& scene) {
  return TableFor<Flight>(scene.shape<Flight::State::dimension>().region);
}

/// The scene's record times and mass.  A forced flight costs ~10 containment tests, so every
/// flight of a forced run is checked (12% measured); free flights are 2× slower checked, so
/// there only when `verify` asks for it.
template <class Flight>
RunOptions run_options(const Scene& scene, bool verify) {
  RunOptions opt;
  opt.record_times = scene.record_times;
  opt.mass = scene.mass;
  opt.verify_every_flight = verify || !is_straight<Flight>;
  return opt;
}

/// Particle i's initial state: row i of the scene's initial-condition file, or its draw from the
/// microcanonical ensemble at the scene's energy with ParticleRng(seed, i).  `scene` and `table`
/// must outlive the returned function.  A scene whose particles enter through exits is refused:
/// only the open-table code (analysis/escape.hpp) samples that ensemble.
template <class Flight>
auto initial_states(const Scene& scene, const TableFor<Flight>& table, const Flight& flight) {
  if (scene.through_exit)
    throw InputError(scene.through_exit->file, scene.through_exit->line,
                     "particles entering through exits ('through_exit') are for open tables: billiard escape and "
                     "billiardkit.escape; this command needs 'microcanonical' or 'csv'");
  const auto* given = &scene.initial_states<Flight::State::dimension>();
  const auto sampled = microcanonical(table, flight, std::sqrt(2 * scene.energy / scene.mass), scene.seed);
  return [given, sampled, flight](std::size_t i) { return given->empty() ? sampled(i) : flight.start((*given)[i]); };
}

}  // namespace billiards::dynamics
