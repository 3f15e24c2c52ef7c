// Poincaré sections of curved flights and of 3-D tables (analysis/boundary_map.hpp's
// line_section): the crossings of a parabola with a line against the quadratic's closed-form
// roots; the crossings of driven flights (2-D and 3-D) on the section and as many as a fine
// brute-force scan of each flight finds; the stroboscopic section in 3-D against states found
// by a collision search with the strobe time as its horizon; `billiard bmap --section` and
// `--strobe` in 3-D.
#include "cli_helpers.hpp"
#include "phase_space_helpers.hpp"

#include "billiards/analysis/boundary_map.hpp"
#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

using namespace billiards;

namespace {

double at(const analysis::SectionRows& r, std::size_t i, std::size_t j) { return r.rows[i * r.columns + j]; }

/// The flights of particle `initial` over `collisions` bounces: (state after a bounce, time of
/// the next hit).
template <class Table, class Flight>
std::vector<std::pair<typename Flight::State, double>> flights_of(const Table& table, const Flight& flight,
                                                                   typename Flight::State s, std::size_t collisions) {
  std::vector<std::pair<typename Flight::State, double>> out;
  dynamics::evolve(table, flight, s, collisions, [&](const auto& hit, const auto& bounced) {
    out.emplace_back(s, double(hit.t));
    s = bounced;
  });
  return out;
}

/// Upward crossings of n·x = c by a fine scan of each flight (2000 steps), counted.
template <class Flight, class Section>
std::size_t brute_force_crossings(const Flight& flight, const typename Flight::State& s, double t_end,
                                  const Section& section) {
  std::size_t n = 0;
  constexpr int steps = 2000;
  double previous = section.normal.dot(s.x) - section.offset;
  for (int k = 1; k <= steps; ++k) {
    const double f = section.normal.dot(flight.advance(s, s.t + (t_end - s.t) * k / steps).x) - section.offset;
    n += previous < 0 && f >= 0;
    previous = f;
  }
  return n;
}

}  // namespace

TEST_CASE("a parabola's crossings of a line: the section against the quadratic's closed-form roots") {
  const auto sh = bundled_shape("sinai.yaml");
  const dynamics::Table table(sh.region);
  const dynamics::ConstantForceFlight gravity{geometry::Vec2(0.3, -2.0)};
  const geometry::Vec2 n = geometry::Vec2(-0.3, 1).normalized();
  const analysis::SectionLine line{n, 0.35 * n.y()};  // y = 0.3 x + 0.35
  const auto initial = dynamics::microcanonical(table, dynamics::FreeFlight{}, 1.0, 3);
  const std::size_t particles = 6, collisions = 400;
  const auto r = analysis::line_section(table, gravity, line, initial, particles, collisions, 2);
  std::vector<double> expected_t, expected_u;
  for (std::size_t i = 0; i < particles; ++i)
    for (const auto& [s, t_hit] : flights_of(table, gravity, initial(i), collisions)) {
      // n·x(τ) − c = A τ²/2 + B τ + C with A = n·a, B = n·v, C = n·x − c; upward: B + A τ > 0.
      const double A = n.dot(gravity.accel), B = n.dot(s.v), C = n.dot(s.x) - line.offset;
      const double disc = B * B - 2 * A * C;
      if (disc < 0) continue;
      const double q = -(B + std::copysign(std::sqrt(disc), B));  // (the stable pair of roots)
      std::vector<double> roots{q / A, 2 * C / q};
      std::sort(roots.begin(), roots.end());
      for (const double tau : roots)
        if (tau > 0 && s.t + tau <= t_hit && B + A * tau > 0) {
          expected_t.push_back(s.t + tau);
          const auto x = s.x + s.v * tau + 0.5 * gravity.accel * tau * tau;
          expected_u.push_back(geometry::Vec2(-n.y(), n.x()).dot(x));
        }
    }
  REQUIRE(expected_t.size() > 100);
  REQUIRE(r.row_count() == expected_t.size());
  for (std::size_t i = 0; i < r.row_count(); ++i) {
    CHECK(at(r, i, 4) == Approx(expected_t[i]).epsilon(1e-12));
    CHECK(at(r, i, 2) == Approx(expected_u[i]).margin(1e-10));
  }
}

