// Forced flights: closed forms against MPFR, certified exit times against brute force, and the
// paper's driven clover against g1 Δt and g2 Δt.
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <boost/multiprecision/mpfr.hpp>
#include "brute_force_root.hpp"
#include "many_walls.hpp"

#include <catch2/catch.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

using namespace billiards;
using dynamics::DrivenState;
using dynamics::PeriodicDriveFlight;
using dynamics::Vec2;
using Real = boost::multiprecision::mpfr_float_100;

namespace {

const double pi = geometry::pi;

/// Appendix B's x(t), v(t) from (x0, v0) at t = 0, phase θ = ω t + φ, in the scalar type T
/// (100-bit MPFR for references, long double for fast scans).
template <class T>
std::pair<std::array<T, 2>, std::array<T, 2>> reference(const Vec2& x0, const Vec2& v0, const Vec2& A,
                                                        double omega, double phase, const T& t) {
  using std::cos;
  using std::sin;
  const T w = omega, th0 = T(phase), th = w * t + phase;
  std::array<T, 2> x, v;
  for (int i = 0; i < 2; ++i) {
    const T a = A[i];
    v[i] = v0[i] + a / w * (sin(th) - sin(th0));
    x[i] = x0[i] + (v0[i] - a / w * sin(th0)) * t - a / (w * w) * (cos(th) - cos(th0));
  }
  return {x, v};
}

/// An ensemble's energies at 41 record times against each particle's own flight: its bounces
/// (evolve), and the last one before a record time advanced there with the particle's own
/// phase, its sine and cosine.  The ensemble records from the drive's sine at each record time,
/// computed once for every particle (RecordMarks).  Records before the fourth bounce only:
/// `evolve` searches without the ensemble's horizon, and chaos amplifies their last-bit
/// differences after a few bounces (5e-14 after the third, 3e-10 after ten).
/// A run that checks every flight's midpoint records four record times at a time (Trajectory's
/// record_marks_until): its energies must be those recorded one at a time, to the bit.
template <class TableT, class Flight>
void check_records_against_own_flights(const TableT& table, const Flight& flight) {
  dynamics::RunOptions opt;
  for (int k = 0; k <= 40; ++k) opt.record_times.push_back(0.29 * k);
  const std::size_t n = 40, m = opt.record_times.size();
  const auto initial = dynamics::microcanonical(table, flight, 1.0, 7);
  const auto res = dynamics::run_ensemble(table, flight, initial, opt, n, 1);
  REQUIRE(res.escapes() == 0);
  opt.verify_every_flight = true;
  CHECK(dynamics::run_ensemble(table, flight, initial, opt, n, 1).energies == res.energies);
  int checked = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<typename Flight::State> bounces{initial(i)};
    dynamics::evolve(table, flight, initial(i), 3, [&](const auto&, const auto& s) { bounces.push_back(s); });
    REQUIRE(bounces.size() == 4);
    for (std::size_t k = 0; k < m && opt.record_times[k] < bounces.back().t; ++k, ++checked) {
      const double t = opt.record_times[k];
      const auto last = std::upper_bound(bounces.begin(), bounces.end(), t, [](double t, const auto& s) { return t < s.t; });
      const double expected = dynamics::kinetic_energy(flight.advance(*std::prev(last), t), 1.0);
      CHECK(res.energies[i * m + k] == Approx(expected).epsilon(1e-12));
    }
  }
  CHECK(checked > 100);
}

}  // namespace

TEST_CASE("energies recorded at many times equal each particle's own flight advanced there") {
  // The clover (the lock-step search where the processor has it), the stadium, the 3-D Sinai.
  for (const char* name : {"clover", "stadium"}) {
    const dynamics::Table table(geometry::load_shape(fmt::format("{}/shapes/{}.yaml", BILLIARDS_SOURCE_DIR, name)).region);
    check_records_against_own_flights(table, PeriodicDriveFlight{Vec2(7, 7), 40 * pi, 0.3});
  }
  const auto sinai3 = geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/sinai3.yaml");  // (Table3 refers to it)
  const dynamics::Table3 table(sinai3.region);
  check_records_against_own_flights(table, dynamics::PeriodicDriveFlight3{dynamics::Vec3(6, 3, 5), 40 * pi, 0.3});
}

TEST_CASE("the closed-form flight matches MPFR, with the phase reduced at large omega t") {
  const PeriodicDriveFlight flight{Vec2(7, -3), 2560 * pi, 0.3};
  dynamics::State s0;
  s0.x = Vec2(0.1, 0.2);
  s0.v = Vec2(0.6, -0.8);
  const DrivenState s = flight.start(s0);
  for (const double t : {0.37, 12.5, 1e4}) {
    const DrivenState r = flight.advance(s, t);
    const auto [x, v] = reference<Real>(s0.x, s0.v, flight.accel, flight.omega, flight.phase0, Real(t));
    for (int i = 0; i < 2; ++i) {
      CHECK(std::abs(r.v[i] - static_cast<double>(v[i])) < 1e-13);
      // x grows like |v| t: compare relative to it.
      CHECK(std::abs(r.x[i] - static_cast<double>(x[i])) < 1e-13 * (1 + t));
    }
  }
}

