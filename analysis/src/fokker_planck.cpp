#include "billiards/analysis/fokker_planck.hpp"

#include <boost/math/distributions/non_central_chi_squared.hpp>
#include <boost/math/special_functions/bessel.hpp>

#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace billiards::analysis {

double scaled_bessel_i(double nu, double x) {
  if (x < 500) return boost::math::cyl_bessel_i(nu, x) * std::exp(-x);
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
  const double x = 2 * k * std::pow(E0 * E, 0.25);
  const double gap = std::pow(E0, 0.25) - std::pow(E, 0.25);
  // I_{d−1}(x) e^{−k(√E0 + √E)} = [e⁻ˣ I_{d−1}(x)] e^{−k (E0^{1/4} − E^{1/4})²}
  return (d + 1) / (s * std::sqrt(E0)) * std::pow(E / E0, (d - 3) / 4.0) * scaled_bessel_i(d - 1, x) *
         std::exp(-k * gap * gap);
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
  return boost::math::cdf(boost::math::non_central_chi_squared(k, lambda), 2 * c * std::sqrt(E));
}

EnergyGrid quartic_root_grid(double e_max, int cells) {
  EnergyGrid g;
  const double top = std::pow(e_max, 0.25);
  for (int i = 0; i <= cells; ++i) {
    const double u = top * i / cells;
    g.edges.push_back(u * u * u * u);
  }
  return g;
}

namespace {

/// Bernoulli function w/(eʷ − 1), with its limit 1 at w = 0.
double bernoulli(double w) { return std::abs(w) < 1e-10 ? 1 - w / 2 : w / std::expm1(w); }

}  // namespace

std::vector<double> evolve_fokker_planck(const EnergyGrid& grid, std::vector<double> eta,
                                         const std::function<double(double)>& g1,
                                         const std::function<double(double)>& g2, double duration, int steps) {
  // Flux J = A η − D ∂η/∂E with A = g1 − ½ g2', D = ½ g2; across the face between cells i and
  // i+1: J = (D/h)[B(−w) η_i − B(w) η_{i+1}], w = A h/D, which is exact for zero-flux states.
  const std::size_t n = grid.cells();
  std::vector<Eigen::Triplet<double>> entries;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double e = grid.edges[i + 1], h = grid.center(i + 1) - grid.center(i);
    const double dg2 = (g2(e + 1e-6 * e) - g2(e - 1e-6 * e)) / (2e-6 * e);
    const double A = g1(e) - 0.5 * dg2, D = 0.5 * g2(e);
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

FokkerPlanckSolution solve_fokker_planck(const std::vector<double>& s, double E0, int d, int cells, int steps) {
  if (s.empty() || !(s.front() > 0)) throw std::invalid_argument("Fokker-Planck times must be positive");
  for (std::size_t k = 1; k < s.size(); ++k)
    if (!(s[k] > s[k - 1])) throw std::invalid_argument("Fokker-Planck times must be increasing");
  FokkerPlanckSolution out{quartic_root_grid(40 * E0 + 50 * s.back() * s.back(), cells), {}};
  auto g1 = [](double E) { return std::sqrt(E); };
  auto g2 = [d](double E) { return 4 * std::pow(E, 1.5) / (d + 1); };
  double now = s.front() / 10;
  std::vector<double> eta(out.grid.cells());
  for (std::size_t i = 0; i < eta.size(); ++i) eta[i] = fokker_planck_eta(out.grid.center(i), now, E0, d);
  for (double next : s) {
    eta = evolve_fokker_planck(out.grid, eta, g1, g2, next - now, steps);
    now = next;
    out.eta.push_back(eta);
  }
  return out;
}

}  // namespace billiards::analysis
