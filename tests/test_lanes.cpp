// Straight and magnetic flights searched in lock step (free_lockstep.hpp, magnetic_lockstep.hpp)
// against the scalar search, for every SIMD target this processor runs: the same hits, bit for
// bit, from states along orbits (each starting on the wall it has just left) with and without
// horizons, in every flat table (segments, focusing and dispersing arcs, holes, elliptic arcs)
// and in one with more walls than a vector has lanes, in weak and strong fields of both signs;
// 3-D straight flights in tables of planes and spheres (focusing and dispersing) and in meshes,
// in batches and as a stream whose lanes are refilled in any order; and ensembles equal to
// `simulate`, particle by particle, for any thread count.
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/free_lockstep.hpp"
#include "billiards/dynamics/magnetic_lockstep.hpp"
#include "billiards/geometry.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include "lanes_helpers.hpp"
#include "many_walls.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

using namespace billiards;
using dynamics::FreeFlight;
using dynamics::FreeFlight3;
using dynamics::MagneticFlight;
using dynamics::State;
using dynamics::Table;

namespace {

template <class Kernel>
struct TargetKernel {
  const char* name;
  Kernel kernel;
};
/// The kernel of each SIMD target this processor runs, for the flight's lock-step table.
template <class Flight>
auto kernels() {
  using Kernel = std::conditional_t<std::is_same_v<Flight, FreeFlight>, dynamics::free_lanes::Kernel,
                                    std::conditional_t<std::is_same_v<Flight, FreeFlight3>, dynamics::free_lanes::Kernel3,
                                                       dynamics::magnetic_lanes::Kernel>>;
  std::vector<TargetKernel<Kernel>> all;
  for (const auto& t : dynamics::simd::runnable_targets()) {
    if constexpr (std::is_same_v<Flight, FreeFlight>) all.push_back({t.name, dynamics::free_lanes::kernel_of(t.bit)});
    else if constexpr (std::is_same_v<Flight, FreeFlight3>) all.push_back({t.name, dynamics::free_lanes::kernel3_of(t.bit)});
    else all.push_back({t.name, dynamics::magnetic_lanes::kernel_of(t.bit)});
  }
  return all;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
template <class V>
bool same_bits(const V& a, const V& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * std::size_t(a.size())) == 0;
}

template <class Flight>
bool same_hit(const dynamics::FlightHit<Flight>& a, const dynamics::FlightHit<Flight>& b) {
  if (a.wall != b.wall || !same_bits(a.t, b.t)) return false;
  return !a.found() || (same_bits(a.point, b.point) && same_bits(a.normal, b.normal) && same_bits(a.state.x, b.state.x) &&
                        same_bits(a.state.v, b.state.v) && same_bits(a.state.t, b.state.t));
}

Table table_of(const std::string& shape) {
  return Table(geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + shape + ".yaml").region);
}

/// Fresh microcanonical starts and the states after each bounce of their orbits, each flight on
/// its own clock, as in the ensembles.  (A magnetic orbit that circles without meeting a wall
/// ends there.)
template <class TableT, class Flight>
auto states_along_orbits(const TableT& table, const Flight& flight, int particles, int bounces) {
  using S = typename Flight::State;
  std::vector<S> states;
  for (int p = 0; p < particles; ++p) {
    dynamics::ParticleRng rng(97, std::uint64_t(p));
    S s = flight.start(dynamics::sample_microcanonical(table, 1.0, rng));
    const double v2 = s.v.squaredNorm();
    dynamics::Clock clock;
    states.push_back(s);
    for (int k = 0; k < bounces; ++k) {
      const auto hit = dynamics::collision(table, flight, s);
      if (!hit.found()) break;
      dynamics::bounce(flight, s, hit);
      dynamics::restore_speed(s.v, v2);
      dynamics::restart_clock(flight, s, clock);
      states.push_back(s);
    }
  }
  return states;
}

std::vector<std::pair<std::string, Table>> flat_tables() {
  std::vector<std::pair<std::string, Table>> tables;
  for (const char* shape : {"clover", "stadium", "sinai", "mushroom", "square", "circle", "triangle", "l-room",
                            "annulus", "ellipse", "sinai-ellipse", "elliptic-stadium"})
    tables.emplace_back(shape, table_of(shape));
  tables.emplace_back("twenty-gon", twenty_gon());
  REQUIRE(tables.back().second.segments().size() == 20);
  return tables;
}

