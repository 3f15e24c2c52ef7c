// The theory with a potential (analysis/potential.hpp): Σ(E) by strip quadrature against the
// exact area (U = 0) and against closed forms for harmonic bowls in the circle and the stadium;
// γ_E, g1, g2 against hand-derived closed forms; the fluctuation–dissipation relation with
// U ≠ 0; the Fokker–Planck equation driven by the quadrature coefficients, and the general
// solver (Gaussian start, range, tabulation) against the analytic η and the short-time moments.
#include "cli_helpers.hpp"

#include "billiards/analysis.hpp"
#include "billiards/dynamics/scene.hpp"
#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

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
    const auto by_quadrature = analysis::evolve_fokker_planck(grid, eta0, analysis::tabulate(grid, quad), t - 0.05 / C, 300);
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
    // (zero below the threshold, where v = 0, also at E = 0 where Σ = 0)
    auto g1 = [&](double E) { return v(E) > 0 ? 2 / (omega * omega * m) * 2 / m * v(E) / Sigma(E) * wall : 0.0; };
    auto g2 = [&](double E) {
      return v(E) > 0 ? 4 / (3 * omega * omega) * 2 / m * std::pow(v(E), 3) / Sigma(E) * wall : 0.0;
    };
    const auto quad = analysis::energy_coefficients(region, bowl(k), uniform(F), omega, m);
    const auto grid = analysis::quartic_root_grid(10, 200);
    std::vector<double> eta0(grid.cells());
    for (std::size_t i = 0; i < eta0.size(); ++i) eta0[i] = std::exp(-std::pow((grid.center(i) - E0) / 0.1, 2));
    const double t = 0.5 / g1(E0);
    const auto by_quadrature = analysis::evolve_fokker_planck(grid, eta0, analysis::tabulate(grid, quad), t, 200);
    const auto closed = analysis::evolve_fokker_planck(grid, eta0, g1, g2, t, 200);
    double mass = 0;
    for (std::size_t i = 0; i < eta0.size(); ++i) mass += eta0[i] * grid.width(i);
    CHECK(l1(grid, by_quadrature, closed) <= 1e-9 * mass);  // measured 4.8e-12 of the mass
    CHECK(l1(grid, closed, eta0) >= 0.05 * mass);  // it did evolve
  }
}

namespace {

/// The paper's clover under F = 10 along (1, 1)/√2 at E0 = 1/2, with `extra` scene keys; loaded.
dynamics::Scene clover_scene(const std::string& name, const std::string& omega, const std::string& extra) {
  static const auto dir = scratch("analysis-fp-scenes");
  const auto path = dir / (name + ".yaml");
  std::ofstream(path) << "shape: " BILLIARDS_SOURCE_DIR "/shapes/clover.yaml\nparameters: {F: 10, omega: " << omega
                      << "}\ninitial:\n  microcanonical: {energy: 1/2}\nforce:\n  periodic: {amplitude: "
                         "[F/sqrt(2), F/sqrt(2)], omega: omega}\nrun: {particles: 10, time: 1}\n"
                      << extra;
  return dynamics::load_scene(path.string(), {});
}

double mass_of(const analysis::EnergyGrid& grid, const std::vector<double>& eta) {
  double m = 0;
  for (std::size_t i = 0; i < eta.size(); ++i) m += eta[i] * grid.width(i);
  return m;
}

}  // namespace

TEST_CASE("the general Fokker-Planck solver: U = 0 given as a potential reproduces the analytic eta") {
  // The potential "0" sends the scene through the quadrature coefficients (closed_form false),
  // the Gaussian start, the range walk and the tabulation: end to end against eq. (B4).
  const auto scene = clover_scene("zero", "40*pi", "potential: {expression: \"0\"}\n");
  const auto flat = analysis::prediction_of(clover_scene("flat", "40*pi", ""));
  REQUIRE(!analysis::prediction_of(scene)->closed_form);
  const double C = flat->C, E0 = 0.5;
  const std::vector<double> s{0.1, 1, 10};
  std::vector<double> t;
  for (double sk : s) t.push_back(sk / C);
  const int cells = 1500;
  const auto sol = *analysis::fokker_planck_of(scene, t, cells);
  CHECK(sol.evaluations <= std::size_t(cells) + 100);  // tabulated once, plus the range walk
  for (std::size_t k = 0; k < s.size(); ++k) {
    // Cell masses against the exact CDF's increments.
    double l1 = 0;
    for (std::size_t i = 0; i < sol.grid.cells(); ++i)
      l1 += std::abs(sol.eta[k][i] * sol.grid.width(i) - (analysis::fokker_planck_cdf(sol.grid.edges[i + 1], s[k], E0, 2) -
                                                            analysis::fokker_planck_cdf(sol.grid.edges[i], s[k], E0, 2)));
    INFO("s = " << s[k] << ": L1 = " << l1 << ", resolution " << sol.resolution << " cells");
    CHECK(l1 <= 1e-3);
    const auto m = analysis::moments_of(sol.grid, sol.eta[k]);
    const auto exact = analysis::fokker_planck_exact_moments(s[k], E0, 2);
    CHECK(m.mean == Approx(exact.mean).epsilon(1e-3));
    CHECK(m.variance == Approx(exact.variance).epsilon(1e-2));
  }
}

