#include "billiards/analysis/fokker_planck.hpp"

#include <boost/math/distributions/non_central_chi_squared.hpp>
#include <boost/math/special_functions/bessel.hpp>

#include <Eigen/SparseLU>
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace billiards::analysis {

namespace {
/// Boost.Math in double throughout: its default policy carries a double through long double
/// for a last bit, at several times the cost of the noncentral chi-squared CDF that the
/// Kolmogorov–Smirnov distance calls (the tests bound the difference by 1e-14).
using in_double = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
}  // namespace

double scaled_bessel_i(double nu, double x) {
  if (x < 500) return boost::math::cyl_bessel_i(nu, x, in_double()) * std::exp(-x);
  // Hankel's asymptotic series e⁻ˣ I_ν(x) ~ (2πx)^{−1/2} Σ (−1)^k a_k(ν)/x^k,
  // a_k = Π_{j=1..k} (4ν² − (2j−1)²)/(8 j); at x ≥ 500 twelve terms reach rounding.
  const double mu = 4 * nu * nu;
  double term = 1, sum = 1;
  for (int k = 1; k <= 12; ++k) {
    term *= -(mu - (2 * k - 1) * (2 * k - 1)) / (8.0 * k * x);
    sum += term;
  }
  return sum / std::sqrt(2 * M_PI * x);
}

double fokker_planck_eta(double E, double s, double E0, int d) {
  if (E <= 0) return 0;
  const double k = 2.0 * (d + 1) / s;
  // (Fourth roots as square roots of square roots: two instructions instead of a pow, within an ulp.)
  const double e = std::sqrt(std::sqrt(E)), e0 = std::sqrt(std::sqrt(E0));
  const double x = 2 * k * e * e0;
  const double gap = e0 - e;
  // I_{d−1}(x) e^{−k(√E0 + √E)} = [e⁻ˣ I_{d−1}(x)] e^{−k (E0^{1/4} − E^{1/4})²}
  const double power = d == 3 ? 1 : d == 2 ? e0 / e : std::pow(e / e0, d - 3);  // (E/E0)^{(d−3)/4}
  return (d + 1) / (s * std::sqrt(E0)) * power * scaled_bessel_i(d - 1, x) * std::exp(-k * gap * gap);
}

Moments fokker_planck_moments(double s, double E0, int d, int points) {
  const double hi = std::pow(40 * E0 + 50 * s * s, 0.25), h = hi / points;
  double m0 = 0, m1 = 0, m2 = 0;
  for (int i = 1; i < points; ++i) {
    const double u = i * h, E = u * u * u * u, w = fokker_planck_eta(E, s, E0, d) * 4 * u * u * u * h;
    m0 += w;
    m1 += w * E;
    m2 += w * E * E;
  }
  const double mean = m1 / m0;
  return {m0, mean, m2 / m0 - mean * mean};
}

namespace {

/// The parameters of X = 2c√E ~ χ'²(k, λ) (see the header).
struct ChiSquared {
  double c, k, lambda;
};
ChiSquared chi_squared_of(double s, double E0, int d) {
  const double c = 2.0 * (d + 1) / s;
  return {c, 2.0 * d, 2 * c * std::sqrt(E0)};
}

}  // namespace

EnergyMoments fokker_planck_exact_moments(double s, double E0, int d) {
  const auto [c, k, lambda] = chi_squared_of(s, E0, d);
  const double k1 = k + lambda, k2 = 2 * (k + 2 * lambda), k3 = 8 * (k + 3 * lambda), k4 = 48 * (k + 4 * lambda);
  // E = X²/(4c²): ⟨X²⟩ = κ2 + κ1², Var(X²) = κ4 + 4κ3κ1 + 2κ2² + 4κ2κ1².
  const double c2 = c * c;
  return {(k2 + k1 * k1) / (4 * c2), (k4 + 4 * k3 * k1 + 2 * k2 * k2 + 4 * k2 * k1 * k1) / (16 * c2 * c2),
          k1 / (2 * c)};
}

double fokker_planck_cdf(double E, double s, double E0, int d) {
  if (E <= 0) return 0;
  const auto [c, k, lambda] = chi_squared_of(s, E0, d);
  return boost::math::cdf(boost::math::non_central_chi_squared_distribution<double, in_double>(k, lambda),
                          2 * c * std::sqrt(E));
}

EnergyGrid quartic_root_grid(double floor, double lo, double hi, int cells) {
  EnergyGrid g;
  const double bottom = std::pow(lo - floor, 0.25), top = std::pow(hi - floor, 0.25);
  for (int i = 0; i <= cells; ++i) {
    const double u = bottom + (top - bottom) * i / cells;
    g.edges.push_back(floor + u * u * u * u);
  }
  g.edges.front() = lo;  // exactly, whatever the rounding of the fourth powers
  g.edges.back() = hi;
  return g;
}

EnergyGrid quartic_root_grid(double e_max, int cells) { return quartic_root_grid(0, 0, e_max, cells); }

TabulatedCoefficients tabulate(const EnergyGrid& grid, const EnergyCoefficients& g) {
  TabulatedCoefficients t;
  for (double e : grid.edges) {
    const DriftDiffusion c = g(e);
    if (!std::isfinite(c.g1) || !std::isfinite(c.g2) || c.g2 < 0)
      throw std::invalid_argument(fmt::format("Fokker-Planck coefficients at E = {}: g1 = {}, g2 = {}", e, c.g1, c.g2));
    t.g1.push_back(c.g1);
    t.g2.push_back(c.g2);
  }
  return t;
}

namespace {

/// Bernoulli function w/(eʷ − 1), with its limit 1 at w = 0.
double bernoulli(double w) { return std::abs(w) < 1e-10 ? 1 - w / 2 : w / std::expm1(w); }

/// f'(x_i) from f at x_{i−1}, x_i, x_{i+1} (unequal spacings; exact for quadratics).
double three_point_derivative(const std::vector<double>& x, const std::vector<double>& f, std::size_t i) {
  const double hl = x[i] - x[i - 1], hr = x[i + 1] - x[i];
  return (hl * hl * (f[i + 1] - f[i]) + hr * hr * (f[i] - f[i - 1])) / (hl * hr * (hl + hr));
}

}  // namespace

std::vector<double> evolve_fokker_planck(const EnergyGrid& grid, std::vector<double> eta,
                                         const TabulatedCoefficients& g, double duration, int steps) {
  // Flux J = A η − D ∂η/∂E with A = g1 − ½ g2', D = ½ g2; across the face between cells i and
  // i+1: J = (D/h)[B(−w) η_i − B(w) η_{i+1}], w = A h/D, which is exact for zero-flux states.
  const std::size_t n = grid.cells();
  std::vector<Eigen::Triplet<double>> entries;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const std::size_t face = i + 1;  // the edge between cells i and i+1
    const double h = grid.center(i + 1) - grid.center(i);
    const double A = g.g1[face] - 0.5 * three_point_derivative(grid.edges, g.g2, face), D = 0.5 * g.g2[face];
    // J = left η_i − right η_{i+1}.  Where g2 = 0 (an energy at which no particle reaches the
    // wall, under a potential) the flux is pure upwind advection, the limit D → 0.
    double left = std::max(A, 0.0), right = std::max(-A, 0.0);
    if (D > 0) {
      const double w = A * h / D;
      left = D / h * bernoulli(-w);
      right = D / h * bernoulli(w);
    }
    // Δ_i dη_i/dt = J_{i−1/2} − J_{i+1/2}
    entries.emplace_back(i, i, -left / grid.width(i));
    entries.emplace_back(i, i + 1, right / grid.width(i));
    entries.emplace_back(i + 1, i, left / grid.width(i + 1));
    entries.emplace_back(i + 1, i + 1, -right / grid.width(i + 1));
  }
  Eigen::SparseMatrix<double> L(n, n), I(n, n);
  L.setFromTriplets(entries.begin(), entries.end());
  I.setIdentity();
  const double dt = duration / steps;
  Eigen::SparseMatrix<double> M = I - dt * L;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  lu.compute(M);
  Eigen::VectorXd x = Eigen::Map<Eigen::VectorXd>(eta.data(), Eigen::Index(n));
  for (int k = 0; k < steps; ++k) x = lu.solve(x);
  return {x.data(), x.data() + n};
}

