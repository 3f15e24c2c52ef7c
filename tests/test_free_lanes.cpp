// Straight flights searched in lock step (free_lockstep.hpp) against the scalar search, for
// every SIMD target this processor runs: the same hits, bit for bit, from states along orbits
// (each starting on the wall it has just left) with and without horizons, in every flat table
// (segments, focusing and dispersing arcs, holes, elliptic arcs) and in one with more walls
// than a vector has lanes; and ensembles equal to `simulate`, particle by particle, for any
// thread count.
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/free_lockstep.hpp"
#include "billiards/geometry.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace billiards;
using dynamics::FreeFlight;
using dynamics::State;
using dynamics::Table;

namespace {

struct TargetKernel {
  const char* name;
  dynamics::free_lanes::Kernel kernel;
};
/// The kernel of each SIMD target this processor runs.
std::vector<TargetKernel> kernels() {
  std::vector<TargetKernel> all;
  for (const auto& t : dynamics::simd::runnable_targets()) all.push_back({t.name, dynamics::free_lanes::kernel_of(t.bit)});
  return all;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_hit(const dynamics::FlightHit<FreeFlight>& a, const dynamics::FlightHit<FreeFlight>& b) {
  if (a.wall != b.wall || !same_bits(a.t, b.t)) return false;
  return !a.found() || (same_bits(a.point.x(), b.point.x()) && same_bits(a.point.y(), b.point.y()) &&
                        same_bits(a.normal.x(), b.normal.x()) && same_bits(a.normal.y(), b.normal.y()) &&
                        same_bits(a.state.x.x(), b.state.x.x()) && same_bits(a.state.x.y(), b.state.x.y()) &&
                        same_bits(a.state.v.x(), b.state.v.x()) && same_bits(a.state.v.y(), b.state.v.y()) &&
                        same_bits(a.state.t, b.state.t));
}

Table table_of(const std::string& shape) {
  return Table(geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + shape + ".yaml").region);
}

/// A 20-gon with three circular holes: 20 segments and 3 arcs.
Table twenty_gon() {
  std::string text = "name: twenty-gon\nboundary:\n  polygon: [";
  for (int k = 0; k < 20; ++k)
    text += (k ? ", [" : "[") + std::to_string(std::cos(2 * geometry::pi * k / 20)) + ", " +
            std::to_string(std::sin(2 * geometry::pi * k / 20)) + "]";
  text += R"(]
holes:
  - circle: {center: [0.3, 0], radius: 0.15}
  - circle: {center: [-0.3, 0.3], radius: 0.1}
  - circle: {center: [-0.2, -0.4], radius: 0.2}
)";
  return Table(geometry::parse_shape(text, "twenty-gon").region);
}

/// Fresh microcanonical starts and the states after each bounce of their orbits, each flight on
/// its own clock, as in the ensembles.
std::vector<State> states_along_orbits(const Table& table, int particles, int bounces) {
  const FreeFlight flight;
  std::vector<State> states;
  for (int p = 0; p < particles; ++p) {
    dynamics::ParticleRng rng(97, std::uint64_t(p));
    State s = flight.start(dynamics::sample_microcanonical(table, 1.0, rng));
    const double v2 = s.v.squaredNorm();
    dynamics::Clock clock;
    states.push_back(s);
    for (int k = 0; k < bounces; ++k) {
      const auto hit = dynamics::collision(table, flight, s);
      REQUIRE(hit.found());
      dynamics::bounce(flight, s, hit);
      dynamics::restore_speed(s.v, v2);
      dynamics::restart_clock(flight, s, clock);
      states.push_back(s);
    }
  }
  return states;
}

}  // namespace