/// The section of 3 particles x 300 bounces, checked to hold as many crossings as a fine scan
/// of each flight finds.
template <class Table, class Flight, class Section, class Initial>
analysis::SectionRows section_against_scan(const Table& table, const Flight& flight, const Section& section,
                                           const Initial& initial) {
  const auto r = analysis::line_section(table, flight, section, initial, 3, 300, 2);
  std::size_t expected = 0;
  for (std::size_t i = 0; i < 3; ++i)
    for (const auto& [s, t_hit] : flights_of(table, flight, initial(i), 300))
      expected += brute_force_crossings(flight, s, t_hit, section);
  REQUIRE(expected > 20);
  CHECK(r.row_count() == expected);
  return r;
}

TEST_CASE("a section's crossings do not depend on when the orbit starts: found on each flight's own clock") {
  // The same orbit started at t = 1e8 + 1/8 instead of 0 crosses the section at the same
  // points with the same velocities, bit for bit, at times T later (to ulp(T) = 1.5e-8, the
  // rounding of the absolute time reported).  Crossing times searched in absolute time would
  // be rounded to ulp(1e8) before the flight is advanced to them, moving each point by ~1e-8.
  const auto sh = bundled_shape("sinai.yaml");
  const dynamics::Table table(sh.region);
  const dynamics::ConstantForceFlight gravity{geometry::Vec2(0.3, -2.0)};
  const analysis::SectionLine line{geometry::Vec2(0, 1), 0.1};
  const double T = 1e8 + 0.125;
  dynamics::State s;
  s.x = geometry::Vec2(0.1, 0.2);
  s.v = geometry::Vec2(std::cos(0.7), std::sin(0.7));
  auto late = s;
  late.t = T;
  auto section = [&](const auto& flight, const dynamics::State& start) {
    return analysis::line_section(table, flight, line, [&](std::size_t) { return start; }, 2, 500, 1);
  };
  auto check = [&](const auto& flight) {
    const auto a = section(flight, s), b = section(flight, late);
    REQUIRE(a.row_count() > 50);
    REQUIRE(b.row_count() == a.row_count());
    for (std::size_t i = 0; i < a.row_count(); ++i) {
      for (const std::size_t j : {2, 3, 5}) CHECK(at(b, i, j) == at(a, i, j));  // u, p, energy
      CHECK(std::abs((at(b, i, 4) - T) - at(a, i, 4)) <= 1.5e-8);
    }
  };
  check(dynamics::FreeFlight{});
  check(gravity);
}

TEST_CASE("driven flights' crossings lie on the section, as many as a fine scan of each flight finds") {
  const auto scene = bundled_scene("clover-driven.yaml", 3);
  const dynamics::Table table(scene.shape<2>().region);
  const dynamics::PeriodicDriveFlight drive{geometry::Vec2(6, 2), 5.0, 0.3};  // slow: curved flights
  const auto initial = [&](std::size_t i) {
    return drive.start(dynamics::microcanonical(table, dynamics::FreeFlight{}, 1.0, 5)(i));
  };
  const auto r = section_against_scan(table, drive, analysis::SectionLine{geometry::Vec2(0, 1), 0.2}, initial);
  for (std::size_t i = 0; i < r.row_count(); ++i)  // (u = −x on "y = 0.2")
    CHECK(table.contains(geometry::Vec2(-at(r, i, 2), 0.2)));

  const auto sh = geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/sinai3.yaml");
  const dynamics::Table3 table3(sh.region);
  const dynamics::PeriodicDriveFlight3 drive3{geometry3::Vec3(2, 1, 3), 4.0, 0.1};
  const auto initial3 = [&](std::size_t i) {
    return drive3.start(dynamics::microcanonical(table3, dynamics::FreeFlight3{}, 1.0, 5)(i));
  };
  const auto r3 = section_against_scan(table3, drive3, analysis::SectionPlane{geometry3::Vec3(0, 0, 1), 0.1}, initial3);
  for (std::size_t i = 0; i < r3.row_count(); ++i) {
    // (u1, u2) = (x, y) on "z = 0.1"; the point lies in the table.
    CHECK(table3.contains(geometry3::Vec3(at(r3, i, 2), at(r3, i, 3), 0.1)));
    CHECK(std::hypot(at(r3, i, 4), at(r3, i, 5)) <= 1 + 1e-12);
  }
}