std::vector<double> evolve_fokker_planck(const EnergyGrid& grid, std::vector<double> eta,
                                         const std::function<double(double)>& g1,
                                         const std::function<double(double)>& g2, double duration, int steps) {
  const auto table = tabulate(grid, [&](double E) { return DriftDiffusion{g1(E), g2(E)}; });
  return evolve_fokker_planck(grid, std::move(eta), table, duration, steps);
}

namespace {

/// The energy at which y = ∫ dE/√g2 lies `distance` from E0 (upwards for direction +1,
/// downwards for −1, never below `floor`): steps of at most 25% of E − floor (20% downwards),
/// each counted at the larger g2 of its ends, so that y is underestimated and the edge errs
/// outwards.  Downwards, within 1e-3 (E0 − floor) of the floor, the floor itself.
double spread_edge(const EnergyCoefficients& g, double E0, double g2_E0, double floor, double distance,
                   int direction) {
  double E = E0, g2 = g2_E0, left = distance;
  for (int k = 0; left > 0; ++k) {
    if (k == 400) throw std::invalid_argument("Fokker-Planck range: the walk in energy did not end (g2 vanishes?)");
    if (direction < 0 && E - floor <= 1e-3 * (E0 - floor)) return floor;
    const double step = std::min(left * std::sqrt(g2), (direction > 0 ? 0.25 : 0.2) * (E - floor));
    const double next = E + direction * step, g2_next = g(next).g2;
    left -= step / std::sqrt(std::max(g2, g2_next));
    E = next;
    g2 = g2_next;
  }
  return E;
}

/// Cell averages of the short-time law of E at time t from E0: the Milstein expansion
/// E = E0 + g1 t + √(g2 t) Z + ¼ g2' t (Z² − 1), Z ~ N(0, 1), whose mean and variance are g1 t
/// and g2 t and whose third cumulant (3/2) g2 g2' t² is the FP solution's to leading order
/// (dκ3/dt = 3 g2' κ2).  Cell masses are Φ(Z(b)) − Φ(Z(a)) on the branch where E increases with
/// Z (the other branch lies beyond −√(g2 t)/(½ g2' t) standard deviations); renormalized.
std::vector<double> short_time_cells(const EnergyGrid& grid, double E0, const DriftDiffusion& g, double dg2, double t) {
  const double b = std::sqrt(g.g2 * t), c = 0.25 * dg2 * t, a = E0 + g.g1 * t - c;  // E = a + b Z + c Z²
  // Z(E) on the increasing branch, written so that c → 0 loses no precision.
  auto Z = [&](double E) {
    const double disc = b * b + 4 * c * (E - a);
    if (disc <= 0) return -b / (2 * c);  // beyond the fold: Φ stays at its value there
    return 2 * (E - a) / (b + std::sqrt(disc));
  };
  auto Phi = [&](double E) { return 0.5 * std::erfc(-Z(E) / std::sqrt(2.0)); };
  std::vector<double> eta(grid.cells());
  double total = 0;
  for (std::size_t i = 0; i < eta.size(); ++i) {
    const double p = Phi(grid.edges[i + 1]) - Phi(grid.edges[i]);
    total += p;
    eta[i] = p / grid.width(i);
  }
  for (double& e : eta) e /= total;
  return eta;
}

/// The mass in the outer 1% of the cells at the top, and at the bottom unless it is the floor.
double tail_mass(const EnergyGrid& grid, const std::vector<double>& eta, double floor) {
  const std::size_t n = grid.cells(), outer = std::max<std::size_t>(1, n / 100);
  double m = 0;
  for (std::size_t i = 0; i < outer; ++i) {
    m += eta[n - 1 - i] * grid.width(n - 1 - i);
    if (grid.edges.front() > floor) m += eta[i] * grid.width(i);
  }
  return m;
}

}  // namespace

