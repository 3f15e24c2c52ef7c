// The paper's drive in 3-D: Appendix B's flight against planes and spheres, certified exit
// times against a brute-force scan, F = 0 against the free flight, and the 3-D Sinai billiard
// against the analysis layer's g1, g2 in d = 3.
#include "billiards/analysis.hpp"
#include "billiards/dynamics3/table3.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace billiards;
using dynamics3::DrivenState3;
using dynamics3::PeriodicDriveFlight3;
using dynamics3::Vec3;

namespace {

const double pi = geometry::pi;

geometry3::Shape3 sinai3() { return geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/sinai3.yaml"); }

/// x(t) of Appendix B from (x0, v0) at t = 0, in long double.
Eigen::Matrix<long double, 3, 1> position(const PeriodicDriveFlight3& f, const Vec3& x0, const Vec3& v0, long double t) {
  const long double w = f.omega, th0 = f.phase0, th = w * t + th0;
  Eigen::Matrix<long double, 3, 1> x;
  for (int i = 0; i < 3; ++i) {
    const long double a = f.accel[i];
    x[i] = x0[i] + (v0[i] - a / w * std::sin(th0)) * t - a / (w * w) * (std::cos(th) - std::cos(th0));
  }
  return x;
}

/// First crossing of g from < 0 to > 0 after t = 0 by sampling every h and bisecting; -1 if none.
template <class G>
double first_crossing(G g, double h, double t_max) {
  long double before = g(0.0L);
  for (long n = 1; n * h <= t_max; ++n) {
    const long double t = (long double)n * h, now = g(t);
    if (before < 0 && now > 0) {
      long double a = t - h, b = t;
      for (int i = 0; i < 80; ++i) {
        const long double m = (a + b) / 2;
        (g(m) > 0 ? b : a) = m;
      }
      return double(b);
    }
    before = now;
  }
  return -1;
}

}  // namespace

TEST_CASE("3-D driven exit times through a plane and a sphere equal a brute-force scan") {
  const dynamics3::PlaneWall plane{Vec3(0, 0, 1), 1.0, 1e-15};  // z ≤ 1
  const dynamics3::SphereWall ball{Vec3::Zero(), 1.0, 1.0, true, 1e-15};
  dynamics::ParticleRng rng(5, 0);
  int compared = 0;
  for (const double omega : {2 * pi, 40 * pi, 640 * pi}) {
    for (int k = 0; k < 12; ++k) {
      const Vec3 F = 10 * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalized();
      const PeriodicDriveFlight3 flight{F, omega, 2 * pi * rng.uniform()};
      dynamics3::State3 s0;
      s0.x = 0.5 * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
      s0.v = Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalized();
      const double h = std::min(2 * pi / omega / 128, 2e-3);
      const double t_plane = first_crossing([&](long double t) { return position(flight, s0.x, s0.v, t)[2] - 1; }, h, 3);
      const double t_ball = first_crossing([&](long double t) { return position(flight, s0.x, s0.v, t).norm() - 1; }, h, 3);
      const auto s = flight.start(s0);
      INFO("omega " << omega << " case " << k);
      const double got_plane = flight.exit_time(s, plane, 3), got_ball = flight.exit_time(s, ball, 3);
      for (const auto& [got, expected] : {std::pair{got_plane, t_plane}, std::pair{got_ball, t_ball}}) {
        if (expected < 0) {
          CHECK(got == dynamics3::never);
        } else {
          CHECK(std::abs(got - expected) < 1e-10);
          ++compared;
        }
      }
    }
  }
  CHECK(compared > 36);  // 45 of the 72 flights meet the wall within 3 time units
}

TEST_CASE("3-D: zero drive is the free billiard, collision for collision") {
  const auto shape = sinai3();
  const dynamics3::Table3 table(shape.region);
  const PeriodicDriveFlight3 flight{Vec3::Zero(), 40 * pi, 0};
  dynamics::ParticleRng rng(9, 0);
  dynamics3::State3 free = dynamics3::sample_microcanonical(table, 1.0, rng);
  DrivenState3 driven = flight.start(free);
  for (int k = 0; k < 12; ++k) {  // few enough that chaos has not amplified the roots' rounding
    const auto a = table.collision(free), b = table.collision(flight, driven);
    REQUIRE(a.found());
    REQUIRE(b.found());
    CHECK(a.wall == b.wall);
    CHECK((a.point - b.point).norm() < 1e-9);
    dynamics3::bounce(free, a, 1.0);
    dynamics3::bounce(flight, driven, b);
  }
}

// With 8000 particles the standard errors are 23% (mean) and 1.6% (variance).  With 80 000
// (measured 2026-11-23) the mean still agrees (−0.1 SE) but the variance is 2.7% above g2 dt
// (+5 SE); the 2-D Sinai table (square and disk) shows a like excess (mean +4 SE at 10⁵
// particles) that vanishes at 2560π, while the clover and the stadium agree at 320π: a
// finite-frequency correction of Sinai tables, not a d = 3 effect (README, "3-D shapes").
TEST_CASE("3-D Sinai at omega = 320 pi: <dE> and Var(dE) match g1 dt and g2 dt (d = 3)") {
  const auto shape = sinai3();
  const dynamics3::Table3 table(shape.region);
  const double F = 10, omega = 320 * pi, E0 = 0.5, dt = 10;
  const PeriodicDriveFlight3 flight{Vec3(F, F, F) / std::sqrt(3.0), omega, 0};
  const std::size_t n = 8000;
  std::vector<double> dE(n);
  std::size_t collisions = 0;
  for (std::size_t i = 0; i < n; ++i) {
    dynamics::ParticleRng rng(1, i);
    auto s = flight.start(dynamics3::sample_microcanonical(table, std::sqrt(2 * E0), rng));
    while (true) {
      const auto hit = table.collision(flight, s, dt);
      if (!hit.found()) break;  // no wall before dt
      dynamics3::bounce(flight, s, hit);
      ++collisions;
    }
    const auto end = flight.advance(s, dt);
    REQUIRE(geometry3::contains(shape.region, end.x));
    dE[i] = 0.5 * end.v.squaredNorm() - E0;
  }
  analysis::Drive drive;
  drive.F = Eigen::Vector3d(F, F, F) / std::sqrt(3.0);
  drive.omega = omega;
  drive.mass = 1;
  const auto c = analysis::coefficients(geometry3::measures_of(shape.region), drive, E0);
  REQUIRE(c.dimension == 3);
  CHECK(c.warnings.empty());
  // About v/λ · dt = 18 collisions per particle: the diffusion limit.
  CHECK(double(collisions) / double(n) == Approx(std::sqrt(2 * E0) / c.mean_free_path * dt).epsilon(0.05));
  const auto m = analysis::sample_moments(dE);
  INFO("<dE> = " << m.mean << " ± " << m.se_mean << " vs g1 dt = " << c.g1 * dt);
  INFO("Var = " << m.variance << " ± " << m.se_variance << " vs g2 dt = " << c.g2 * dt);
  CHECK(std::abs(m.mean - c.g1 * dt) < 3 * m.se_mean);
  CHECK(std::abs(m.variance - c.g2 * dt) < 3 * m.se_variance);
  // And the exact Fokker–Planck moments with I_2 (d = 3).
  const auto fp = analysis::fokker_planck_exact_moments(c.C * dt, E0, 3);
  CHECK(std::abs(m.variance - fp.variance) < 3 * m.se_variance);
}
