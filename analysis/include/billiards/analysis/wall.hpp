// Integrals over the billiard wall for a position-dependent drive F(x), and the paper's general
// drift and diffusion coefficients (eqs. g1, g2), which need only γ_E(x) and v_E(x) on the wall
// and so serve a potential U(x) as well as the standard billiard.  Two-dimensional tables.
#pragma once

#include "billiards/analysis/quadrature.hpp"
#include "billiards/geometry/pieces.hpp"

#include <functional>

namespace billiards::analysis {

using ForceField = std::function<geometry::Vec2(const geometry::Vec2&)>;  // F(x)
using ScalarField = std::function<double(const geometry::Vec2&)>;         // e.g. γ_E(x), v_E(x)
/// Integrand f(x, n̂) at a wall point x with outward unit normal n̂.
using WallIntegrand = std::function<double(const geometry::Vec2& x, const geometry::Vec2& n)>;

/// ∮ f(x, n̂) dS over every loop of the region (holes included), by adaptive Gauss–Kronrod on
/// each piece separately (integrate_adaptive in the arc-length fraction): the normal jumps only
/// at joints, so the integrand is smooth on a piece.  Errors are summed over the pieces.
Quadrature wall_quadrature(const geometry::Region2& region, const WallIntegrand& f, double tolerance = 1e-10);

/// The largest f(x) on the wall, sampled at 257 points per piece (its ends included).
double wall_maximum(const geometry::Region2& region, const ScalarField& f);

/// ∮ (F(x)·n̂)² dS.  For a uniform F this is Fᵀ T F with T = ∮ n̂ n̂ᵀ dS (geometry::wall_integral).
Quadrature wall_integral(const geometry::Region2& region, const ForceField& F, double tolerance = 1e-10);

/// v_E(x) = √(2 (E − U(x))/m) where U(x) ≤ E, else 0 (eq. defvE).
double local_speed(double E, double U, double mass);
/// γ_E(x) = B_{d−1}/m · v_E(x)^{d−1}/Σ(E), the collision rate per unit wall (eq. gamma).
double collision_rate_density(int d, double mass, double v_E, double Sigma);

// Both split every piece where γ_E(x) > 0 switches on or off (turning points U(x) = E on the
// wall, where the integrands have square-root kinks), located by sampling each piece at 64
// points and bisecting; a stretch shorter than 1/64 of a piece may go unnoticed.

/// g1(E, ω) = 2 ω⁻²/m ∮ γ_E (F·n̂)² dS  (eq. g1), with γ_E evaluated on the wall.
Quadrature drift_g1(const geometry::Region2& region, const ForceField& F, const ScalarField& gamma_E, double omega,
                    double mass, double tolerance = 1e-10);
/// g2(E, ω) = 4 ω⁻²/(d+1) ∮ γ_E v_E² (F·n̂)² dS  (eq. g2), d = 2.
Quadrature diffusion_g2(const geometry::Region2& region, const ForceField& F, const ScalarField& gamma_E,
                        const ScalarField& v_E, double omega, double tolerance = 1e-10);

}  // namespace billiards::analysis
