// The theory with a potential U(x) ≠ 0 (the paper's section 3 in general): the density of states
// Σ(E), the fields v_E(x) and γ_E(x), the drift and diffusion coefficients g1(E), g2(E) of a
// position-dependent drive F(x) cos(ωt), the fluctuation–dissipation check, and the
// Fokker–Planck equation driven by those coefficients.  Two-dimensional tables; U and F are
// callables, so a scene's expressions (or a closed form in a test) plug in directly.
//
// Σ(E) ≡ ∫ dᵈx dᵈv δ(E − ½m|v|² − U(x)) (eq. dos; velocities, not momenta, as in the paper).
// The velocity integral over the sphere |v| = v_E(x) gives |S^{d−1}| v_E^{d−1}/(m v_E) =
// d B_d v_E^{d−2}/m, so
//     Σ(E) = (d B_d/m) ∫_{U(x)<E} v_E(x)^{d−2} dᵈx,
// which in d = 2 is Σ(E) = (2π/m) · area{x ∈ Ω : U(x) < E}, and for U = 0 the paper's
// d B_d V v_E^{d−2}/m.
#pragma once

#include "billiards/analysis/coefficients.hpp"
#include "billiards/analysis/fokker_planck.hpp"
#include "billiards/analysis/quadrature.hpp"
#include "billiards/analysis/wall.hpp"
#include "billiards/geometry/pieces.hpp"

#include <functional>

namespace billiards::analysis {

using Potential = ScalarField;  // U(x)

/// area{x ∈ Ω : U(x) < E} by quadrature over vertical strips.  Ω is cut at the abscissae of
/// its joints and of its arcs' leftmost and rightmost points, so that on each strip the chord
/// Ω(x) is a fixed number of intervals with smooth ends; each strip is cut again where the
/// number of roots of U(x, ·) − E in Ω(x) changes (the turning curve U = E meets the wall or
/// has a vertical tangent: square-root kinks of the chord length), found by sampling each strip
/// at 64 abscissae and bisecting.  The length of {y : U(x, y) < E} ∩ Ω(x) comes from the roots
/// of U(x, ·) − E, bracketed by sampling each interval at 32 points (and at the minimum of U,
/// by Brent's method, where three forbidden samples dip) and bisected to rounding.
/// The x integral is integrate_adaptive on each piece of strip; the error is the sum of its
/// Gauss–Kronrod estimates.  Missed: a second dip of U below E between two samples of a chord,
/// a forbidden bump narrower than 1/32 of it, a kink closer than 1/64 of a strip to another.
Quadrature allowed_area(const geometry::Region2& region, const Potential& U, double E, double tolerance = 1e-10);

/// Σ(E) = (2π/m) · allowed_area (d = 2, see the header comment).
Quadrature density_of_states(const geometry::Region2& region, const Potential& U, double E, double mass,
                             double tolerance = 1e-10);

/// v_E(x) = √(2(E − U(x))/m) where U ≤ E, else 0 (eq. defvE).
ScalarField speed_field(Potential U, double E, double mass);
/// γ_E(x) = B_1/m · v_E(x)/Σ(E) (eq. gamma, d = 2), zero where U > E.
ScalarField collision_rate_field(Potential U, double E, double mass, double Sigma);

/// Σ, g1, g2 at one energy.  g1 and g2 come from drift_g1 and diffusion_g2 (wall.hpp) with the
/// fields above; their errors include the relative error of Σ.
struct PotentialCoefficients {
  double energy = 0;
  Quadrature Sigma, g1, g2;
};
PotentialCoefficients potential_coefficients(const geometry::Region2& region, const Potential& U,
                                             const ForceField& F, double E, double omega, double mass,
                                             double tolerance = 1e-10);

/// The fluctuation–dissipation prediction of g1 (eq. fd): (1/2Σ) ∂E(g2 Σ), the derivative by a
/// five-point central difference with step E/100 (truncation ~1e-8 relative for smooth g2Σ);
/// the error is the propagated quadrature error.  Compare with potential_coefficients().g1.
Quadrature fluctuation_dissipation_g1(const geometry::Region2& region, const Potential& U, const ForceField& F,
                                      double E, double omega, double mass, double tolerance = 1e-12);

/// g1(E), g2(E) as a function of the energy, for the Fokker–Planck solvers (fokker_planck.hpp):
/// each call is one potential_coefficients evaluation (a quadrature over {U < E}, ~ms), so
/// tabulate it.  The region must outlive the result.
EnergyCoefficients energy_coefficients(const geometry::Region2& region, const Potential& U, const ForceField& F,
                                       double omega, double mass, double tolerance = 1e-12);

/// Everything `billiard coeffs` reports, with a potential: Σ, g1, g2 (with their errors) from
/// potential_coefficients; the collision rate ∮ γ_E dS; γ_E its mean over the wall; V, S and λ
/// those of the table (geometry only); ∮ (F·n)² dS over the whole wall.  v_E, used by the
/// validity ratios, is the mean speed of the particles that hit the wall, ∮ γ_E v_E dS / ∮ γ_E dS
/// (v_E → 0 at turning points on the wall, where condition 1 fails locally whatever ω).
/// `closed_form` is false and C is 0.
Coefficients coefficients(const geometry::Region2& region, const Potential& U, const ForceField& F, double omega,
                          double mass, double E);

}  // namespace billiards::analysis