FokkerPlanckSolution solve_fokker_planck(const std::vector<double>& times, double E0, double floor,
                                         const EnergyCoefficients& g_in, int cells, int steps) {
  if (times.empty() || !(times.front() > 0)) throw std::invalid_argument("Fokker-Planck times must be positive");
  for (std::size_t k = 1; k < times.size(); ++k)
    if (!(times[k] > times[k - 1])) throw std::invalid_argument("Fokker-Planck times must be increasing");
  if (!(E0 > floor)) throw std::invalid_argument("Fokker-Planck: E0 must lie above the floor energy");
  std::size_t evaluations = 0;
  const EnergyCoefficients g = [&](double E) {
    ++evaluations;
    return g_in(E);
  };
  const DriftDiffusion at_E0 = g(E0);
  if (!(at_E0.g2 > 0)) throw std::invalid_argument("Fokker-Planck: g2(E0) = 0, the energy does not diffuse from E0");
  const double t1 = times.front(), spread = std::sqrt(times.back());
  double reach = 7;
  for (int attempt = 0;; ++attempt, reach *= 1.5) {
    const double lo = spread_edge(g, E0, at_E0.g2, floor, reach * spread, -1);
    const double hi = spread_edge(g, E0, at_E0.g2, floor, reach * spread, +1);
    FokkerPlanckSolution out{quartic_root_grid(floor, lo, hi, cells), times, {}, t1 / 100, 0, 0};
    const auto& grid = out.grid;
    const auto cell = std::upper_bound(grid.edges.begin(), grid.edges.end(), E0) - grid.edges.begin() - 1;
    const double h = grid.width(std::size_t(cell));
    out.start = std::min(t1 / 4, std::max(out.start, 16 * h * h / at_E0.g2));  // σ0 ≥ 4 cells
    out.resolution = std::sqrt(at_E0.g2 * t1) / h;
    const auto table = tabulate(grid, g);
    const double dg2 = (table.g2[cell + 1] - table.g2[cell]) / h;
    auto eta = short_time_cells(grid, E0, at_E0, dg2, out.start);
    double now = out.start;
    for (double next : times) {
      eta = evolve_fokker_planck(grid, eta, table, next - now, steps);
      now = next;
      out.eta.push_back(eta);
    }
    out.evaluations = evaluations;
    if (attempt == 2 || tail_mass(grid, eta, floor) <= 1e-7) return out;
  }
}