TEST_CASE("zero force gives exactly the free billiard") {
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
  const dynamics::Table table(shape.region);
  const PeriodicDriveFlight driven{Vec2(0, 0), 40 * pi, 0};
  const dynamics::ConstantForceFlight constant{Vec2(0, 0)};
  dynamics::ParticleRng rng(4, 0);
  dynamics::State free = dynamics::sample_microcanonical(table, 1.0, rng);
  for (int k = 0; k < 500; ++k) {
    const auto hf = dynamics::collision(table, dynamics::FreeFlight{}, free, 1e9);
    const auto hd = dynamics::collision(table, driven, driven.start(free), 1e9);
    const auto hc = dynamics::collision(table, constant, free, 1e9);
    REQUIRE(hd.wall == hf.wall);
    REQUIRE(hc.wall == hf.wall);
    REQUIRE(std::abs(hd.t - hf.t) <= 1e-12 * (1 + hf.t));
    REQUIRE(std::abs(hc.t - hf.t) <= 1e-12 * (1 + hf.t));
    dynamics::bounce(dynamics::FreeFlight{}, free, hf);
  }
}

TEST_CASE("certified exit times equal a brute-force MPFR root scan") {
  // A long straight wall y = 1 (region below), a focusing unit circle and a dispersing circle.
  const dynamics::SegmentWall line(geometry::Segment{Vec2(10, 1), Vec2(-10, 1)});
  geometry::Arc outer{Vec2(0, 0), 1.0, 0, 2 * pi, Vec2(1, 0), Vec2(1, 0)};
  geometry::Arc scatterer{Vec2(0, 0), 0.5, 0, -2 * pi, Vec2(0.5, 0), Vec2(0.5, 0)};
  const dynamics::ArcWall focusing(outer), dispersing(scatterer);
  dynamics::ParticleRng rng(17, 0);
  int compared = 0;
  for (const double omega : {2 * pi, 40 * pi, 2560 * pi}) {
    for (int k = 0; k < 10; ++k) {
      const double angle = 2 * pi * rng.uniform();
      const PeriodicDriveFlight flight{10 * Vec2(std::cos(angle), std::sin(angle)), omega, 2 * pi * rng.uniform()};
      const double dir = 2 * pi * rng.uniform();
      dynamics::State s0;
      s0.v = Vec2(std::cos(dir), std::sin(dir));
      const double h = std::min(2 * pi / omega / 256, 2e-3);
      auto check = [&](const auto& wall, auto f, const char* what) {
        INFO(what << " omega " << omega << " case " << k);
        const double expected = brute_force::first_upward_root(f, h, 2.0);
        const double got = flight.exit_time(flight.start(s0), wall, 2.0);
        if (expected < 0) {
          CHECK(got == dynamics::never);
        } else {
          CHECK(std::abs(got - expected) <= 1e-10 * (1 + expected));
          ++compared;
        }
      };
      auto position = [&]<class T>(const T& t) { return reference<T>(s0.x, s0.v, flight.accel, omega, flight.phase0, t).first; };
      s0.x = Vec2(0.4 * rng.uniform() - 0.2, 0.6 * rng.uniform() - 0.3);
      check(line, [&]<class T>(const T& t) -> T { return position(t)[1] - 1; }, "line");
      check(focusing, [&]<class T>(const T& t) -> T { auto x = position(t); return x[0] * x[0] + x[1] * x[1] - 1; }, "focusing");
      // Start outside the scatterer, aimed near it: some hit, some graze, some miss.
      s0.x = Vec2(-0.9, 0.5 + 0.2 * rng.uniform() - 0.1);
      s0.v = Vec2(1, -0.55 + 0.1 * rng.uniform());
      check(dispersing, [&]<class T>(const T& t) -> T { auto x = position(t); return T(0.25) - x[0] * x[0] - x[1] * x[1]; },
            "dispersing");
    }
  }
  CHECK(compared > 40);
}

