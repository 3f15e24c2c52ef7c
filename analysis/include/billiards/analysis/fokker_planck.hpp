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

/// `cells` cells on [lo, hi] (floor ≤ lo < hi), uniform in (E − floor)^{1/4}: dense near the
/// floor, the energy where g2 vanishes (0 for U = 0), like g2 itself (∝ (E − floor)^{3/2} there).
EnergyGrid quartic_root_grid(double floor, double lo, double hi, int cells);
/// `cells` cells on [0, e_max], uniform in E^{1/4}: dense at low energy, where early
/// distributions are narrow and where g2 vanishes.
EnergyGrid quartic_root_grid(double e_max, int cells);

/// The drift and diffusion coefficients at one energy.
struct DriftDiffusion {
  double g1 = 0, g2 = 0;
};
/// g1(E), g2(E) as one function of the energy: with a potential one call is a quadrature over the
/// table (potential.hpp's energy_coefficients), so both come from the same call.
using EnergyCoefficients = std::function<DriftDiffusion(double E)>;

/// g1, g2 at every edge of a grid: the solver's only calls of the coefficients (cells + 1).
struct TabulatedCoefficients {
  std::vector<double> g1, g2;
};
TabulatedCoefficients tabulate(const EnergyGrid& grid, const EnergyCoefficients& g);

/// Evolves cell averages η under ∂η/∂t = −∂E(g1 η) + ½ ∂E²(g2 η) for `duration`, in `steps`
/// implicit Euler steps.  Finite volumes with Chang–Cooper (Scharfetter–Gummel) fluxes and
/// zero flux at both ends: η stays positive and ∫η is conserved to rounding.  g2' at a face
/// is the three-point (second-order) difference of the tabulated g2 at the neighbouring edges.
/// The operator is factorized once (Eigen SparseLU) and reused for every step.
std::vector<double> evolve_fokker_planck(const EnergyGrid& grid, std::vector<double> eta,
                                         const TabulatedCoefficients& g, double duration, int steps);
/// The same with g1 and g2 given as functions (tabulated on the grid's edges first).
std::vector<double> evolve_fokker_planck(const EnergyGrid& grid, std::vector<double> eta,
                                         const std::function<double(double)>& g1,
                                         const std::function<double(double)>& g2, double duration, int steps);

/// η(·, t_k) at increasing times t_k on one grid.
struct FokkerPlanckSolution {
  EnergyGrid grid;
  std::vector<double> times;             // t_k (s_k for the standard billiard's solver)
  std::vector<std::vector<double>> eta;  // [k][cell]
  double start = 0;                      // the time of the Gaussian start (below)
  std::size_t evaluations = 0;           // calls of the coefficients
  double resolution = 0;                 // √(g2(E0) t_1) over the width of E0's cell
};

/// η(·, t_k) at increasing times t_1 < t_2 < ... for any g1(E), g2(E), starting from
/// δ(E − E0), by evolve_fokker_planck with `steps` steps between consecutive times.
///
/// - Start: the δ cannot be gridded; at a short time t0 the solution is close to the law of
///   the short-time (Milstein) expansion E0 + g1 t0 + √(g2 t0) Z + ¼ g2' t0 (Z² − 1), Z normal:
///   mean g1 t0 and variance g2 t0 as the FP solution's, and its third cumulant to leading
///   order; its cell averages (exact, by erfc) start the evolution.  t0 = t_1/100, enlarged
///   until the spread √(g2 t0) covers 4 cells (at most t_1/4): a start error whose first three
///   moments are right fades like (t0/t)², while the O(t0²) errors of the moments stay,
///   relatively O(t0/t_1).
/// - Range: in y = ∫ dE/√g2 the diffusion has unit rate, so η(t) spreads by ~√t in y.  The
///   grid spans 7 √t_last in y on either side of E0 (stopping at `floor`, the energy below
///   which g2 = 0 and no particle reaches the wall: 0 for U = 0; a 7σ tail holds ~1e-12, and a
///   Bessel-like drift in y, as for U = 0, adds ~2√t), found by walking out from E0
///   in steps of at most 25% of E − floor, counting each step at the larger g2 of its ends (an
///   underestimate of y, so the range errs wide).  If more than 1e-7 of the mass ends in the
///   outer 1% of the cells of an open end, the reach grows 1.5× and the solve is repeated (at
///   most twice).
/// - Coefficients: tabulated once on the grid's edges (cells + 1 calls, plus the walk's).
/// - One grid serves every time: `resolution` says how many cells the short-time spread at t_1
///   covers; below ~5 the first times are smeared by the cells (their variance grows by
///   width²/12) and more cells are needed.
/// Throws std::invalid_argument unless the times are positive and increasing, E0 > floor and
/// g2(E0) > 0.
FokkerPlanckSolution solve_fokker_planck(const std::vector<double>& times, double E0, double floor,
                                         const EnergyCoefficients& g, int cells, int steps = 2000);

/// The standard billiard in s = C t (g1 = √E, g2 = 4E^{3/2}/(d+1)): the general solver with
/// floor 0 and times s_k.
FokkerPlanckSolution solve_fokker_planck(const std::vector<double>& s, double E0, int d, int cells,
                                         int steps = 2000);

/// ∫η, mean and variance of cell averages, η uniform within each cell (so the variance includes
/// each cell's width²/12).
Moments moments_of(const EnergyGrid& grid, const std::vector<double>& eta);

/// ∫ η up to E of cell averages, η uniform within each cell: piecewise linear between the edges,
/// 0 below the grid and ∫η above it.  For Kolmogorov–Smirnov tests and histogram bins.
std::function<double(double)> cdf_of(const EnergyGrid& grid, const std::vector<double>& eta);

}  // namespace billiards::analysis
