// The theory with a potential (analysis/potential.hpp): Σ(E) by strip quadrature against the
// exact area (U = 0) and against closed forms for harmonic bowls in the circle and the stadium;
// γ_E, g1, g2 against hand-derived closed forms; the fluctuation–dissipation relation with
// U ≠ 0; and the Fokker–Planck equation driven by the quadrature coefficients.
#include "billiards/analysis.hpp"
#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace billiards;
using geometry::pi;
using geometry::Vec2;

namespace {

geometry::Region2 shape(const std::string& name, const Overrides& set = {}) {
  return geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR) + "/shapes/" + name + ".yaml", set).region;
}

/// U = k |x − c|²/2.
analysis::Potential bowl(double k, Vec2 c = Vec2::Zero()) {
  return [k, c](const Vec2& x) { return 0.5 * k * (x - c).squaredNorm(); };
}

analysis::ForceField uniform(Vec2 F) {
  return [F](const Vec2&) { return F; };
}

/// Area of the intersection of two disks (radii r1, r2, centres d apart), closed form.
double lens_area(double r1, double r2, double d) {
  const double a1 = std::acos((d * d + r1 * r1 - r2 * r2) / (2 * d * r1));
  const double a2 = std::acos((d * d + r2 * r2 - r1 * r1) / (2 * d * r2));
  return r1 * r1 * a1 + r2 * r2 * a2 -
         0.5 * std::sqrt((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2));
}

const analysis::Potential flat = [](const Vec2&) { return 0.0; };

}  // namespace

TEST_CASE("U = 0: the allowed area is the exact area of every kind of table") {
  // Arcs (focusing and dispersing), holes, non-convex polygons, tangent joints.
  for (const char* name : {"clover", "stadium", "sinai", "mushroom", "circle", "annulus", "l-room", "triangle"}) {
    const auto region = shape(name);
    const double V = geometry::measures_of(region).volume;
    const auto a = analysis::allowed_area(region, flat, 1.0);
    INFO(name << ": " << a.value << " ± " << a.error << " vs " << V);
    CHECK(std::abs(a.value - V) <= 1e-9 * V);
    CHECK(a.error <= 1e-8 * V);
    CHECK(std::abs(a.value - V) <= a.error + 1e-14 * V);  // the estimate bounds the error
    // Σ(E) = d B_d V v^{d−2}/m, the analysis layer's U = 0 formula.
    const double m = 1.7, E = 0.3;
    CHECK(analysis::density_of_states(region, flat, E, m).value ==
          Approx(analysis::density_of_states(geometry::measures_of(region), m, E)).epsilon(1e-9));
  }
}

TEST_CASE("a harmonic bowl centred in the circle: Sigma, gamma_E, g1, g2 in closed form") {
  const auto region = shape("circle", {{"R", "1.3"}});
  const double R = 1.3, k = 2.5, m = 1.5, omega = 40 * pi;
  const Vec2 F(3, -4);
  const auto U = bowl(k);
  for (double E : {0.4, 1.0, 2.2, 5.0}) {
    INFO("E = " << E);
    const double rE2 = 2 * E / k, threshold = 0.5 * k * R * R;
    const double Sigma = 2 * pi / m * pi * std::min(rE2, R * R);
    const auto c = analysis::potential_coefficients(region, U, uniform(F), E, omega, m);
    CHECK(c.Sigma.value == Approx(Sigma).epsilon(1e-10));
    // On the wall v_E = √(2(E − kR²/2)/m) (0 below the threshold), γ_E = (2/m) v/Σ, and
    // ∮ (F·n)² dS = π R |F|².
    const double v = E > threshold ? std::sqrt(2 * (E - threshold) / m) : 0;
    const double gamma = 2 / m * v / Sigma;
    const auto gamma_field = analysis::collision_rate_field(U, E, m, c.Sigma.value);
    CHECK(gamma_field(Vec2(0, R)) == Approx(gamma).epsilon(1e-10));
    const double wall = pi * R * F.squaredNorm();
    CHECK(c.g1.value == Approx(2 / (omega * omega * m) * gamma * wall).epsilon(1e-9).margin(1e-300));
    CHECK(c.g2.value == Approx(4 / (3 * omega * omega) * gamma * v * v * wall).epsilon(1e-9).margin(1e-300));
  }
}

