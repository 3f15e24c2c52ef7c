// Coefficients against hand-derived closed forms and the paper; the Fokker–Planck solution.
#include "billiards/analysis.hpp"
#include "billiards/geometry.hpp"

#include <boost/math/special_functions/bessel.hpp>
#include <catch2/catch.hpp>

#include <cmath>

using namespace billiards;
using geometry::pi;

namespace {

geometry::Measures measures(const char* name) {
  return geometry::measures_of(geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml").region);
}

analysis::Drive drive(double Fx, double Fy, double omega, double mass = 1) {
  analysis::Drive d;
  d.F = Eigen::Vector2d(Fx, Fy);
  d.omega = omega;
  d.mass = mass;
  return d;
}

}  // namespace

TEST_CASE("unit square by hand: T = 2 I, lambda = pi/4") {
  // F = (3, 4), m = 2, E = 1: v = 1, W = Fᵀ(2I)F = 50, W/S = 12.5, λ = π/4.
  const auto m = measures("square");
  const auto c = analysis::coefficients(m, drive(3, 4, 10, 2), 1.0);
  CHECK(c.wall_integral == Approx(50).epsilon(1e-14));
  CHECK(c.mean_free_path == Approx(pi / 4).epsilon(1e-14));
  CHECK(c.density_of_states == Approx(2 * pi * 1 / 2.0).epsilon(1e-14));   // d B_d V v^0/m
  CHECK(c.collision_rate_density == Approx(2 / (2 * pi) * 1).epsilon(1e-14)); // B_1/(2 B_2) v/V
  CHECK(c.collision_rate == Approx(1 / (pi / 4)).epsilon(1e-14));           // v/λ
  CHECK(c.g1 == Approx(2 * 1 / (100 * 2 * (pi / 4)) * 12.5).epsilon(1e-14));
  CHECK(c.g2 == Approx(4 * 1 / (100 * 3 * (pi / 4)) * 12.5).epsilon(1e-14));
  CHECK(c.g1 == Approx(c.C * std::sqrt(1.0)).epsilon(1e-14));
}

TEST_CASE("unit circle by hand: the wall integral is pi F^2 for any direction") {
  const auto m = measures("circle");
  const auto c = analysis::coefficients(m, drive(0.6, 0.8, 4, 1), 0.5);
  CHECK(c.wall_integral == Approx(pi).epsilon(1e-14));
  CHECK(c.mean_free_path == Approx(pi / 2).epsilon(1e-14));
  CHECK(c.g2 == Approx(4 * std::pow(c.speed, 3) / (16 * 3 * (pi / 2)) * 0.5).epsilon(1e-14));
  CHECK(c.force_ratio == Approx(1 / (4 * 1.0)).epsilon(1e-14));
  CHECK(c.warnings.size() == 2);  // both ratios exceed 0.1 at ω = 4
}

TEST_CASE("the paper's clover: lambda = 2.610 and C = 0.5419 F^2/omega^2") {
  const auto m = measures("clover");
  const double F = 10, omega = 40 * pi;
  const auto c = analysis::coefficients(m, drive(F / std::sqrt(2.0), F / std::sqrt(2.0), omega), 0.5);
  CHECK(std::abs(c.mean_free_path - 2.610) < 5e-4);
  CHECK(std::abs(c.C * omega * omega / (F * F) - 0.5419) < 5e-5);
  CHECK(c.warnings.empty());
}

TEST_CASE("fluctuation-dissipation: g1 = (1/2 Sigma) d/dE (g2 Sigma), d = 2 and 3") {
  for (int d : {2, 3}) {
    geometry::Measures m;
    m.dimension = d;
    m.volume = 1.7;
    m.surface = 5.3;
    m.boundary_tensor = Eigen::MatrixXd::Identity(d, d) * (5.3 / d);
    analysis::Drive dr;
    dr.F = Eigen::VectorXd::Constant(d, 2.0);
    dr.omega = 30;
    dr.mass = 1.3;
    for (double E : {0.2, 1.0, 7.0}) {
      const double h = 1e-5 * E;
      auto product = [&](double e) { return analysis::diffusion_g2(m, dr, e) * analysis::density_of_states(m, dr.mass, e); };
      const double rhs = (product(E + h) - product(E - h)) / (2 * h) / (2 * analysis::density_of_states(m, dr.mass, E));
      CHECK(analysis::drift_g1(m, dr, E) == Approx(rhs).epsilon(1e-8));
    }
  }
}

TEST_CASE("scaled Bessel function: continuous across its two methods, exact below") {
  for (double nu : {1.0, 2.0}) {
    CHECK(analysis::scaled_bessel_i(nu, 3.0) == Approx(boost::math::cyl_bessel_i(nu, 3.0) * std::exp(-3.0)).epsilon(1e-14));
    // Boost is still finite at 650: the asymptotic series must agree there.
    const double direct = boost::math::cyl_bessel_i(nu, 650.0) * std::exp(-650.0);
    CHECK(direct == Approx(analysis::scaled_bessel_i(nu, 650.0)).epsilon(1e-13));
  }
}

TEST_CASE("Fokker-Planck solution: normalized, and its moments grow as the equation says") {
  const double E0 = 0.5;
  for (int d : {2, 3}) {
    for (double s : {0.1, 1.0, 10.0}) {
      INFO("d = " << d << ", s = " << s);
      CHECK(analysis::fokker_planck_moments(s, E0, d).norm == Approx(1).epsilon(2e-6));
    }
    // Small s: d<E>/ds = <√E> ≈ √E0, dVar/ds = 4 E0^{3/2}/(d+1) (g1 = C√E, g2 = 4C E^{3/2}/(d+1)).
    const double s = 1e-3;
    const auto m = analysis::fokker_planck_moments(s, E0, d);
    CHECK((m.mean - E0) / s == Approx(std::sqrt(E0)).epsilon(2e-2));
    CHECK(m.variance / s == Approx(4 * std::pow(E0, 1.5) / (d + 1)).epsilon(2e-2));
    // At any s, d<E>/ds = <√E> (the drift g1 = C√E averaged over η): by central differences.
    const double s1 = 2.0, ds = 1e-3;
    const double slope = (analysis::fokker_planck_moments(s1 + ds, E0, d).mean -
                          analysis::fokker_planck_moments(s1 - ds, E0, d).mean) / (2 * ds);
    const int n = 200000;
    const double hi = std::pow(40 * E0 + 50 * s1 * s1, 0.25), h = hi / n;
    double root_mean = 0;
    for (int i = 1; i < n; ++i) {
      const double u = i * h;
      root_mean += u * u * analysis::fokker_planck_eta(u * u * u * u, s1, E0, d) * 4 * u * u * u * h;
    }
    CHECK(slope == Approx(root_mean).epsilon(1e-5));
  }
}

TEST_CASE("numerical Fokker-Planck (Chang-Cooper) against the analytic solution: L1 <= 1e-3") {
  const double E0 = 0.5;
  for (int d : {2, 3}) {
    auto g1 = [](double E) { return std::sqrt(E); };  // in units of s = C t
    auto g2 = [d](double E) { return 4 * std::pow(E, 1.5) / (d + 1); };
    for (double s : {0.1, 1.0, 10.0}) {
      INFO("d = " << d << ", s = " << s);
      const double s0 = s / 10;
      const auto grid = analysis::quartic_root_grid(40 * E0 + 50 * s * s, 4000);
      std::vector<double> eta(grid.cells());
      for (std::size_t i = 0; i < eta.size(); ++i) eta[i] = analysis::fokker_planck_eta(grid.center(i), s0, E0, d);
      const auto out = analysis::evolve_fokker_planck(grid, eta, g1, g2, s - s0, 4000);
      double l1 = 0, mass0 = 0, mass1 = 0, negative = 0;
      for (std::size_t i = 0; i < out.size(); ++i) {
        l1 += std::abs(out[i] - analysis::fokker_planck_eta(grid.center(i), s, E0, d)) * grid.width(i);
        mass0 += eta[i] * grid.width(i);
        mass1 += out[i] * grid.width(i);
        negative = std::min(negative, out[i]);
      }
      CHECK(l1 <= 1e-3);
      CHECK(std::abs(mass1 - mass0) < 1e-10);  // conservative, to rounding over 4000 solves
      CHECK(negative >= 0);                    // positive
    }
  }
}