/// A 3-D table and the shape it keeps a reference to.
struct Table3Of {
  std::string name;
  geometry3::Shape3 shape;
  dynamics::Table3 table;
  Table3Of(std::string n, geometry3::Shape3 s) : name(std::move(n)), shape(std::move(s)), table(shape.region) {}
};

/// The 3-D tables of planes and spheres: the bundled ones, and a ball with three balls inside
/// (one focusing sphere, three dispersing ones) and a box with four.
std::vector<std::unique_ptr<Table3Of>> sphere_and_plane_tables() {
  std::vector<std::unique_ptr<Table3Of>> tables;
  for (const char* shape : {"sinai3", "ball", "cube", "octahedron"})
    tables.push_back(std::make_unique<Table3Of>(shape, geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/" + std::string(shape) + ".yaml")));
  tables.push_back(std::make_unique<Table3Of>("ball-of-balls", geometry3::parse_shape3(R"(name: ball-of-balls
dimension: 3
boundary:
  sphere: {center: [0, 0, 0], radius: 1}
holes:
  - ball: {center: [0.4, 0, 0], radius: 0.3}
  - ball: {center: [-0.3, 0.4, 0.1], radius: 0.2}
  - ball: {center: [-0.2, -0.3, -0.5], radius: 0.25}
)", "ball-of-balls")));
  tables.push_back(std::make_unique<Table3Of>("box-of-balls", geometry3::parse_shape3(R"(name: box-of-balls
dimension: 3
boundary:
  box: {min: [-1, -0.5, -0.5], max: [1, 0.5, 0.5]}
holes:
  - ball: {center: [-0.5, 0, 0], radius: 0.3}
  - ball: {center: [0.5, 0.2, 0.1], radius: 0.25}
  - ball: {center: [0.1, -0.3, 0.3], radius: 0.1}
  - ball: {center: [0.7, -0.25, -0.25], radius: 0.2}
)", "box-of-balls")));
  return tables;
}

/// The 3-D tables with a mesh, whose flights' BVH walks run together: the L-prism, the L-prism
/// with two balls inside (spheres asked after the triangles) and the bumpy sphere of 100 820
/// triangles.
std::vector<std::unique_ptr<Table3Of>> mesh_tables() {
  const std::string dir = BILLIARDS_SOURCE_DIR "/shapes/3d";
  std::vector<std::unique_ptr<Table3Of>> tables;
  for (const char* shape : {"l-prism", "bumpy-100k"})
    tables.push_back(std::make_unique<Table3Of>(shape, geometry3::load_shape3(dir + "/" + shape + ".yaml")));
  tables.push_back(std::make_unique<Table3Of>("l-prism-of-balls", geometry3::parse_shape3(R"(name: l-prism-of-balls
dimension: 3
boundary:
  mesh: l-prism.off
holes:
  - ball: {center: [0.5, 0.5, 1], radius: 0.3}
  - ball: {center: [1.5, 0.5, 0.6], radius: 0.2}
)", "l-prism-of-balls", {}, dir)));
  return tables;
}

/// The end of the search from state k of states along orbits: the horizons cycle through none
/// and some that end flights before their walls (in units of the table's size).
template <class S>
double horizon_end(const S& s, std::size_t k, double size) {
  const double horizons[] = {dynamics::never, 1e-3, 0.7, 3};
  const double h = horizons[k % 4];
  return h == dynamics::never ? h : s.t + h * size;
}

/// Batches of every size 1..16 of states along the flight's orbits in the table and along
/// straight orbits (on every wall, leaving it in every direction: a strong field's orbits from
/// a fresh start may circle without meeting one), the states taken in turn, each state's horizon
/// cycling through none and some that end flights before their walls: the lock-step hits equal
/// the scalar search's, bit for bit, for every target.
template <class TableT, class Flight>
void check_batches(const std::string& shape, const TableT& table, const Flight& flight) {
  using LockstepT = dynamics::LockstepTableOf<Flight>;
  using S = typename Flight::State;
  using Straight = dynamics::BasicFreeFlight<double, S::dimension>;
  constexpr int lanes = LockstepT::lanes;
  auto states = states_along_orbits(table, Straight{}, 6, 2000);
  if constexpr (!std::is_same_v<Flight, Straight>) {
    const auto own = states_along_orbits(table, flight, 6, 2000);
    states.insert(states.end(), own.begin(), own.end());
  }
  const double size = (table.hi() - table.lo()).norm();
  for (const auto& [name, kernel] : kernels<Flight>()) {
    const LockstepT lockstep(table, flight, kernel);
    REQUIRE(lockstep.usable());
    int found = 0, mismatches = 0;
    std::size_t next = 0;
    for (int round = 0; next < states.size(); ++round) {
      const int n = std::min<int>(1 + round % lanes, int(states.size() - next));
      const S* batch[lanes];
      double t_end[lanes];
      for (int i = 0; i < n; ++i) {
        batch[i] = &states[next + std::size_t(i)];
        t_end[i] = horizon_end(*batch[i], next + std::size_t(i), size);
      }
      dynamics::FlightHit<Flight> hits[lanes];
      lockstep.collisions(batch, t_end, n, hits);
      for (int i = 0; i < n; ++i) {
        const auto expected = dynamics::collision(table, flight, *batch[i], t_end[i]);
        found += expected.found();
        if (!same_hit(hits[i], expected)) {
          ++mismatches;
          UNSCOPED_INFO(name << " kernel, " << shape << ", state " << next + std::size_t(i) << ": wall "
                             << hits[i].wall << " at " << hits[i].t << ", scalar wall " << expected.wall << " at "
                             << expected.t);
        }
      }
      next += std::size_t(n);
    }
    INFO(name << " kernel, " << shape << ", " << states.size() << " states");
    CHECK(mismatches == 0);
    CHECK(found > int(states.size()) / 2);  // most flights end on a wall...
    CHECK(found < int(states.size()));      // ...and some at their short horizon
  }
}

/// What the raw kernel found by itself from states in batches of sixteen with no horizon: its
/// hits by wall kind, those it handed back, and those that are not the scalar search's wall
/// and time to the bit.  (The batch tests would pass as well if it handed every flight back.)
struct KernelTally {
  int on_kind[3] = {}, handed_back = 0, mismatches = 0;
};
template <class TableT, class Flight, class Walls, class Kernel>
KernelTally tally_kernel(const TableT& table, const Flight& flight, const Walls& walls, Kernel kernel,
                         const std::vector<typename Flight::State>& states) {
  constexpr int lanes = dynamics::free_lanes::lanes;
  KernelTally tally;
  double t_end[lanes];
  std::fill(t_end, t_end + lanes, dynamics::never);
  for (std::size_t first = 0; first + lanes <= states.size(); first += lanes) {
    const typename Flight::State* batch[lanes];
    for (int i = 0; i < lanes; ++i) batch[i] = &states[first + std::size_t(i)];
    const auto rays = dynamics::free_lanes::rays_of(batch, t_end, lanes);
    dynamics::free_lanes::Hits hits;
    kernel(walls, rays, hits);
    for (int i = 0; i < lanes; ++i) {
      if (hits.handed_back[i]) {
        ++tally.handed_back;
        continue;
      }
      const auto expected = dynamics::collision(table, flight, *batch[i]);
      if (hits.kind[i] >= 0) ++tally.on_kind[hits.kind[i]];
      tally.mismatches += hits.kind[i] != expected.wall.kind || hits.index[i] != expected.wall.index ||
                          !same_bits(hits.t[i], expected.t);
    }
  }
  return tally;
}

}  // namespace

TEST_CASE("free lock step: each batch's hits are the scalar search's, bit for bit, in every flat table") {
  for (const auto& [shape, table] : flat_tables()) check_batches(shape, table, FreeFlight{});
}

TEST_CASE("free lock step in 3-D: each batch's hits are the scalar search's, bit for bit, in tables of planes and spheres") {
  for (const auto& t : sphere_and_plane_tables()) check_batches(t->name, t->table, FreeFlight3{});
}

TEST_CASE("free lock step in 3-D: the BVH walks of a batch run together find the scalar search's hits, bit for bit, in meshes") {
  for (const auto& t : mesh_tables()) check_batches(t->name, t->table, FreeFlight3{});
}

TEST_CASE("free lock step in 3-D: a stream of flights, each lane given its next as soon as its hit is found, finds the scalar search's hits, bit for bit, in meshes") {
  using dynamics::FlightHit;
  using dynamics::NextFlight;
  using dynamics::State3;
  for (const auto& t : mesh_tables())
    for (const int lanes : {dynamics::Table3::max_together, 5}) {
      const auto states = states_along_orbits(t->table, FreeFlight3{}, 6, 2000);
      const double size = (t->table.hi() - t->table.lo()).norm();
      std::vector<double> t_end(states.size());
      for (std::size_t k = 0; k < states.size(); ++k) t_end[k] = horizon_end(states[k], k, size);
      // The states handed out in turn to whichever lane asks; the hits as the lanes are told them.
      std::vector<FlightHit<FreeFlight3>> hits(states.size());
      std::vector<std::size_t> told;
      std::size_t handed = 0, searching[dynamics::Table3::max_together];
      t->table.collision_stream(FreeFlight3{}, lanes, [&](int i, const FlightHit<FreeFlight3>* hit) {
        if (hit) hits[searching[i]] = *hit, told.push_back(searching[i]);
        if (handed == states.size()) return NextFlight<State3>{};
        searching[i] = handed;
        return NextFlight<State3>{&states[handed], t_end[handed++]};
      });
      INFO(t->name << ", " << lanes << " lanes, " << states.size() << " states");
      REQUIRE(told.size() == states.size());
      int mismatches = 0, found = 0, out_of_turn = 0;
      for (std::size_t k = 0; k < states.size(); ++k) {
        const auto expected = dynamics::collision(t->table, FreeFlight3{}, states[k], t_end[k]);
        found += expected.found();
        mismatches += !same_hit(hits[k], expected);
        out_of_turn += k > 0 && told[k] < told[k - 1];
      }
      CHECK(mismatches == 0);
      CHECK(found > int(states.size()) / 2);
      CHECK(found < int(states.size()));
      // Lanes were refilled while others walked on: the hits were not told in the states' order.
      CHECK(out_of_turn > int(states.size()) / 10);
    }
}

TEST_CASE("free lock step in 3-D: the kernel itself finds the hits on planes and spheres, at the scalar search's times") {
  for (const auto& t : sphere_and_plane_tables()) {
    const auto& table = t->table;
    const auto states = states_along_orbits(table, FreeFlight3{}, 4, 400);
    const auto walls = dynamics::free_lanes::walls_of(table);
    for (const auto& [name, kernel] : kernels<FreeFlight3>()) {
      INFO(name << " kernel, " << t->name);
      const KernelTally tally = tally_kernel(table, FreeFlight3{}, walls, kernel, states);
      CHECK(tally.mismatches == 0);
      CHECK(tally.handed_back == 0);  // (no grazing flight among these)
      // Every wall kind of the table is met by the kernel's own search.
      if (!table.planes().empty()) CHECK(tally.on_kind[dynamics::wall_kind3::plane] > int(states.size()) / 10);
      if (!table.spheres().empty()) CHECK(tally.on_kind[dynamics::wall_kind3::sphere] > int(states.size()) / 10);
    }
  }
}

TEST_CASE("magnetic lock step: each batch's hits are the scalar search's, bit for bit, in every flat table") {
  // Cyclotron radii 10, 2, 0.3 and 0.05 (speed 1), turning either way.
  for (const auto& [shape, table] : flat_tables())
    for (const double omega : {0.1, -0.5, 1 / 0.3, -20.0}) {
      INFO("Omega " << omega);
      check_batches(shape, table, MagneticFlight{omega});
    }
}

TEST_CASE("free lock step: of two walls hit at the same time, the first is kept, as the scalar search keeps it") {
  // From the square's centre along its diagonals: each flight meets two walls at its corner at
  // exactly the same time (the same operations on mirrored numbers).
  const auto table = table_of("square");
  const FreeFlight flight;
  constexpr int lanes = dynamics::FreeLockstepTable::lanes;
  State states[lanes];
  const State* batch[lanes];
  double t_end[lanes];
  for (int i = 0; i < lanes; ++i) {
    const double sx = i & 1 ? 1 : -1, sy = i & 2 ? 1 : -1, speed = 1 + i / 4;
    states[i].x = geometry::Vec2(0.5, 0.5), states[i].v = speed * geometry::Vec2(sx, sy), states[i].t = 0;
    batch[i] = &states[i], t_end[i] = dynamics::never;
  }
  for (const auto& [name, kernel] : kernels<FreeFlight>()) {
    INFO(name << " kernel");
    const dynamics::FreeLockstepTable lockstep(table, flight, kernel);
    dynamics::FlightHit<FreeFlight> hits[lanes];
    lockstep.collisions(batch, t_end, lanes, hits);
    for (int i = 0; i < lanes; ++i) {
      const auto expected = dynamics::collision(table, flight, states[i]);
      REQUIRE(expected.found());
      // Both walls at the corner give this time: the other one's exit time, asked alone.
      int at_that_time = 0;
      for (const auto& w : table.segments()) at_that_time += flight.exit_time(states[i], w, dynamics::never) == expected.t;
      CHECK(at_that_time == 2);
      CHECK(same_hit(hits[i], expected));
    }
  }
}

TEST_CASE("free lock step: the kernel itself finds the hits on elliptic arcs, at the scalar search's times") {
  for (const char* shape : {"ellipse", "elliptic-stadium"}) {
    const auto table = table_of(shape);
    const auto states = states_along_orbits(table, FreeFlight{}, 4, 400);
    const auto walls = dynamics::free_lanes::walls_of(table);
    REQUIRE(walls.ellipse_count == int(table.elliptic_arcs().size()));
    for (const auto& [name, kernel] : kernels<FreeFlight>()) {
      INFO(name << " kernel, " << shape);
      const KernelTally tally = tally_kernel(table, FreeFlight{}, walls, kernel, states);
      CHECK(tally.mismatches == 0);
      CHECK(tally.handed_back == 0);  // (no grazing flight among these)
      CHECK(tally.on_kind[dynamics::wall_kind::elliptic_arc] > int(states.size()) / 4);
    }
  }
}

TEST_CASE("lock step: tables with a grid, or too many walls of a kind, or no kernel, are left to the scalar search (meshes walk together)") {
  const auto wavy = table_of("wavy-1200");
  REQUIRE(wavy.grid() != nullptr);
  for (const auto& [name, kernel] : kernels<FreeFlight>()) CHECK_FALSE(dynamics::FreeLockstepTable(wavy, FreeFlight{}, kernel).usable());
  for (const auto& [name, kernel] : kernels<MagneticFlight>())
    CHECK_FALSE(dynamics::MagneticLockstepTable(wavy, MagneticFlight{1}, kernel).usable());
  // BILLIARDS_SIMD=scalar
  CHECK_FALSE(dynamics::FreeLockstepTable(table_of("clover"), FreeFlight{}, nullptr).usable());
  CHECK_FALSE(dynamics::MagneticLockstepTable(table_of("clover"), MagneticFlight{1}, nullptr).usable());
  // 3-D: 25 balls; a mesh walks its flights together with any kernel or none.
  const auto prism = geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/l-prism.yaml");
  const dynamics::Table3 mesh(prism.region);
  REQUIRE_FALSE(mesh.triangles().empty());
  std::string balls = "name: balls\ndimension: 3\nboundary:\n  box: {min: [0, 0, 0], max: [5, 5, 1]}\nholes:\n";
  for (int k = 0; k < 25; ++k)
    balls += "  - ball: {center: [" + std::to_string(0.5 + k % 5) + ", " + std::to_string(0.5 + k / 5) + ", 0.5], radius: 0.2}\n";
  const auto many = geometry3::parse_shape3(balls, "balls");
  const dynamics::Table3 crowded(many.region);
  REQUIRE(crowded.spheres().size() == 25);
  for (const auto& [name, kernel] : kernels<FreeFlight3>()) {
    CHECK(dynamics::FreeLockstepTable3(mesh, FreeFlight3{}, kernel).usable());
    CHECK_FALSE(dynamics::FreeLockstepTable3(crowded, FreeFlight3{}, kernel).usable());
  }
  const auto sinai3 = geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/sinai3.yaml");
  CHECK_FALSE(dynamics::FreeLockstepTable3(dynamics::Table3(sinai3.region), FreeFlight3{}, nullptr).usable());
  CHECK(dynamics::FreeLockstepTable3(mesh, FreeFlight3{}, nullptr).usable());
}

TEST_CASE("free lock step: particles kept in the lanes across their bounces equal simulate particle by particle, for every target's propagator") {
  // Records sparse and dense (taken in the lanes, or by the scalar code in a cell a wall comes
  // near); segments, arcs, elliptic arcs, a disk's hole, reflex and convex corners.
  std::vector<double> dense;
  for (double t = 0; t < 60; t += 0.37) dense.push_back(t);
  for (const char* shape : {"clover", "stadium", "sinai", "mushroom", "elliptic-stadium", "annulus", "l-room", "square"})
    for (const auto& times : {std::vector<double>{0, 0.5, 10, 200}, dense}) {
      const auto table = table_of(shape);
      dynamics::RunOptions opt;
      opt.record_times = times;
      INFO(shape << ", " << times.size() << " record times");
      for (const auto& t : dynamics::simd::runnable_targets()) {
        INFO(t.name << " kernel and propagator");
        const dynamics::FreeLockstepTable lockstep(table, FreeFlight{}, dynamics::free_lanes::kernel_of(t.bit),
                                                   dynamics::free_lanes::propagator_of(t.bit));
        CHECK(lockstep.propagates() == (dynamics::free_lanes::propagator_of(t.bit) != nullptr));
        check_ensemble_equals_simulate(lockstep, table, FreeFlight{}, opt, 40);
      }
    }
}

TEST_CASE("free lock step: a particle outside the table escapes at its record in the lanes as in simulate") {
  // One particle in three starts in the Sinai table's disk: the lanes' cells there are not
  // inside, so its record at t = 0 goes to the scalar code's point-in-region test, which
  // catches it; the others record in the lanes, in cells inside or near a wall.
  const auto table = table_of("sinai");
  const auto microcanonical = dynamics::microcanonical(table, FreeFlight{}, 1.0, 2021);
  const auto initial = [&](std::size_t i) {
    if (i % 3 != 0) return microcanonical(i);
    const double a = 0.7 * double(i);
    State s;
    s.x = 0.1 * dynamics::Vec2(std::cos(a), std::sin(a)), s.v = dynamics::Vec2(std::cos(2 * a), std::sin(2 * a)), s.t = 0;
    return s;
  };
  dynamics::RunOptions opt;
  for (double t = 0; t < 30; t += 0.37) opt.record_times.push_back(t);
  std::vector<double> energies(opt.record_times.size());
  CHECK(dynamics::simulate(table, FreeFlight{}, initial(0), opt, energies.data()).escaped);
  CHECK_FALSE(dynamics::simulate(table, FreeFlight{}, initial(1), opt, energies.data()).escaped);
  for (const auto& t : dynamics::simd::runnable_targets()) {
    INFO(t.name << " kernel and propagator");
    check_ensemble_equals_simulate(dynamics::FreeLockstepTable(table, FreeFlight{}, dynamics::free_lanes::kernel_of(t.bit),
                                                               dynamics::free_lanes::propagator_of(t.bit)),
                                   table, FreeFlight{}, opt, 40, initial);
  }
}

TEST_CASE("lock step: free and magnetic ensembles equal simulate particle by particle, for every target and 1, 2 and 3 threads") {
  for (const char* shape : {"clover", "mushroom", "elliptic-stadium"})
    for (const bool verify : {false, true}) {
      const auto table = table_of(shape);
      dynamics::RunOptions opt;
      opt.record_times = {0, 0.5, 10, 200};
      opt.verify_every_flight = verify;
      INFO(shape << (verify ? ", every flight verified" : ""));
      for (const auto& [name, kernel] : kernels<FreeFlight>()) {
        INFO(name << " kernel");
        check_ensemble_equals_simulate(dynamics::FreeLockstepTable(table, FreeFlight{}, kernel), table, FreeFlight{}, opt, 40);
      }
      for (const double omega : {0.1, -3.0})
        for (const auto& [name, kernel] : kernels<MagneticFlight>()) {
          INFO(name << " kernel, Omega " << omega);
          const MagneticFlight flight{omega};
          check_ensemble_equals_simulate(dynamics::MagneticLockstepTable(table, flight, kernel), table, flight, opt, 40);
        }
    }
  auto tables3 = sphere_and_plane_tables();
  for (auto& t : mesh_tables())
    if (t->name != "bumpy-100k") tables3.push_back(std::move(t));
  for (const auto& t : tables3)
    for (const bool verify : {false, true}) {
      dynamics::RunOptions opt;
      opt.record_times = {0, 0.5, 10, 100};
      opt.verify_every_flight = verify;
      INFO(t->name << (verify ? ", every flight verified" : ""));
      for (const auto& [name, kernel] : kernels<FreeFlight3>()) {
        INFO(name << " kernel");
        check_ensemble_equals_simulate(dynamics::FreeLockstepTable3(t->table, FreeFlight3{}, kernel), t->table, FreeFlight3{}, opt, 40);
      }
    }
}
