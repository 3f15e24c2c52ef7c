// The standard-billiard coefficients (U = 0) against values derived by hand from the paper's
// formulas, in 2-D and 3-D, and the fluctuation-dissipation relation they must satisfy.
#include "billiards/analysis.hpp"
#include "billiards/geometry.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>

using namespace billiards;
using geometry::pi;

namespace {

geometry::Measures measures(const char* name) {
  return geometry::measures_of(
      geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml").region);
}

/// Measures given by hand: T = ∮ n nᵀ dS is isotropic, (S/d)·I, for every table used here.
geometry::Measures isotropic(int d, double V, double S) {
  geometry::Measures m;
  m.dimension = d;
  m.volume = V;
  m.surface = S;
  m.boundary_tensor = Eigen::MatrixXd::Identity(d, d) * (S / d);
  return m;
}

analysis::Drive drive(Eigen::VectorXd F, double omega, double mass) {
  analysis::Drive dr;
  dr.F = std::move(F);
  dr.omega = omega;
  dr.mass = mass;
  return dr;
}

constexpr double tight = 1e-14;

}  // namespace

TEST_CASE("unit square, F = (3, 4), m = 2, omega = 40, E = 4: every coefficient by hand") {
  // V = 1, S = 4, T = 2I, λ = πV/S = π/4; v = √(2E/m) = 2; W = Fᵀ T F = 50, W/S = 25/2.
  const auto c = analysis::coefficients(isotropic(2, 1, 4), drive(Eigen::Vector2d(3, 4), 40, 2), 4);
  CHECK(c.speed == Approx(2).epsilon(tight));
  CHECK(c.mean_free_path == Approx(pi / 4).epsilon(tight));
  CHECK(c.wall_integral == Approx(50).epsilon(tight));
  CHECK(c.density_of_states == Approx(pi).epsilon(tight));           // 2 B_2 V v⁰/m = 2π/2
  CHECK(c.collision_rate_density == Approx(2 / pi).epsilon(tight));  // B_1/(2 B_2) v/V = (1/π)·2
  CHECK(c.collision_rate == Approx(8 / pi).epsilon(tight));          // γ_E S = v/λ
  CHECK(c.g1 == Approx(1 / (16 * pi)).epsilon(tight));               // 2 v/(ω² m λ) W/S
  CHECK(c.g2 == Approx(1 / (3 * pi)).epsilon(tight));                // 4 v³/(3 ω² λ) W/S
  CHECK(c.C == Approx(1 / (32 * pi)).epsilon(tight));                // (2/m)^{3/2} W/(S λ ω²)
  CHECK(c.g1 == Approx(c.C * std::sqrt(4.0)).epsilon(tight));
  CHECK(c.g2 == Approx(4 * c.C * std::pow(4.0, 1.5) / 3).epsilon(tight));
  CHECK(c.force_ratio == Approx(1 / 32.0).epsilon(tight));   // 5/(2·40·2)
  CHECK(c.length_ratio == Approx(0.2 / pi).epsilon(tight));  // 2/(40·π/4)
  CHECK(c.warnings.empty());
}

TEST_CASE("unit circle, |F| = 2, m = 1, omega = 5, E = 2: by hand, and both validity warnings") {
  // V = π, S = 2π, T = πI for any direction of F, λ = π/2; v = 2; W/S = π·4/(2π) = 2.
  const auto c = analysis::coefficients(isotropic(2, pi, 2 * pi), drive(Eigen::Vector2d(1.2, 1.6), 5, 1), 2);
  CHECK(c.wall_integral == Approx(4 * pi).epsilon(tight));
  CHECK(c.mean_free_path == Approx(pi / 2).epsilon(tight));
  CHECK(c.density_of_states == Approx(2 * pi * pi).epsilon(tight));
  CHECK(c.collision_rate_density == Approx(2 / (pi * pi)).epsilon(tight));
  CHECK(c.collision_rate == Approx(4 / pi).epsilon(tight));
  CHECK(c.g1 == Approx(16 / (25 * pi)).epsilon(tight));
  CHECK(c.g2 == Approx(128 / (75 * pi)).epsilon(tight));
  CHECK(c.force_ratio == Approx(0.2).epsilon(tight));        // 2/(1·5·2)
  CHECK(c.length_ratio == Approx(0.8 / pi).epsilon(tight));  // 2/(5·π/2)
  REQUIRE(c.warnings.size() == 2);
  CHECK(c.warnings[0].find("F/(m omega v_E)") != std::string::npos);
  CHECK(c.warnings[1].find("v_E/(omega lambda)") != std::string::npos);
}

TEST_CASE("the paper's clover from its shape file: lambda = 2.6096 and C = 0.5419 F^2/omega^2") {
  // The measures come from shapes/clover.yaml through the geometry layer; W/S = F²/2 for
  // F = F(x̂ + ŷ)/√2 because the clover's boundary tensor is isotropic, as in the paper.
  const auto m = measures("clover");
  const double F = 10, omega = 40 * pi;
  const auto c = analysis::coefficients(m, drive(Eigen::Vector2d(F, F) / std::sqrt(2.0), omega, 1), 0.5);
  CHECK(c.mean_free_path == Approx(pi * c.volume / c.surface).epsilon(tight));
  CHECK(std::abs(c.mean_free_path - 2.610) < 5e-4);
  CHECK(c.wall_integral / c.surface == Approx(F * F / 2).epsilon(1e-12));
  CHECK(c.C * omega * omega / (F * F) == Approx(std::sqrt(2.0) / c.mean_free_path).epsilon(1e-13));
  CHECK(std::abs(c.C * omega * omega / (F * F) - 0.5419) < 5e-5);
  CHECK(c.warnings.empty());
}

TEST_CASE("the square and the circle from their shape files: T = 2 I and pi I, lambda = pi/4 and pi/2") {
  const auto sq = analysis::coefficients(measures("square"), drive(Eigen::Vector2d(3, 4), 10, 2), 1.0);
  CHECK(sq.wall_integral == Approx(50).epsilon(tight));  // Fᵀ(2I)F
  CHECK(sq.mean_free_path == Approx(pi / 4).epsilon(tight));
  const auto ci = analysis::coefficients(measures("circle"), drive(Eigen::Vector2d(0.6, 0.8), 4, 1), 0.5);
  CHECK(ci.wall_integral == Approx(pi).epsilon(tight));  // π|F|² for any direction
  CHECK(ci.mean_free_path == Approx(pi / 2).epsilon(tight));
}

TEST_CASE("unit ball in 3-D, F = z-hat, m = 1, E = 1/2: the paper's 3-D wall formula") {
  // V = 4π/3, S = 4π, T = (4π/3) I, λ = 4V/S = 4/3, v = 1, W/S = 1/3.
  const double omega = 7;
  const auto c =
      analysis::coefficients(isotropic(3, 4 * pi / 3, 4 * pi), drive(Eigen::Vector3d(0, 0, 1), omega, 1), 0.5);
  CHECK(c.mean_free_path == Approx(4.0 / 3).epsilon(tight));
  CHECK(c.density_of_states == Approx(3 * (4 * pi / 3) * (4 * pi / 3)).epsilon(tight));  // 3 B_3 V v/m
  CHECK(c.collision_rate_density == Approx(1 / (4 * (4 * pi / 3))).epsilon(tight));      // B_2/(3 B_3) v/V
  // d⟨E⟩/dt = v/(2 m ω² V) ∮(F·n)² dS (the paper's 3-D result) = 1/(2ω²) here.
  CHECK(c.g1 == Approx(1 / (2 * omega * omega)).epsilon(tight));
  CHECK(c.g2 == Approx(1 / (4 * omega * omega)).epsilon(tight));
  CHECK(c.C == Approx(std::sqrt(2.0) / (2 * omega * omega)).epsilon(tight));
}

TEST_CASE("fluctuation-dissipation g1 = (1/2 Sigma) d/dE (g2 Sigma) by central differences, d = 2 and 3") {
  for (int d : {2, 3}) {
    const auto m = isotropic(d, 1.7, 5.3);
    const auto dr = drive(Eigen::VectorXd::LinSpaced(d, 0.5, 2.0), 30, 1.3);
    auto product = [&](double e) {
      return analysis::diffusion_g2(m, dr, e) * analysis::density_of_states(m, dr.mass, e);
    };
    for (double E : {0.2, 1.0, 7.0}) {
      INFO("d = " << d << ", E = " << E);
      const double h = 1e-4 * E;
      const double rhs = (product(E + h) - product(E - h)) / (2 * h) / (2 * analysis::density_of_states(m, dr.mass, E));
      CHECK(analysis::drift_g1(m, dr, E) == Approx(rhs).epsilon(1e-8));
    }
  }
}

TEST_CASE("Coefficients to JSON: every key, with its value") {
  const auto c = analysis::coefficients(isotropic(2, pi, 2 * pi), drive(Eigen::Vector2d(1.2, 1.6), 5, 1), 2);
  const nlohmann::json j = c;
  CHECK(j.at("dimension") == 2);
  CHECK(j.at("E") == 2.0);
  CHECK(j.at("v_E") == c.speed);
  CHECK(j.at("V") == pi);
  CHECK(j.at("S") == 2 * pi);
  CHECK(j.at("mean_free_path") == c.mean_free_path);
  CHECK(j.at("wall_integral") == c.wall_integral);
  CHECK(j.at("C") == c.C);
  CHECK(j.at("g1") == c.g1);
  CHECK(j.at("g2") == c.g2);
  CHECK(j.at("Sigma") == c.density_of_states);
  CHECK(j.at("gamma_E") == c.collision_rate_density);
  CHECK(j.at("collision_rate") == c.collision_rate);
  CHECK(j.at("validity_force_ratio") == c.force_ratio);
  CHECK(j.at("validity_length_ratio") == c.length_ratio);
  CHECK(j.at("warnings").size() == 2);
}