TEST_CASE("collisions in tables with partial walls equal a brute-force scan over every wall") {
  // Window culling passes whole windows where the particle cannot be in a wall's span; the
  // first in-span outward crossing over all walls, found by fine sampling and bisection in long
  // double, must still be the collision found, in the clover (arcs) and the L-room (segments).
  for (const char* name : {"clover", "l-room"}) {
    const auto region = geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml").region;
    const dynamics::Table table(region);
    int compared = 0;
    for (const double omega : {2 * pi, 40 * pi, 320 * pi}) {
      for (std::uint64_t k = 0; k < 8; ++k) {
        dynamics::ParticleRng rng(23, k);
        const double angle = 2 * pi * rng.uniform();
        const PeriodicDriveFlight flight{10 * Vec2(std::cos(angle), std::sin(angle)), omega, 2 * pi * rng.uniform()};
        const dynamics::State s0 = dynamics::sample_microcanonical(table, 1.0, rng);
        const double t_max = 3, h = std::min(2 * pi / omega / 64, 1e-3);
        auto position = [&](long double t) {
          return reference<long double>(s0.x, s0.v, flight.accel, omega, flight.phase0, t).first;
        };
        // How far beyond wall w the point is, and whether it lies in the wall's span.
        auto beyond = [&](const dynamics::WallId& w, const std::array<long double, 2>& x) -> long double {
          if (w.kind == dynamics::wall_kind::segment) {
            const auto& sw = table.segments()[w.index];
            return sw.normal.x() * (x[0] - sw.a.x()) + sw.normal.y() * (x[1] - sw.a.y());
          }
          const auto& aw = table.arcs()[w.index];
          const long double r = std::hypot(x[0] - aw.center.x(), x[1] - aw.center.y()) - aw.radius;
          return aw.focusing ? r : -r;
        };
        auto in_span = [&](const dynamics::WallId& w, const std::array<long double, 2>& x) {
          const Vec2 p{double(x[0]), double(x[1])};
          return table.visit(w, [&](const auto& wall) { return wall.within_span(p); });
        };
        double expected = dynamics::never;
        dynamics::WallId expected_wall;
        for (const auto& w : table.wall_ids()) {
          long double before = beyond(w, position(0));
          for (long n = 1; n * h <= std::min(t_max, expected); ++n) {
            const long double t = (long double)n * h, now = beyond(w, position(t));
            if (before < 0 && now > 0) {
              long double a = t - h, b = t;
              for (int i = 0; i < 80; ++i) {
                const long double m = (a + b) / 2;
                (beyond(w, position(m)) > 0 ? b : a) = m;
              }
              if (in_span(w, position(b))) {
                if (double(b) < expected) expected = double(b), expected_wall = w;
                break;
              }
            }
            before = now;
          }
        }
        const auto hit = dynamics::collision(table, flight, flight.start(s0), t_max);
        INFO(name << " omega " << omega << " case " << k);
        CHECK(hit.wall == expected_wall);  // invalid on both sides: no wall within t_max
        if (expected_wall.valid()) {
          CHECK(std::abs(hit.t - expected) <= 1e-9);
          ++compared;
        }
      }
    }
    CHECK(compared >= 20);
  }
}

