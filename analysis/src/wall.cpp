#include "billiards/analysis/wall.hpp"

#include "billiards/geometry/measures.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace billiards::analysis {

using geometry::Vec2;

namespace {

/// Scales a quadrature by a constant prefactor, error included.
Quadrature times(double factor, Quadrature q) { return {factor * q.value, std::abs(factor) * q.error}; }

void accumulate(Quadrature& total, const Quadrature& q) {
  total.value += q.value;
  total.error += q.error;
}

double normal_force2(const ForceField& F, const Vec2& x, const Vec2& n) {
  const double Fn = F(x).dot(n);
  return Fn * Fn;
}

/// ∫ f dS over one piece between arc-length fractions `from` and `to`.
Quadrature piece_quadrature(const geometry::Piece& piece, const WallIntegrand& f, double from, double to,
                            double tolerance) {
  // u is the arc-length fraction, so dS = length · du.
  auto along = [&](double u) {
    const Vec2 x = geometry::point_along(piece, u);
    return f(x, geometry::outward_normal(piece, x));
  };
  return times(geometry::length_of(piece), integrate_adaptive(along, from, to, tolerance));
}

/// Σ of per_piece(piece) over every piece of every loop.
template <class PerPiece>
Quadrature sum_over_pieces(const geometry::Region2& region, PerPiece per_piece) {
  Quadrature total;
  for (const geometry::Loop* loop : region.loops())
    for (const geometry::Piece& piece : loop->pieces) accumulate(total, per_piece(piece));
  return total;
}

/// Arc-length fractions 0 = u0 < u1 < ... < 1 at which γ_E(x) > 0 switches on or off along the
/// piece: the wall's turning points, U(x) = E, where v_E has a square-root kink.  A Gauss rule
/// never samples its interval's ends, so a kink close to a subinterval's end can hide from the
/// error estimate; splitting there removes the kinks.  Sampled at 64 points, then bisected to
/// rounding: an accessible (or forbidden) stretch shorter than 1/64 of the piece may be missed.
std::vector<double> turning_points(const geometry::Piece& piece, const ScalarField& gamma_E) {
  constexpr int samples = 64;
  auto accessible = [&](double u) { return gamma_E(geometry::point_along(piece, u)) > 0; };
  std::vector<double> cuts{0};
  bool before = accessible(0);
  for (int k = 1; k <= samples; ++k) {
    double lo = double(k - 1) / samples, hi = double(k) / samples;
    const bool after = accessible(hi);
    if (after == before) continue;
    for (double mid = (lo + hi) / 2; lo < mid && mid < hi; mid = (lo + hi) / 2) {
      if (accessible(mid) == before)
        lo = mid;
      else
        hi = mid;
    }
    cuts.push_back(hi);
    before = after;
  }
  cuts.push_back(1);
  return cuts;
}

/// ∮ f dS with each piece split at its turning points.
Quadrature accessible_wall_quadrature(const geometry::Region2& region, const WallIntegrand& f,
                                      const ScalarField& gamma_E, double tolerance) {
  return sum_over_pieces(region, [&](const geometry::Piece& piece) {
    const auto cuts = turning_points(piece, gamma_E);
    Quadrature total;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
      accumulate(total, piece_quadrature(piece, f, cuts[i], cuts[i + 1], tolerance));
    return total;
  });
}

}  // namespace

Quadrature wall_quadrature(const geometry::Region2& region, const WallIntegrand& f, double tolerance) {
  return sum_over_pieces(region,
                         [&](const geometry::Piece& piece) { return piece_quadrature(piece, f, 0, 1, tolerance); });
}

double wall_maximum(const geometry::Region2& region, const ScalarField& f) {
  double largest = -INFINITY;
  for (const geometry::Loop* loop : region.loops())
    for (const geometry::Piece& piece : loop->pieces)
      for (int k = 0; k <= 256; ++k) largest = std::max(largest, f(geometry::point_along(piece, k / 256.0)));
  return largest;
}

Quadrature wall_integral(const geometry::Region2& region, const ForceField& F, double tolerance) {
  return wall_quadrature(
      region, [&](const Vec2& x, const Vec2& n) { return normal_force2(F, x, n); }, tolerance);
}

double local_speed(double E, double U, double mass) { return U <= E ? std::sqrt(2 * (E - U) / mass) : 0.0; }

double collision_rate_density(int d, double mass, double v_E, double Sigma) {
  return geometry::unit_ball_volume(d - 1) / mass * std::pow(v_E, d - 1) / Sigma;
}

Quadrature drift_g1(const geometry::Region2& region, const ForceField& F, const ScalarField& gamma_E, double omega,
                    double mass, double tolerance) {
  auto integrand = [&](const Vec2& x, const Vec2& n) { return gamma_E(x) * normal_force2(F, x, n); };
  return times(2 / (omega * omega * mass), accessible_wall_quadrature(region, integrand, gamma_E, tolerance));
}

Quadrature diffusion_g2(const geometry::Region2& region, const ForceField& F, const ScalarField& gamma_E,
                        const ScalarField& v_E, double omega, double tolerance) {
  constexpr int d = 2;
  auto integrand = [&](const Vec2& x, const Vec2& n) {
    const double v = v_E(x);
    return gamma_E(x) * v * v * normal_force2(F, x, n);
  };
  return times(4 / (omega * omega * (d + 1)), accessible_wall_quadrature(region, integrand, gamma_E, tolerance));
}

}  // namespace billiards::analysis
