// The flights' fallback for a wall kind they have no closed form for: the certified scan of the
// wall's gap (walls.hpp's and walls3.hpp's `gap_sample`, flight.hpp's `scanned_exit_time`).
// Called explicitly (the `Scanned` overloads) on the kinds that do have closed forms, it must
// find the same exit times: an independent method for every flight and every wall kind, in
// 2-D and 3-D.
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/magnetic_flight.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry/shape_file.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

using namespace billiards;
using dynamics::never;
using dynamics::Vec2;

namespace {

const double pi = geometry::pi;

dynamics::Table table_of(const std::string& name) {
  return dynamics::Table(geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + name + ".yaml").region);
}

/// Both `never`, or equal within `tol` (relative to 1 + |t|).
bool same_time(double a, double b, double tol) {
  if (a == never || b == never) return a == b;
  return std::abs(a - b) <= tol * (1 + std::abs(a));
}

dynamics::Table3 table3_of(const std::string& name) {
  // (The table keeps a reference to its region.)
  static std::vector<std::unique_ptr<geometry3::Shape3>> shapes;
  shapes.push_back(std::make_unique<geometry3::Shape3>(geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/" + name + ".yaml")));
  return dynamics::Table3(shapes.back()->region);
}

/// For each of 40 microcanonical states and every wall of the table: the closed form
/// `closed(s, wall)` and the scan `scanned(s, wall)` agree; returns how many exit times were
/// finite, so that the comparison is not vacuous (a state leaves through one or two walls
/// within the horizon; fewer in a magnetic field, whose small circles miss most walls).
template <class Table, class Start, class Closed, class Scan>
int compare_every_wall(const Table& table, Start start, Closed closed, Scan scanned, double tol) {
  int finite = 0;
  for (std::uint64_t p = 0; p < 40; ++p) {
    dynamics::ParticleRng rng(21, p);
    const auto s = start(dynamics::sample_microcanonical(table, 1.0, rng));
    table.for_each_kind([&](const auto& walls, int kind) {
      for (int i = 0; i < int(walls.size()); ++i) {
        const double want = closed(s, walls[i]), got = scanned(s, walls[i]);
        INFO("particle " << p << ", wall kind " << kind << " index " << i << ": closed form " << want << ", scan " << got);
        CHECK(same_time(want, got, tol));
        finite += want != never;
      }
    });
  }
  return finite;
}

}  // namespace

TEST_CASE("the scan of a wall's gap equals every flight's closed forms, wall kind by wall kind") {
  const double horizon = 3;
  for (const char* name : {"stadium", "clover", "sinai-ellipse", "elliptic-stadium"}) {
    INFO("table " << name);
    const auto table = table_of(name);
    auto same = [](const auto& s) { return s; };
    SECTION("straight lines") {
      const dynamics::FreeFlight flight;
      CHECK(compare_every_wall(
                table, same, [&](const auto& s, const auto& w) { return dynamics::detail::WallByWall<dynamics::FreeFlight>{flight, s}.exit_time(w, never); },
                [&](const auto& s, const auto& w) { return flight.exit_time(s, w, never, dynamics::Scanned{}); }, 1e-12) >= 15);
    }
    SECTION("parabolas") {
      const dynamics::ConstantForceFlight flight{Vec2(0.3, -0.8)};
      CHECK(compare_every_wall(
                table, same, [&](const auto& s, const auto& w) { return dynamics::detail::WallByWall<dynamics::ConstantForceFlight>{flight, s}.exit_time(w, s.t + horizon); },
                [&](const auto& s, const auto& w) { return flight.template exit_time<std::decay_t<decltype(w)>>(s, w, s.t + horizon); }, 1e-10) >= 15);
    }
    SECTION("the periodic drive, lab frame and quivering walls") {
      for (const double omega : {2 * pi, 40 * pi}) {
        INFO("omega " << omega);
        const dynamics::PeriodicDriveFlight lab{Vec2(3, 4), omega, 0.3};
        const dynamics::QuiveringWallFlight walls{Vec2(3, 4), omega, 0.3};
        auto start_lab = [&](const auto& s) { return lab.start(s); };
        auto start_walls = [&](const auto& s) { return walls.start(s); };
        CHECK(compare_every_wall(
                  table, start_lab, [&](const auto& s, const auto& w) { return lab.scan_from(s).exit_time(w, s.t + horizon); },
                  [&](const auto& s, const auto& w) { return lab.scan_from(s).template exit_time<std::decay_t<decltype(w)>>(w, s.t + horizon); }, 1e-10) >= 15);
        CHECK(compare_every_wall(
                  table, start_walls, [&](const auto& s, const auto& w) { return walls.scan_from(s).exit_time(w, s.t + horizon); },
                  [&](const auto& s, const auto& w) { return walls.scan_from(s).template exit_time<std::decay_t<decltype(w)>>(w, s.t + horizon); }, 1e-10) >= 15);
      }
    }
    SECTION("circles in a magnetic field") {
      // (Elliptic arcs have no closed form here: both sides scan them.)
      for (const double omega_c : {0.5, -3.0}) {
        const dynamics::MagneticFlight flight{omega_c};
        CHECK(compare_every_wall(
                  table, same, [&](const auto& s, const auto& w) { return flight.exit_time(s, w, never); },
                  [&](const auto& s, const auto& w) { return flight.scan_from(s).exit_time(w, never, dynamics::Scanned{}); }, 1e-10) >= 15);
      }
    }
    SECTION("a magnetic field with a force") {
      const dynamics::MagneticDriveFlight flight{1.5, Vec2(0.4, -0.3), 5.0, 0.2};
      auto start = [&](const auto& s) { return flight.start(s); };
      CHECK(compare_every_wall(
                table, start, [&](const auto& s, const auto& w) { return flight.exit_time(s, w, s.t + 1); },
                [&](const auto& s, const auto& w) { return flight.exit_time(s, w, s.t + 1, dynamics::Scanned{}); }, 1e-10) >= 15);
    }
  }
}

TEST_CASE("the scan of a wall's gap equals the 3-D flights' closed forms, wall kind by wall kind") {
  for (const char* name : {"sinai3", "l-prism"}) {  // planes and a sphere; mesh triangles
    INFO("table " << name);
    const auto table = table3_of(name);
    auto same = [](const auto& s) { return s; };
    SECTION("straight lines") {
      const dynamics::FreeFlight3 flight;
      CHECK(compare_every_wall(
                table, same, [&](const auto& s, const auto& w) { return flight.exit_time(s, w, never); },
                [&](const auto& s, const auto& w) { return flight.scan_from(s).template exit_time<std::decay_t<decltype(w)>>(w, never); }, 1e-12) >= 15);
    }
    SECTION("the periodic drive") {
      const dynamics::PeriodicDriveFlight3 flight{dynamics::Vec3(3, 4, -2), 40 * pi, 0.3};
      auto start = [&](const auto& s) { return flight.start(s); };
      CHECK(compare_every_wall(
                table, start, [&](const auto& s, const auto& w) { return flight.exit_time(s, w, s.t + 3); },
                [&](const auto& s, const auto& w) { return flight.exit_time(s, w, s.t + 3, dynamics::Scanned{}); }, 1e-10) >= 15);
    }
    SECTION("helices in a magnetic field") {
      const dynamics::MagneticFlight3 flight{dynamics::Vec3(0.3, -0.5, 2.0)};
      CHECK(compare_every_wall(
                table, same, [&](const auto& s, const auto& w) { return flight.exit_time(s, w, s.t + 5); },
                [&](const auto& s, const auto& w) { return flight.scan_from(s).exit_time(w, s.t + 5, dynamics::Scanned{}); }, 1e-10) >= 15);
    }
    SECTION("a magnetic field with a force") {
      const dynamics::MagneticDriveFlight3 flight{dynamics::Vec3(0.3, -0.5, 2.0), dynamics::Vec3(0.4, -0.3, 0.2), 5.0, 0.2};
      auto start = [&](const auto& s) { return flight.start(s); };
      CHECK(compare_every_wall(
                table, start, [&](const auto& s, const auto& w) { return flight.exit_time(s, w, s.t + 1); },
                [&](const auto& s, const auto& w) { return flight.exit_time(s, w, s.t + 1, dynamics::Scanned{}); }, 1e-10) >= 15);
    }
  }
}
