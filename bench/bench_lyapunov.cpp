// The cost of the phase-space diagnostics per collision against plain collisions, in the same
// run on one core: `evolve` alone (the collision search and the bounce), the boundary map
// (plus s and p of every hit) and the tangent dynamics of `lyapunov` (plus the collision
// Jacobian and a 4 × 4 Gram–Schmidt per collision); free flights in three tables and the
// driven clover.
// Usage: bench_lyapunov [collisions per case, default 2e6]
#include "billiards/analysis/boundary_map.hpp"
#include "billiards/analysis/lyapunov.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/geometry/shape_file.hpp"

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

template <class Flight>
void compare(const std::string& name, const dynamics::Table& table, const geometry::Region2& region,
             const Flight& flight, const typename Flight::State& s, std::size_t collisions) {
  double sink = 0;
  const double plain = seconds_of([&] {
    dynamics::evolve(table, flight, s, collisions, [&](const auto& hit, const auto&) { sink += hit.t; });
  });
  const analysis::BoundaryCoordinates coordinates(region);
  const double bmap = seconds_of([&] {
    const auto r = analysis::boundary_map(table, coordinates, flight, [&](std::size_t) { return s; }, 1, collisions, 1);
    sink += r.rows.back();
  });
  const double tangent = seconds_of([&] { sink += analysis::lyapunov_trajectory(table, flight, s, collisions).time; });
  const double n = double(collisions);
  fmt::print("| {} | {:.0f} | {:.0f} ({:.2f}x) | {:.0f} ({:.2f}x) |\n", name, 1e9 * plain / n, 1e9 * bmap / n,
             bmap / plain, 1e9 * tangent / n, tangent / plain);
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
    const auto s = dynamics::microcanonical(table, dynamics::FreeFlight{}, 1.0, 1)(0);
    compare(std::string(name) + " (free)", table, shape.region, dynamics::FreeFlight{}, s, collisions);
  }
  const auto scene = dynamics::load_scene(BILLIARDS_SOURCE_DIR "/scenes/clover-driven.yaml");
  const dynamics::Table table(scene.shape.region);
  const dynamics::PeriodicDriveFlight drive{scene.force.amplitude / scene.mass, scene.force.omega, scene.force.phase};
  compare("clover (driven)", table, scene.shape.region, drive, dynamics::initial_states(scene, table, drive)(0),
          collisions / 10);
}