FokkerPlanckSolution solve_fokker_planck(const std::vector<double>& s, double E0, int d, int cells, int steps) {
  const EnergyCoefficients g = [d](double E) {
    return DriftDiffusion{std::sqrt(E), 4 * std::pow(E, 1.5) / (d + 1)};
  };
  return solve_fokker_planck(s, E0, 0.0, g, cells, steps);
}

Moments moments_of(const EnergyGrid& grid, const std::vector<double>& eta) {
  // Two passes: a narrow η far from E = 0 would lose its variance in ⟨E²⟩ − ⟨E⟩².
  double m0 = 0, m1 = 0, m2 = 0;
  for (std::size_t i = 0; i < eta.size(); ++i) {
    m0 += eta[i] * grid.width(i);
    m1 += eta[i] * grid.width(i) * grid.center(i);
  }
  const double mean = m1 / m0;
  for (std::size_t i = 0; i < eta.size(); ++i) {
    const double w = grid.width(i), d = grid.center(i) - mean;
    m2 += eta[i] * w * (d * d + w * w / 12);
  }
  return {m0, mean, m2 / m0};
}

std::function<double(double)> cdf_of(const EnergyGrid& grid, const std::vector<double>& eta) {
  std::vector<double> below{0};  // ∫η up to each edge
  for (std::size_t i = 0; i < eta.size(); ++i) below.push_back(below.back() + eta[i] * grid.width(i));
  return [edges = grid.edges, below = std::move(below)](double E) {
    if (E <= edges.front()) return 0.0;
    if (E >= edges.back()) return below.back();
    const std::size_t i = std::size_t(std::upper_bound(edges.begin(), edges.end(), E) - edges.begin()) - 1;
    return below[i] + (below[i + 1] - below[i]) * (E - edges[i]) / (edges[i + 1] - edges[i]);
  };
}

}  // namespace billiards::analysis