TEST_CASE("3-D stroboscopic section: the states at the drive phase asked for, as a search up to each time finds") {
  const auto scene = bundled_scene("sinai3-driven.yaml", 3);
  const dynamics::Table3 table(scene.shape<3>().region);
  const dynamics::PeriodicDriveFlight3 flight{scene.force.amplitude / scene.mass, scene.force.omega, scene.force.phase};
  const auto initial = dynamics::initial_states(scene, table, flight);
  const double phase = 1.0;
  // 30 collisions a particle: the search below asks for each strobe time as its horizon, which
  // moves its roots by rounding; the chaotic table amplifies that past 1e-9 after ~40.
  const auto r = analysis::stroboscopic_section(table, flight, phase, initial, 3, 30, 2, scene.mass);
  REQUIRE(r.columns == 10);
  REQUIRE(r.row_count() > 6);
  std::size_t particle = r.row_count();  // (none yet)
  auto s = initial(0);
  dynamics::Clock clock;  // (each flight on its own clock, as every run)
  for (std::size_t i = 0; i < r.row_count(); ++i) {
    const double t = at(r, i, 8);
    CHECK(t == Approx((phase - flight.phase0 + 2 * geometry::pi * at(r, i, 1)) / flight.omega).margin(1e-12));
    // Independently: the particle's collisions up to t, searched with t as the horizon.
    if (std::size_t(at(r, i, 0)) != particle) particle = std::size_t(at(r, i, 0)), s = initial(particle), clock = {};
    for (auto hit = dynamics::collision(table, flight, s, clock.until(t)); hit.found();
         hit = dynamics::collision(table, flight, s, clock.until(t))) {
      dynamics::bounce(flight, s, hit);
      dynamics::restart_clock(flight, s, clock);
    }
    const auto there = flight.advance(s, clock.until(t));
    const Eigen::Vector3d x(at(r, i, 2), at(r, i, 3), at(r, i, 4)), v(at(r, i, 5), at(r, i, 6), at(r, i, 7));
    CHECK((x - there.x).norm() < 1e-9);
    CHECK((v - there.v).norm() < 1e-9 * (1 + v.norm()));
    CHECK(at(r, i, 9) == Approx(0.5 * scene.mass * v.squaredNorm()));
  }
}

TEST_CASE("billiard bmap in 3-D: a plane section, the same for 1 and 2 threads; no boundary map without one") {
  const auto dir = scratch_root() / "bmap3";
  const std::string cmd = "bmap shapes/3d/sinai3.yaml --section \"z = 0\" --particles 3 --collisions 400 --quiet ";
  const auto one = billiard(cmd + "--threads 1 --out " + (dir / "t1").string());
  const auto two = billiard(cmd + "--threads 2 --out " + (dir / "t2").string());
  INFO(one.output);
  REQUIRE(one.status == 0);
  REQUIRE(two.status == 0);
  CHECK(read_file(dir / "t1" / "section3.csv") == read_file(dir / "t2" / "section3.csv"));
  CHECK(read_file(dir / "t1" / "section3.csv").rfind("particle,crossing,u1,u2,p1,p2,t,energy\n", 0) == 0);
  CHECK(std::filesystem::exists(dir / "t1" / "section3.png"));
  const auto r = billiard("bmap shapes/3d/sinai3.yaml --out " + (dir / "bad").string());
  CHECK(r.status == 2);
  CHECK(r.output.find("are 2-D only: for a 3-D table give a plane section, such as --section \"z = 0\"") !=
        std::string::npos);
  CHECK(!std::filesystem::exists(dir / "bad"));
  const auto strobe = billiard("bmap scenes/sinai3-driven.yaml --strobe pi/2 --particles 2 --collisions 300 --quiet --out " +
                               (dir / "strobe").string());
  INFO(strobe.output);
  REQUIRE(strobe.status == 0);
  CHECK(read_file(dir / "strobe" / "strobe3.csv").rfind("particle,k,x,y,z,vx,vy,vz,t,energy\n", 0) == 0);
  CHECK(std::filesystem::exists(dir / "strobe" / "strobe3.png"));
}
