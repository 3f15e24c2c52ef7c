// The cost of the phase-space diagnostics per collision against plain collisions, in the same
// run on one core: `evolve` alone (the collision search and the bounce), the boundary map
// (plus s and p of every hit) and the tangent dynamics of `lyapunov` (plus the collision
// Jacobian and a 4 × 4 Gram–Schmidt per collision; 6 × 6 in 3-D); free flights in three
// tables, the driven clover (lab and quivering walls, and in a magnetic field) and the stadium
// in a magnetic field, and in 3-D free flights in the Sinai cube and the ball, the driven Sinai
// cube and the Sinai cube in a magnetic field, alone and driven (no boundary map in 3-D, nor
// for a field with a force, followed to successive horizons: `evolve_to_horizons` is the
// plain run there).
// Usage: bench_lyapunov [collisions per case, default 2e6]
#include "billiards/analysis/boundary_map.hpp"
#include "billiards/analysis/lyapunov.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/geometry/shape_file.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <fmt/core.h>

#include <chrono>
#include <cstdlib>

using namespace billiards;

namespace {

template <class Fn>
double seconds_of(Fn&& fn) {
  const auto start = std::chrono::steady_clock::now();
  fn();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// One table's row: plain collisions, the boundary map (2-D), tangent dynamics.
template <class Flight, class Coordinates>
void compare(const std::string& name, const dynamics::TableFor<Flight>& table, const Coordinates* coordinates,
             const Flight& flight, const typename Flight::State& s, std::size_t collisions) {
  double sink = 0;
  const double plain = seconds_of([&] {
    const auto visit = [&](const auto& hit, const auto&) { sink += hit.t; };
    if constexpr (analysis::horizon_flight<Flight>) {
      auto from = s;
      analysis::evolve_to_horizons(table, flight, from, collisions, visit);
    } else {
      dynamics::evolve(table, flight, s, collisions, visit);
    }
  });
  const double n = double(collisions);
  std::string bmap_cell = "—";
  if constexpr (!dynamics::is_3d<Flight> && !analysis::horizon_flight<Flight>) {
    const double bmap = seconds_of([&] {
      const auto r =
          analysis::boundary_map(table, *coordinates, flight, [&](std::size_t) { return s; }, 1, collisions, 1);
      sink += r.rows.back();
    });
    bmap_cell = fmt::format("{:.0f} ({:.2f}x)", 1e9 * bmap / n, bmap / plain);
  }
  const double tangent = seconds_of([&] { sink += analysis::lyapunov_trajectory(table, flight, s, collisions).time; });
  fmt::print("| {} | {:.0f} | {} | {:.0f} ({:.2f}x) |\n", name, 1e9 * plain / n, bmap_cell, 1e9 * tangent / n,
             tangent / plain);
  if (sink == 0.5) fmt::print("\n");  // (keeps the work)
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t collisions = argc > 1 ? std::size_t(std::atof(argv[1])) : 2000000;
  fmt::print("{} collisions per case, one thread; ns per collision (ratio to plain collisions)\n\n", collisions);
  fmt::print("| table | plain | boundary map | tangent dynamics |\n|---|---|---|---|\n");
  for (const char* name : {"sinai", "clover", "elliptic-stadium"}) {
    const auto shape = geometry::load_shape(fmt::format("{}/shapes/{}.yaml", BILLIARDS_SOURCE_DIR, name));
    const dynamics::Table table(shape.region);
    const analysis::BoundaryCoordinates coordinates(shape.region);
    const auto s = dynamics::microcanonical(table, dynamics::FreeFlight{}, 1.0, 1)(0);
    compare(std::string(name) + " (free)", table, &coordinates, dynamics::FreeFlight{}, s, collisions);
  }
  const auto scene = dynamics::load_scene(BILLIARDS_SOURCE_DIR "/scenes/clover-driven.yaml");
  const dynamics::Table table(scene.shape<2>().region);
  const analysis::BoundaryCoordinates coordinates(scene.shape<2>().region);
  const dynamics::PeriodicDriveFlight drive{scene.force.amplitude / scene.mass, scene.force.omega, scene.force.phase};
  compare("clover (driven)", table, &coordinates, drive, dynamics::initial_states(scene, table, drive)(0),
          collisions / 10);
  const dynamics::QuiveringWallFlight quiver{drive.accel, drive.omega, drive.phase0};
  compare("clover (quivering walls)", table, &coordinates, quiver, quiver.start(dynamics::initial_states(scene, table, drive)(0)),
          collisions / 10);
  const auto forced = dynamics::load_scene(BILLIARDS_SOURCE_DIR "/scenes/clover-magnetic-driven.yaml");
  const dynamics::MagneticDriveFlight forced_field{forced.cyclotron_frequency(), forced.force.amplitude / forced.mass,
                                                   forced.force.omega, forced.force.phase};
  compare("clover (driven, magnetic)", table, &coordinates, forced_field,
          dynamics::initial_states(forced, table, forced_field)(0), collisions / 10);
  const auto stadium = dynamics::load_scene(BILLIARDS_SOURCE_DIR "/scenes/stadium-magnetic.yaml");
  const dynamics::Table stadium_table(stadium.shape<2>().region);
  const analysis::BoundaryCoordinates stadium_coordinates(stadium.shape<2>().region);
  const dynamics::MagneticFlight field{stadium.cyclotron_frequency()};
  compare("stadium (magnetic)", stadium_table, &stadium_coordinates, field,
          dynamics::initial_states(stadium, stadium_table, field)(0), collisions);
  for (const char* name : {"sinai3", "ball"}) {
    const auto shape = geometry3::load_shape3(fmt::format("{}/shapes/3d/{}.yaml", BILLIARDS_SOURCE_DIR, name));
    const dynamics::Table3 table3(shape.region);
    const auto s = dynamics::microcanonical(table3, dynamics::FreeFlight3{}, 1.0, 1)(0);
    compare<dynamics::FreeFlight3, void>(std::string(name) + " 3-D (free)", table3, nullptr, {}, s, collisions);
  }
  const auto scene3 = dynamics::load_scene(BILLIARDS_SOURCE_DIR "/scenes/sinai3-driven.yaml");
  const dynamics::Table3 table3(scene3.shape<3>().region);
  const dynamics::PeriodicDriveFlight3 drive3{scene3.force.amplitude / scene3.mass, scene3.force.omega,
                                             scene3.force.phase};
  compare<dynamics::PeriodicDriveFlight3, void>("sinai3 3-D (driven)", table3, nullptr, drive3,
                                                dynamics::initial_states(scene3, table3, drive3)(0), collisions / 10);
  const auto magnetic3 = dynamics::load_scene(BILLIARDS_SOURCE_DIR "/scenes/sinai3-magnetic.yaml");
  const dynamics::Table3 magnetic_table3(magnetic3.shape<3>().region);
  const dynamics::MagneticFlight3 helix{magnetic3.cyclotron_vector()};
  compare<dynamics::MagneticFlight3, void>("sinai3 3-D (magnetic)", magnetic_table3, nullptr, helix,
                                           dynamics::initial_states(magnetic3, magnetic_table3, helix)(0),
                                           collisions / 10);
  const auto forced3 = dynamics::load_scene(BILLIARDS_SOURCE_DIR "/scenes/sinai3-magnetic-driven.yaml");
  const dynamics::MagneticDriveFlight3 forced_helix{forced3.cyclotron_vector(), forced3.force.amplitude / forced3.mass,
                                                    forced3.force.omega, forced3.force.phase};
  compare<dynamics::MagneticDriveFlight3, void>("sinai3 3-D (driven, magnetic)", magnetic_table3, nullptr,
                                                forced_helix,
                                                dynamics::initial_states(forced3, magnetic_table3, forced_helix)(0),
                                                collisions / 10);
}
