// The Fokker–Planck equation in energy for a standard billiard, ∂η/∂t = −∂E(g1 η) + ½ ∂E²(g2 η)
// with g1 = C√E, g2 = 4C E^{3/2}/(d+1), and its exact solution for η(E, 0) = δ(E − E0) (the
// paper's eq. B4, from Demers & Jarzynski), written with s = C t.
#pragma once

#include <functional>
#include <vector>

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
/// is smooth at E = 0, over E ≤ 40 E0 + 50 s² (η spreads to E ~ s²).  A check of η; the exact
/// values are fokker_planck_exact_moments.
Moments fokker_planck_moments(double s, double E0, int d, int points = 200000);

// η(·, s) is a noncentral chi-squared law in disguise: with c = 2(d+1)/s, X = 2c√E has the
// density of χ'²(k = 2d, λ = 2c√E0) (substitute y = √E in eq. B4 and compare with the
// χ'² density ½ e^{−(x+λ)/2} (x/λ)^{k/4−1/2} I_{k/2−1}(√(λx))).  Its moments and CDF are
// therefore exact, in closed form.

struct EnergyMoments {
  double mean = 0;       // ⟨E⟩
  double variance = 0;   // Var(E)
  double mean_root = 0;  // ⟨√E⟩ = ⟨v_E⟩ √(m/2), which drives d⟨E⟩/ds = ⟨√E⟩
};
/// Exact moments of η(·, s) from the cumulants κ_n = 2^{n−1}(n−1)!(k + nλ) of X; Var(E) is
/// written as a sum of positive terms, so it stays accurate for s → 0.
EnergyMoments fokker_planck_exact_moments(double s, double E0, int d);
/// ∫_0^E η(E', s) dE', exact (Boost's noncentral chi-squared CDF), for Kolmogorov–Smirnov tests.
double fokker_planck_cdf(double E, double s, double E0, int d);

/// Cell-averaged η on a grid in energy: cell i spans [edges[i], edges[i+1]].
struct EnergyGrid {
  std::vector<double> edges;
  double center(std::size_t i) const { return 0.5 * (edges[i] + edges[i + 1]); }
  double width(std::size_t i) const { return edges[i + 1] - edges[i]; }
  std::size_t cells() const { return edges.size() - 1; }
};

/// `cells` cells on [0, e_max], uniform in E^{1/4}: dense at low energy, where early
/// distributions are narrow and where g2 vanishes.
EnergyGrid quartic_root_grid(double e_max, int cells);

/// Evolves cell averages η under ∂η/∂t = −∂E(g1 η) + ½ ∂E²(g2 η) for `duration`, in `steps`
/// implicit Euler steps.  Finite volumes with Chang–Cooper (Scharfetter–Gummel) fluxes and
/// zero flux at both ends: η stays positive and ∫η is conserved to rounding.  The operator is
/// factorized once (Eigen SparseLU) and reused for every step.
std::vector<double> evolve_fokker_planck(const EnergyGrid& grid, std::vector<double> eta,
                                         const std::function<double(double)>& g1,
                                         const std::function<double(double)>& g2, double duration, int steps);

/// η(·, s_k) at increasing s_1 < s_2 < ... (time measured in s = C t, so g1 = √E and
/// g2 = 4E^{3/2}/(d+1)), starting from δ(E − E0), by evolve_fokker_planck with `steps` steps
/// between consecutive s_k, on `cells` cells of quartic_root_grid(40 E0 + 50 s_last²) (η spreads
/// to E ~ s²).  The δ cannot be gridded: the solver starts from the exact η at s_1/10.
/// Throws std::invalid_argument unless the s_k are positive and increasing.
struct FokkerPlanckSolution {
  EnergyGrid grid;
  std::vector<std::vector<double>> eta;  // [k][cell]
};
FokkerPlanckSolution solve_fokker_planck(const std::vector<double>& s, double E0, int d, int cells,
                                         int steps = 2000);

}  // namespace billiards::analysis
