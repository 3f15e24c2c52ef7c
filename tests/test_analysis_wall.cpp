// Wall integrals of a position-dependent drive by Gauss–Kronrod quadrature, and the paper's
// general g1, g2 (eqs. g1, g2) built from gamma_E(x) and v_E(x) on the wall.
#include "billiards/analysis.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace billiards;
using geometry::pi;
using geometry::Vec2;

namespace {

geometry::Loop polygon(std::initializer_list<Vec2> vertices) {
  const std::vector<Vec2> v(vertices);
  geometry::Loop loop;
  for (std::size_t i = 0; i < v.size(); ++i) loop.pieces.push_back(geometry::Segment{v[i], v[(i + 1) % v.size()]});
  loop.where.resize(v.size());
  return loop;
}

/// A full circle: counter-clockwise (region inside) or clockwise (a hole, region outside).
geometry::Loop circle(Vec2 center, double r, bool inside) {
  const Vec2 start = center + Vec2(r, 0);
  geometry::Loop loop;
  loop.pieces.push_back(geometry::Arc{center, r, 0, inside ? 2 * pi : -2 * pi, start, start});
  loop.where.resize(1);
  return loop;
}

geometry::Region2 unit_square() {
  geometry::Region2 r;
  r.outer = polygon({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  return r;
}

geometry::Region2 unit_disk() {
  geometry::Region2 r;
  r.outer = circle({0, 0}, 1, true);
  return r;
}

/// Sinai's table: the unit square minus a disk of radius 1/4 at its center.
geometry::Region2 sinai() {
  geometry::Region2 r = unit_square();
  r.holes.push_back(circle({0.5, 0.5}, 0.25, false));
  return r;
}

geometry::Measures square_measures() {
  geometry::Measures m;
  m.volume = 1;
  m.surface = 4;
  m.boundary_tensor = 2 * Eigen::MatrixXd::Identity(2, 2);
  return m;
}

analysis::ForceField uniform(Vec2 F) {
  return [F](const Vec2&) { return F; };
}

/// F(x, y) = (2x − y, x + 3y + 1), used for a closed form on the unit square.
Vec2 linear_force(const Vec2& p) { return {2 * p.x() - p.y(), p.x() + 3 * p.y() + 1}; }

}  // namespace

TEST_CASE("uniform F: the quadrature is F^T T F, T = 2I (square), pi I (disk), (2 + pi/4) I (Sinai)") {
  const Vec2 F(0.3, -1.7);
  const double F2 = F.squaredNorm();
  const std::pair<geometry::Region2, double> cases[] = {{unit_square(), 2}, {unit_disk(), pi}, {sinai(), 2 + pi / 4}};
  for (const auto& [region, t] : cases) {
    const auto q = analysis::wall_integral(region, uniform(F));
    CHECK(q.value == Approx(t * F2).epsilon(1e-14));
    CHECK(q.error <= 1e-10 * q.value);
    // The geometry's exact tensor, through its own wall_integral, agrees.
    CHECK(q.value == Approx(geometry::wall_integral(geometry::measures_of(region), F)).epsilon(1e-14));
  }
}

TEST_CASE("linear F on the unit square: the closed form 76/3") {
  // F = (2x − y, x + 3y + 1).  Per side, ∫(F·n)² along it:
  //   bottom y = 0, n = −ŷ: ∫₀¹ (x + 1)² dx      = 7/3
  //   right  x = 1, n = +x̂: ∫₀¹ (2 − y)² dy      = 7/3
  //   top    y = 1, n = +ŷ: ∫₀¹ (x + 4)² dx      = 61/3
  //   left   x = 0, n = −x̂: ∫₀¹ y² dy            = 1/3
  const auto q = analysis::wall_integral(unit_square(), linear_force);
  CHECK(q.value == Approx(76.0 / 3).epsilon(1e-14));
}

TEST_CASE("linear F on the unit circle: closed forms with n = (cos t, sin t)") {
  const auto disk = unit_disk();
  // F = (x, 0): (F·n)² = cos⁴t, ∫₀^{2π} = 3π/4.
  CHECK(analysis::wall_integral(disk, [](const Vec2& p) { return Vec2(p.x(), 0); }).value ==
        Approx(3 * pi / 4).epsilon(1e-13));
  // F = (y, 0): sin²t cos²t, ∫ = π/4.
  CHECK(analysis::wall_integral(disk, [](const Vec2& p) { return Vec2(p.y(), 0); }).value ==
        Approx(pi / 4).epsilon(1e-13));
  // A rotation field is tangent to the wall: nothing.
  CHECK(std::abs(analysis::wall_integral(disk, [](const Vec2& p) { return Vec2(-p.y(), p.x()); }).value) < 1e-15);
}

TEST_CASE("general g1, g2 by quadrature with U = 0 agree with the closed forms") {
  const double mass = 1.3, omega = 25, E = 0.8;
  const Vec2 F(0.6, 1.1);
  analysis::Drive dr;
  dr.F = F;
  dr.omega = omega;
  dr.mass = mass;
  const auto m = square_measures();
  // γ_E(x) from eq. (gamma) with Σ(E) and v_E uniform: must equal the U = 0 closed form.
  const double v = analysis::local_speed(E, 0, mass), Sigma = analysis::density_of_states(m, mass, E);
  const double gamma = analysis::collision_rate_density(2, mass, v, Sigma);
  CHECK(gamma == Approx(analysis::collision_rate_density(m, mass, E)).epsilon(1e-14));
  auto gamma_E = [&](const Vec2&) { return gamma; };
  auto v_E = [&](const Vec2&) { return v; };
  CHECK(analysis::drift_g1(unit_square(), uniform(F), gamma_E, omega, mass).value ==
        Approx(analysis::drift_g1(m, dr, E)).epsilon(1e-13));
  CHECK(analysis::diffusion_g2(unit_square(), uniform(F), gamma_E, v_E, omega).value ==
        Approx(analysis::diffusion_g2(m, dr, E)).epsilon(1e-13));
  // 3-D: eq. (gamma) against the closed form too (B_2 v²/(m Σ) with Σ = 3 B_3 V v/m).
  geometry::Measures ball;
  ball.dimension = 3;
  ball.volume = 4 * pi / 3;
  ball.surface = 4 * pi;
  CHECK(analysis::collision_rate_density(3, mass, v, analysis::density_of_states(ball, mass, E)) ==
        Approx(analysis::collision_rate_density(ball, mass, E)).epsilon(1e-14));
}

TEST_CASE("local speed v_E(x) is zero where the potential exceeds E") {
  CHECK(analysis::local_speed(2, 0.5, 3) == Approx(1).epsilon(1e-15));
  CHECK(analysis::local_speed(2, 2.5, 3) == 0);
}

TEST_CASE("fluctuation-dissipation with a potential: g1 = (1/2 Sigma) d/dE (g2 Sigma) from eqs. (g1), (g2)") {
  // U(x, y) = 0.3x + 0.2y on the unit square, F(x) linear, m = 1.3.  For d = 2,
  // Σ(E) = (2π/m)·area{U < E}; below E = 0.5 the corner U ≥ E, a triangle with legs
  // (0.5 − E)/0.3 and (0.5 − E)/0.2, is forbidden, and v_E vanishes on part of the wall (the
  // quadrature must find those turning points: missing one costs ~1e-7 here).
  const double mass = 1.3, omega = 25;
  auto U = [](const Vec2& p) { return 0.3 * p.x() + 0.2 * p.y(); };
  auto Sigma = [&](double E) {
    const double gap = std::max(0.0, 0.5 - E);
    return 2 * pi / mass * (1 - gap * gap / 0.12);
  };
  auto g2_at = [&](double E) {
    auto v_E = [&](const Vec2& x) { return analysis::local_speed(E, U(x), mass); };
    auto gamma_E = [&](const Vec2& x) { return analysis::collision_rate_density(2, mass, v_E(x), Sigma(E)); };
    return analysis::diffusion_g2(unit_square(), linear_force, gamma_E, v_E, omega, 1e-13).value;
  };
  for (double E : {0.45, 1.0, 3.0}) {
    INFO("E = " << E);
    auto v_E = [&](const Vec2& x) { return analysis::local_speed(E, U(x), mass); };
    auto gamma_E = [&](const Vec2& x) { return analysis::collision_rate_density(2, mass, v_E(x), Sigma(E)); };
    const auto g1 = analysis::drift_g1(unit_square(), linear_force, gamma_E, omega, mass, 1e-13);
    const double h = 1e-5;  // central differences: error ~ 2e-10 relative here
    const double rhs = (g2_at(E + h) * Sigma(E + h) - g2_at(E - h) * Sigma(E - h)) / (2 * h) / (2 * Sigma(E));
    CHECK(g1.value == Approx(rhs).epsilon(1e-8));
    CHECK(g1.error < 1e-12 * g1.value);
  }
}

TEST_CASE("turning points on the wall: g1 against its closed form for 200 energies") {
  // U = 0.3x + 0.2y on the unit square, F = ŷ: only the bottom (U = 0.3x) and the top
  // (U = 0.2 + 0.3x) count, (F·n)² = 1.  With Σ fixed, g1 = 2 ω⁻²/m · B_1/(m Σ) · ∫ v_E dS and
  //   ∫₀¹ √(2(E − a − 0.3x)/m)₊ dx = √(2/m) · (2/3)[(E − a)₊^{3/2} − (E − a − 0.3)₊^{3/2}]/0.3.
  // For 0.2 < E < 0.5 the top has a turning point at x = (E − 0.2)/0.3; sweeping E moves it
  // across every position relative to the quadrature's nodes.
  const double mass = 1.3, omega = 25, Sigma = 2.0;
  auto edge = [&](double E, double a) {
    auto p32 = [](double t) { return t > 0 ? std::pow(t, 1.5) : 0.0; };
    return std::sqrt(2 / mass) * (2.0 / 3) * (p32(E - a) - p32(E - a - 0.3)) / 0.3;
  };
  for (int k = 0; k < 200; ++k) {
    const double E = 0.2005 + 0.2985 * k / 199;
    auto gamma_E = [&](const Vec2& x) {
      return analysis::collision_rate_density(2, mass, analysis::local_speed(E, 0.3 * x.x() + 0.2 * x.y(), mass),
                                              Sigma);
    };
    const double exact = 2 / (omega * omega * mass) * 2 / (mass * Sigma) * (edge(E, 0) + edge(E, 0.2));
    INFO("E = " << E);
    CHECK(analysis::drift_g1(unit_square(), uniform(Vec2(0, 1)), gamma_E, omega, mass).value ==
          Approx(exact).epsilon(1e-11));
  }
}