TEST_CASE("the general Fokker-Planck solver with a potential: mass conserved, eta >= 0, d<E>/dt = <g1>") {
  // The clover tilted by U = 0.4 y at 40 pi: by t = 3000 eta spreads over most of the energies
  // between the lowest U on the wall (where g2 -> 0) and several times E0.
  const auto scene = clover_scene("tilt40", "40*pi", "potential: {expression: 0.4*y}\n");
  const std::vector<double> t{10, 100, 1000, 1001, 3000};
  const auto sol = *analysis::fokker_planck_of(scene, t, 800);
  const auto& grid = sol.grid;
  double previous_mean = 0.5;
  for (std::size_t k = 0; k < t.size(); ++k) {
    INFO("t = " << t[k]);
    CHECK(std::abs(mass_of(grid, sol.eta[k]) - 1) < 1e-12);
    CHECK(*std::min_element(sol.eta[k].begin(), sol.eta[k].end()) >= 0);
    const double mean = analysis::moments_of(grid, sol.eta[k]).mean;
    CHECK(mean > previous_mean);  // g1 >= 0: the mean never decreases (Fermi acceleration)
    previous_mean = mean;
  }
  // The wide solution reaches down towards the floor: g2 -> 0 there is exercised.
  CHECK(analysis::cdf_of(grid, sol.eta.back())(0.0) > 0.01);
  // The mean's rate between t = 1000 and 1001 is <g1> over eta (the FP equation's first moment).
  const auto U = [](const Vec2& x) { return 0.4 * x.y(); };
  const auto g = analysis::energy_coefficients(scene.shape<2>().region, U, uniform(Vec2(10, 10) / std::sqrt(2.0)),
                                               40 * pi, 1, 1e-10);
  const auto table = analysis::tabulate(grid, g);
  double mean_g1 = 0;
  for (std::size_t i = 0; i < grid.cells(); ++i) {
    const double eta = 0.5 * (sol.eta[2][i] + sol.eta[3][i]);
    mean_g1 += eta * grid.width(i) * 0.5 * (table.g1[i] + table.g1[i + 1]);
  }
  const double rate = analysis::moments_of(grid, sol.eta[3]).mean - analysis::moments_of(grid, sol.eta[2]).mean;
  CHECK(rate == Approx(mean_g1).epsilon(1e-2));
}

TEST_CASE("the general Fokker-Planck solver with a potential: short-time moments g1 t and g2 t") {
  // The clover tilted by U = 0.4 y at 320 pi (test_field_flight's scene): at t = 8 the second-
  // order terms ½ t² (g1 g1' + ½ g2 g1'') and ½ t² (g1 g2' + ½ g2 g2'' + 2 g2 g1') are below
  // 1e-3 of g1 t, g2 t (computed here from the quadratures), so mean − E0 and Var must equal
  // g1 t and g2 t to that order; 3e-3 leaves room for the grid (400 cells over ±7σ: each adds
  // width²/12 to the variance, ~3e-4 of it) and the time steps (measured 2e-4 and 6e-4).
  const auto scene = clover_scene("tilt320", "320*pi", "potential: {expression: 0.4*y}\n");
  const auto U = [](const Vec2& x) { return 0.4 * x.y(); };
  const auto g = analysis::energy_coefficients(scene.shape<2>().region, U, uniform(Vec2(10, 10) / std::sqrt(2.0)),
                                               320 * pi, 1, 1e-10);
  const double E0 = 0.5, h = 0.01, t = 8;
  const auto lo = g(E0 - h), mid = g(E0), hi = g(E0 + h);
  const double g1p = (hi.g1 - lo.g1) / (2 * h), g1pp = (hi.g1 - 2 * mid.g1 + lo.g1) / (h * h);
  const double g2p = (hi.g2 - lo.g2) / (2 * h), g2pp = (hi.g2 - 2 * mid.g2 + lo.g2) / (h * h);
  const double second_mean = 0.5 * t * t * (mid.g1 * g1p + 0.5 * mid.g2 * g1pp);
  const double second_var = 0.5 * t * t * (mid.g1 * g2p + 0.5 * mid.g2 * g2pp + 2 * mid.g2 * g1p);
  INFO("g1 t = " << mid.g1 * t << " (2nd order " << second_mean << "), g2 t = " << mid.g2 * t << " (2nd order "
                 << second_var << ")");
  REQUIRE(std::abs(second_mean) < 1e-3 * mid.g1 * t);
  REQUIRE(std::abs(second_var) < 1e-3 * mid.g2 * t);
  const auto sol = *analysis::fokker_planck_of(scene, {t}, 400);
  const auto m = analysis::moments_of(sol.grid, sol.eta[0]);
  INFO("numerical: mean - E0 = " << m.mean - E0 << ", variance = " << m.variance);
  CHECK(m.mean - E0 == Approx(mid.g1 * t).epsilon(3e-3));
  CHECK(m.variance == Approx(mid.g2 * t).epsilon(3e-3));
  CHECK(std::abs(m.norm - 1) < 1e-12);
}