TEST_CASE("an off-centre bowl crossing the circle's wall: the lens area, gamma_E zero where U > E") {
  const auto region = shape("circle");  // R = 1
  const double k = 2, m = 1;
  const Vec2 c(0.4, 0.1);
  const auto U = bowl(k, c);
  for (double rho : {0.3, 0.9, 1.2}) {
    const double E = 0.5 * k * rho * rho;
    INFO("rho = " << rho);
    const auto S = analysis::density_of_states(region, U, E, m);
    const double area = rho + c.norm() <= 1 ? pi * rho * rho : lens_area(1, rho, c.norm());
    CHECK(S.value == Approx(2 * pi / m * area).epsilon(1e-10));
    CHECK(S.error <= 1e-9 * S.value);
    CHECK(std::abs(S.value - 2 * pi / m * area) <= S.error + 1e-14 * S.value);
    const auto gamma = analysis::collision_rate_field(U, E, m, S.value);
    for (double phi = 0; phi < 2 * pi; phi += 0.1) {
      const Vec2 x(std::cos(phi), std::sin(phi));
      const double d = (x - c).norm();
      if (d > rho) CHECK(gamma(x) == 0);
      if (d < rho) CHECK(gamma(x) == Approx(2 / m * std::sqrt(k / m * (rho * rho - d * d)) / S.value));
    }
  }
}

TEST_CASE("a bowl in the stadium, inside it and crossing its flat walls: Sigma, g1, g2 in closed form") {
  // Straight walls y = ±r from x = −a to a; the disk U < E of radius ρ < a meets only them.
  const double r = 1, k = 1.5, m = 0.8, omega = 320 * pi;
  const auto region = shape("stadium", {{"a", "2"}, {"r", "1"}});
  const Vec2 F(1.5, 2.5);
  const auto U = bowl(k);
  for (double rho : {0.8, 1.5}) {
    INFO("rho = " << rho);
    const double E = 0.5 * k * rho * rho;
    const double area = rho <= r ? pi * rho * rho
                                 : 2 * (r * std::sqrt(rho * rho - r * r) + rho * rho * std::asin(r / rho));
    const double Sigma = 2 * pi / m * area;
    const auto cf = analysis::potential_coefficients(region, U, uniform(F), E, omega, m);
    CHECK(cf.Sigma.value == Approx(Sigma).epsilon(1e-10));
    // On y = ±r: v = √(k/m) √(c² − x²), c² = ρ² − r², and ∫ (c² − x²)^{1/2} = πc²/2,
    // ∫ (c² − x²)^{3/2} = 3πc⁴/8 over |x| < c; two walls, (F·n)² = F_y².
    const double c2 = std::max(0.0, rho * rho - r * r), Fy2 = F.y() * F.y();
    const double wall_gamma = 2 * Fy2 * 2 / (m * Sigma) * std::sqrt(k / m) * pi * c2 / 2;
    const double wall_gamma_v2 = 2 * Fy2 * 2 / (m * Sigma) * std::pow(k / m, 1.5) * 3 * pi * c2 * c2 / 8;
    CHECK(cf.g1.value == Approx(2 / (omega * omega * m) * wall_gamma).epsilon(1e-8).margin(1e-300));
    CHECK(cf.g2.value == Approx(4 / (3 * omega * omega) * wall_gamma_v2).epsilon(1e-8).margin(1e-300));
    if (rho > r) {
      CHECK(cf.g1.value > 0);
      CHECK(cf.g1.error <= 1e-8 * cf.g1.value);
    }
  }
}

TEST_CASE("fluctuation-dissipation with U != 0: g1 = (1/2 Sigma) d/dE (g2 Sigma)") {
  // A position-dependent drive too, so nothing is uniform.
  const analysis::ForceField F = [](const Vec2& x) { return Vec2(1 + x.y(), 2 - 0.5 * x.x() * x.x()); };
  const double omega = 100, m = 1.3;
  struct Case {
    const char* name;
    geometry::Region2 region;
    analysis::Potential U;
    double E;
  };
  const Case cases[] = {
      {"off-centre bowl in the circle", shape("circle"), bowl(2, Vec2(0.4, 0.1)), 0.6},
      {"bowl crossing the stadium's walls", shape("stadium", {{"a", "2"}}), bowl(1.5), 1.2},
      {"tilted clover", shape("clover"), [](const Vec2& x) { return 0.3 * x.x() + 0.2 * x.y() * x.y(); }, 0.7},
  };
  for (const auto& c : cases) {
    INFO(c.name);
    const auto direct = analysis::potential_coefficients(c.region, c.U, F, c.E, omega, m, 1e-12);
    const auto fd = analysis::fluctuation_dissipation_g1(c.region, c.U, F, c.E, omega, m);
    CHECK(direct.g1.value > 0);
    CHECK(fd.value == Approx(direct.g1.value).epsilon(1e-6));
  }
}

