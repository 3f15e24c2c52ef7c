// The Fokker–Planck equation in energy for a standard billiard, ∂η/∂t = −∂E(g1 η) + ½ ∂E²(g2 η)
// with g1 = C√E, g2 = 4C E^{3/2}/(d+1), and its exact solution for η(E, 0) = δ(E − E0) (the
// paper's eq. B4, from Demers & Jarzynski), written with s = C t.
#pragma once

namespace billiards::analysis {

/// e⁻ˣ I_ν(x), finite for every x ≥ 0 (Boost.Math below x = 500, the asymptotic series above).
double scaled_bessel_i(double nu, double x);

/// η(E, s) in dimension d, starting from δ(E − E0).  Never overflows: the exponentials are
/// combined into exp(−2(d+1)/s · (E0^{1/4} − E^{1/4})²) before evaluation.
double fokker_planck_eta(double E, double s, double E0, int d);

struct Moments {
  double norm, mean, variance;  // ∫η, ⟨E⟩, Var(E)
};
/// Moments of η(·, s) by the trapezoidal rule in u = E^{1/4} (dE = 4u³du), where the integrand
/// is smooth at E = 0, over E ≤ 40 E0 + 50 s² (η spreads to E ~ s²).
Moments fokker_planck_moments(double s, double E0, int d, int points = 200000);

}  // namespace billiards::analysis