TEST_CASE("the windows searched in time order find the collision the wall-by-wall scan finds") {
  // collision() searches all walls' windows in the order in which they open, solving windows of
  // certain slope by a bracketed Halley iteration; the wall-by-wall certified scan (checked
  // against MPFR above) must find the same first hit, along trajectories (each flight starts on
  // the wall just bounced off), with and without a horizon, at low and high frequencies.  The
  // state at the hit must carry its phase's sine and cosine.
  // (Elliptic arcs: collision() searches the mapped flight through the unit arc in its windows,
  // the wall-by-wall search scans it: elliptic_exit_time.  Tables of more than
  // scan::windows_group_walls segments and arcs: their windows are searched group by group.
  // Tables of more than scan::windows_in_time_order_walls: collision() tries only the walls
  // listed near the guiding line, cell by cell along it through the table's grid.)
  std::vector<std::pair<std::string, dynamics::Table>> tables;
  for (const char* name : {"clover", "l-room", "mushroom", "sinai", "stadium", "annulus", "sinai-ellipse",
                           "elliptic-stadium", "ellipse"})
    tables.emplace_back(name, geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml").region);
  tables.emplace_back("twenty-gon", twenty_gon());
  tables.emplace_back("gear of 16 around a disk", gear(dynamics::scan::windows_group_walls / 2, true));
  tables.emplace_back("circle of 24 arcs", circle_of_arcs(dynamics::scan::windows_in_time_order_walls));
  tables.emplace_back("wavy-1200", geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/wavy-1200.yaml").region);
  tables.emplace_back("circle of 48 arcs", circle_of_arcs(48));
  tables.emplace_back("gear of 40 around a disk", gear(40, true));
  // (Flights off quivering walls too where the guide is walked through the grid: the free
  // line, within δ of the particle's position relative to the walls.)
  auto compare = [](const std::string& name, const dynamics::Table& table, const auto& flight, std::uint64_t seed) {
    dynamics::ParticleRng rng(31, seed);
    DrivenState s = flight.start(dynamics::sample_microcanonical(table, 1.0, rng));
    int mismatches = 0, bounces = 0;
    for (int k = 0; k < 400; ++k) {
      const double t_end = k % 2 ? s.t + 20 : dynamics::never;
      dynamics::Hit by_wall;
      by_wall.t = t_end;
      for (const auto& w : table.wall_ids()) dynamics::detail::try_wall(table, flight, s, w, by_wall);
      const auto hit = dynamics::collision(table, flight, s, t_end);
      // (Both polish the root to rounding: they agree to 5.5e-16 of 1 + t over these runs.)
      const bool same = hit.wall == by_wall.wall ? std::abs(hit.t - by_wall.t) <= 1e-14 * (1 + std::abs(hit.t))
                                                 : std::abs(hit.t - by_wall.t) <= 1e-12 * (1 + std::abs(hit.t));  // (a joint)
      if (!same) {
        ++mismatches;
        UNSCOPED_INFO(name << " omega " << flight.omega << " bounce " << k << ": wall " << hit.wall << " at " << hit.t
                           << ", wall by wall " << by_wall.wall << " at " << by_wall.t);
      }
      if (!hit.found()) {
        CHECK(t_end != dynamics::never);  // (no wall within the horizon)
        continue;
      }
      // The state at the hit takes the drive's sine and cosine from the root search's last
      // sample, corrected to the hit's phase: as exact as computing them anew.
      const double phase = double(hit.state.phase);
      if (std::abs(hit.state.sin_phase - std::sin(phase)) > 1e-15 || std::abs(hit.state.cos_phase - std::cos(phase)) > 1e-15)
        ++mismatches;
      dynamics::bounce(flight, s, hit);
      ++bounces;
    }
    CHECK(mismatches == 0);
    CHECK(bounces >= 300);
  };
  for (const auto& [name, table] : tables) {
    REQUIRE((table.grid() != nullptr) == (table.wall_count() > std::size_t(dynamics::scan::windows_in_time_order_walls)));
    for (const double omega : {10 * pi, 40 * pi, 320 * pi, 2560 * pi}) {
      const Vec2 force = 10 * Vec2(1, 1) / std::sqrt(2.0);
      compare(name, table, PeriodicDriveFlight{force, omega, 0}, std::uint64_t(omega));
      if (table.grid()) compare(name + " (quivering walls)", table, dynamics::QuiveringWallFlight{force, omega, 0}, std::uint64_t(omega));
    }
  }
}

TEST_CASE("the paper's clover at omega = 320 pi: <dE> and Var(dE) match g1 dt and g2 dt") {
  // Hodson & Jarzynski, Appendix B: m = 1, E0 = 1/2, F = 10 along (1,1)/√2, Δt = 20, and
  // C = (2/m)^{3/2} W/(S λ ω²) with W/S = F²/2 for the clover: g1 = C √E0, g2 = 4 C E0^{3/2}/3.
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
  const auto m = geometry::measures_of(shape.region);
  const double omega = 320 * pi, F = 10, E0 = 0.5, dt = 20;
  const Vec2 force = F / std::sqrt(2.0) * Vec2(1, 1);
  const double C = std::pow(2.0, 1.5) * geometry::wall_integral(m, force) / (m.surface * geometry::mean_free_path(m) * omega * omega);
  REQUIRE(std::abs(C * omega * omega / (F * F) - 0.5419) < 1e-4);
  const double g1 = C * std::sqrt(E0), g2 = 4 * C * std::pow(E0, 1.5) / 3;

  const dynamics::Table table(shape.region);
  const PeriodicDriveFlight flight{force, omega, 0};
  const std::size_t n = 20000;
  dynamics::RunOptions opt;
  opt.record_times = {dt};
  const auto res = dynamics::run_ensemble(table, flight, dynamics::microcanonical(table, flight, 1.0, 2021), opt, n, 2);
  REQUIRE(res.escapes() == 0);
  double mean = 0, m2 = 0, m4 = 0;
  for (double e : res.energies) mean += e - E0;
  mean /= double(n);
  for (double e : res.energies) {
    const double d2 = (e - E0 - mean) * (e - E0 - mean);
    m2 += d2;
    m4 += d2 * d2;
  }
  const double var = m2 / double(n - 1), se_mean = std::sqrt(var / double(n));
  const double se_var = std::sqrt((m4 / double(n) - var * var) / double(n));
  CHECK(std::abs(mean - g1 * dt) < 3 * se_mean);
  CHECK(std::abs(var - g2 * dt) < 3 * se_var);
  CHECK(se_var < 0.02 * g2 * dt);  // resolution: a 6% error in g2 would fail
}