TEST_CASE("Fokker-Planck driven by the quadrature coefficients") {
  const double m = 1, omega = 40 * pi, E0 = 2;
  const Vec2 F(3, 4);
  auto l1 = [](const analysis::EnergyGrid& grid, const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0;
    for (std::size_t i = 0; i < a.size(); ++i) s += std::abs(a[i] - b[i]) * grid.width(i);
    return s;
  };
  SECTION("U = 0 in the stadium: the closed-form coefficients and the analytic eta") {
    const auto region = shape("stadium");
    const auto measures = geometry::measures_of(region);
    analysis::Drive drive{Eigen::Vector2d(F.x(), F.y()), omega, m};
    const double C = analysis::constant_C(measures, drive), t = 0.5 / C;  // s = C t = 0.5
    const auto grid = analysis::quartic_root_grid(30, 300);
    std::vector<double> eta0(grid.cells());
    for (std::size_t i = 0; i < eta0.size(); ++i) eta0[i] = analysis::fokker_planck_eta(grid.center(i), 0.05, E0, 2);
    const auto quad = analysis::energy_coefficients(region, flat, uniform(F), omega, m);
    const auto by_quadrature = analysis::evolve_fokker_planck(grid, eta0, quad.g1, quad.g2, t - 0.05 / C, 300);
    const auto closed = analysis::evolve_fokker_planck(
        grid, eta0, [C](double E) { return C * std::sqrt(E); },
        [C](double E) { return 4 * C * std::pow(E, 1.5) / 3; }, t - 0.05 / C, 300);
    std::vector<double> exact(grid.cells());
    for (std::size_t i = 0; i < exact.size(); ++i) exact[i] = analysis::fokker_planck_eta(grid.center(i), 0.5, E0, 2);
    CHECK(l1(grid, by_quadrature, closed) <= 1e-9);  // measured 1.3e-11
    CHECK(l1(grid, by_quadrature, exact) <= 3e-3);  // measured 1.1e-3 (300 cells, 300 steps)
  }
  SECTION("a bowl centred in the circle, whose wall is reached only above E = kR^2/2") {
    const auto region = shape("circle");
    const double k = 2, threshold = 0.5 * k;  // R = 1
    const double wall = pi * F.squaredNorm();
    auto Sigma = [&](double E) { return 2 * pi / m * pi * std::min(2 * E / k, 1.0); };
    auto v = [&](double E) { return E > threshold ? std::sqrt(2 * (E - threshold) / m) : 0.0; };
    auto g1 = [&](double E) { return 2 / (omega * omega * m) * 2 / m * v(E) / Sigma(E) * wall; };
    auto g2 = [&](double E) { return 4 / (3 * omega * omega) * 2 / m * std::pow(v(E), 3) / Sigma(E) * wall; };
    const auto quad = analysis::energy_coefficients(region, bowl(k), uniform(F), omega, m);
    const auto grid = analysis::quartic_root_grid(10, 200);
    std::vector<double> eta0(grid.cells());
    for (std::size_t i = 0; i < eta0.size(); ++i) eta0[i] = std::exp(-std::pow((grid.center(i) - E0) / 0.1, 2));
    const double t = 0.5 / g1(E0);
    const auto by_quadrature = analysis::evolve_fokker_planck(grid, eta0, quad.g1, quad.g2, t, 200);
    const auto closed = analysis::evolve_fokker_planck(grid, eta0, g1, g2, t, 200);
    double mass = 0;
    for (std::size_t i = 0; i < eta0.size(); ++i) mass += eta0[i] * grid.width(i);
    CHECK(l1(grid, by_quadrature, closed) <= 1e-9 * mass);  // measured 4.8e-12 of the mass
    CHECK(l1(grid, closed, eta0) >= 0.05 * mass);  // it did evolve
  }
}