TEST_CASE("free lock step: each batch's hits are the scalar search's, bit for bit, in every flat table") {
  // Horizons, in units of the table's size: none, and horizons that end some flights before
  // their walls (found() false).
  const double horizons[] = {dynamics::never, 1e-3, 0.7, 3};
  std::vector<std::pair<std::string, Table>> tables;
  for (const char* shape : {"clover", "stadium", "sinai", "mushroom", "square", "circle", "triangle", "l-room",
                            "annulus", "ellipse", "sinai-ellipse", "elliptic-stadium"})
    tables.emplace_back(shape, table_of(shape));
  tables.emplace_back("twenty-gon", twenty_gon());
  REQUIRE(tables.back().second.segments().size() == 20);
  const FreeFlight flight;
  constexpr int lanes = dynamics::FreeLockstepTable::lanes;
  for (const auto& [shape, table] : tables) {
    const auto states = states_along_orbits(table, 6, 2000);
    const double size = (table.hi() - table.lo()).norm();
    for (const auto& [name, kernel] : kernels()) {
      const dynamics::FreeLockstepTable lockstep(table, flight, kernel);
      REQUIRE(lockstep.usable());
      int found = 0, mismatches = 0;
      // Batches of every size 1..16, the states taken in turn; each state's horizon cycles.
      std::size_t next = 0;
      for (int round = 0; next < states.size(); ++round) {
        const int n = std::min<int>(1 + round % lanes, int(states.size() - next));
        const State* batch[lanes];
        double t_end[lanes];
        for (int i = 0; i < n; ++i) {
          batch[i] = &states[next + std::size_t(i)];
          const double h = horizons[(next + std::size_t(i)) % 4];
          t_end[i] = h == dynamics::never ? h : batch[i]->t + h * size;
        }
        dynamics::FlightHit<FreeFlight> hits[lanes];
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
      INFO(name << " kernel, " << shape);
      CHECK(mismatches == 0);
      CHECK(found > int(states.size()) / 2);  // most flights end on a wall...
      CHECK(found < int(states.size()));      // ...and some at their short horizon
    }
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
  for (const auto& [name, kernel] : kernels()) {
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

TEST_CASE("free lock step: tables with a grid, or no kernel, are left to the scalar search") {
  const FreeFlight flight;
  const auto wavy = table_of("wavy-1200");
  REQUIRE(wavy.grid() != nullptr);
  for (const auto& [name, kernel] : kernels()) CHECK_FALSE(dynamics::FreeLockstepTable(wavy, flight, kernel).usable());
  CHECK_FALSE(dynamics::FreeLockstepTable(table_of("clover"), flight, nullptr).usable());  // BILLIARDS_SIMD=scalar
}

TEST_CASE("free lock step: ensembles equal simulate particle by particle, for every target and 1, 2 and 3 threads") {
  const FreeFlight flight;
  for (const char* shape : {"clover", "mushroom", "elliptic-stadium"})
    for (const bool verify : {false, true}) {
      const auto table = table_of(shape);
      dynamics::RunOptions opt;
      opt.record_times = {0, 0.5, 10, 200};
      opt.verify_every_flight = verify;
      const std::size_t n = 40, m = opt.record_times.size();
      const auto initial = dynamics::microcanonical(table, flight, 1.0, 2021);
      std::vector<double> expected(n * m);
      std::vector<dynamics::ParticleLog> logs(n);
      for (std::size_t i = 0; i < n; ++i) logs[i] = dynamics::simulate(table, flight, initial(i), opt, &expected[i * m]);
      for (const auto& [name, kernel] : kernels())
        for (const int threads : {1, 2, 3}) {
          INFO(name << " kernel, " << shape << (verify ? ", every flight verified, " : ", ") << threads << " threads");
          const dynamics::FreeLockstepTable lockstep(table, flight, kernel);
          dynamics::EnsembleResult res;
          res.energies.resize(n * m);
          res.logs.resize(n);
          dynamics::run_in_lockstep(lockstep, table, flight, initial, opt, 0, n, threads, res, {});
          CHECK(std::memcmp(res.energies.data(), expected.data(), n * m * sizeof(double)) == 0);
          for (std::size_t i = 0; i < n; ++i) {
            CHECK(res.logs[i].collisions == logs[i].collisions);
            CHECK(res.logs[i].escaped == logs[i].escaped);
          }
        }
    }
}
