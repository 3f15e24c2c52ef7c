// Speed against error (analysis/speed_error.hpp): the Odeint baseline against the exact flight,
// the exact flight against MPFR, and `billiard bench speed-error --quick`.
#include "cli_helpers.hpp"
#include "billiards/analysis/speed_error.hpp"

#include "billiards/dynamics/ensemble.hpp"
#include "billiards/geometry.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

using namespace billiards;
using dynamics::Vec2;
namespace fs = std::filesystem;

namespace {

const double pi = geometry::pi;

/// The paper's driven clover: F = 10 along (1, 1)/√2, m = 1, E0 = 1/2 (speed 1).
struct Clover {
  geometry::Shape shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
  dynamics::Table table{shape.region};
  dynamics::State initial(std::uint64_t i) const {
    dynamics::ParticleRng rng(7, i);
    return dynamics::sample_microcanonical(table, 1.0, rng);
  }
};

dynamics::PeriodicDriveFlight drive(double omega) { return {10 / std::sqrt(2.0) * Vec2(1, 1), omega, 0}; }

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string f; std::getline(s, f, sep);) out.push_back(f);
  return out;
}

}  // namespace

TEST_CASE("Odeint at tight tolerance reproduces the exact flight's collisions") {
  // Over t = 6 (2 to 4 collisions), dopri5 at tolerance 1e-12 has a local error of ~1e-12
  // per unit of the state over ~1e4 steps; each collision with the clover's dispersing
  // walls amplifies a deviation by ~10.  Measured: at most 1.8e-10 in collision times and
  // 1.6e-9 in the final state.  1e-7 leaves a margin of 60, and is still far below what a
  // wrong collision sequence or a wrong reflection would give (O(1)).
  const Clover clover;
  for (const double omega : {40 * pi, 320 * pi}) {
    const auto flight = drive(omega);
    std::size_t collisions = 0;
    for (std::uint64_t i = 0; i < 6; ++i) {
      const auto s0 = clover.initial(i);
      const auto exact = analysis::exact_run(clover.table, flight, s0, 6);
      const auto ode = analysis::odeint_run(clover.table, flight, s0, 6, 1e-12);
      CHECK_FALSE(ode.escaped);
      REQUIRE(ode.bounces.size() == exact.bounces.size());
      for (std::size_t k = 0; k < exact.bounces.size(); ++k) {
        CHECK(ode.bounces[k].wall == exact.bounces[k].wall);
        CHECK(std::abs(ode.bounces[k].t - exact.bounces[k].t) < 1e-7);
        CHECK((ode.bounces[k].x - exact.bounces[k].x).norm() < 1e-7);
      }
      CHECK((ode.end.x - exact.end.x).norm() < 1e-7);
      CHECK((ode.end.v - exact.end.v).norm() < 1e-7);
      collisions += exact.bounces.size();
    }
    CHECK(collisions >= 10);
  }
}

TEST_CASE("Odeint at loose tolerance is measurably wrong at high frequency") {
  // The controller at tolerance 1e-3 steps over the drive's oscillation: the check above
  // would catch it, so the comparison has teeth.
  const Clover clover;
  const auto flight = drive(320 * pi);
  double worst = 0;
  for (std::uint64_t i = 0; i < 6; ++i) {
    const auto s0 = clover.initial(i);
    const auto exact = analysis::exact_run(clover.table, flight, s0, 6);
    const auto ode = analysis::odeint_run(clover.table, flight, s0, 6, 1e-3);
    worst = std::max(worst, (ode.end.x - exact.end.x).norm());
  }
  CHECK(worst > 1e-3);
}

TEST_CASE("the exact flight agrees with a 100-bit MPFR evaluation of Appendix B") {
  // One flight from the same initial state: rounding only (a few ulps of the coordinates).
  const Clover clover;
  for (const double omega : {40 * pi, 2560 * pi}) {
    const auto flight = drive(omega);
    for (std::uint64_t i = 0; i < 5; ++i) {
      const auto s0 = clover.initial(i);
      const auto exact = analysis::exact_run(clover.table, flight, s0, 4);
      REQUIRE_FALSE(exact.bounces.empty());
      const auto check = analysis::mpfr_check(clover.table, flight, s0, exact, 4, 1);
      REQUIRE(check.confirmed);
      CHECK((check.first_collision - exact.bounces[0].x).norm() < 1e-14);
      // A few collisions later, chaos has amplified rounding, but not beyond 1e-10.
      CHECK((check.x - exact.end.x).norm() < 1e-10);
      CHECK(std::abs(check.energy - dynamics::kinetic_energy(exact.end, 1.0)) < 1e-10);
    }
  }
}

TEST_CASE("billiard bench speed-error --quick writes a well-formed CSV and a PNG") {
  const auto dir = scratch("speed-error");
  const auto r = billiard("bench speed-error --quick --omega 40*pi 320*pi --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(fs::file_size(dir / "out" / "speed-error.png") > 1000);
  std::stringstream csv(read_file(dir / "out" / "speed-error.csv"));
  std::string line;
  std::getline(csv, line);
  const auto header = split(line, ',');
  REQUIRE(header == std::vector<std::string>{"method", "omega", "omega_over_pi", "tolerance", "particles", "escapes",
                                             "unconfirmed", "cpu_seconds_per_time", "var_dE", "var_dE_error",
                                             "var_dE_se", "median_position_error", "median_first_collision_error",
                                             "collisions_per_particle"});
  std::map<std::string, int> methods;
  std::map<double, std::vector<double>> first_errors;  // Odeint's, per omega, loosest tolerance first
  while (std::getline(csv, line)) {
    const auto f = split(line, ',');
    REQUIRE(f.size() == header.size());
    ++methods[f[0]];
    std::vector<double> x;
    for (std::size_t k = 1; k < f.size(); ++k) x.push_back(std::stod(f[k]));
    CHECK(std::abs(x[0] / pi - x[1]) < 1e-9);  // omega, omega / pi
    CHECK(x[6] > 0);                           // CPU time
    CHECK(x[7] > 0);                           // Var(dE)
    CHECK(x[8] >= 0);
    if (f[0] == "exact") {
      CHECK(x[2] == 0);
      CHECK(x[4] + x[5] == 0);  // no escapes, every collision confirmed in MPFR
      CHECK(x[11] < 1e-14);     // the first collision, against MPFR
    } else {
      CHECK(x[2] > 0);
      first_errors[x[1]].push_back(x[11]);
    }
  }
  CHECK(methods == std::map<std::string, int>{{"exact", 2}, {"odeint", 8}});
  // One flight is not yet chaotic: its error must fall as the tolerance tightens.
  for (const auto& [omega, e] : first_errors)
    for (std::size_t k = 1; k < e.size(); ++k) CHECK(e[k] < e[k - 1]);
}

TEST_CASE("billiard bench speed-error rejects a scene without a periodic drive and writes nothing") {
  const auto dir = scratch("speed-error-bad");
  const auto r = billiard("bench speed-error scenes/clover-free.yaml --quick --out " + (dir / "out").string());
  CHECK(r.status != 0);
  CHECK(r.output.find("billiard: error: scenes/clover-free.yaml: bench speed-error needs a periodic drive") !=
        std::string::npos);
  CHECK_FALSE(fs::exists(dir / "out"));
}
