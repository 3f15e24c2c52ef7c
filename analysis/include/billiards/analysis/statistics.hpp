// Statistics of an ensemble of energies, for comparing simulation with the theory: moments with
// their standard errors, histograms, and two distances to a predicted distribution together
// with the size each would have from sampling noise alone.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <utility>
#include <vector>

namespace billiards::analysis {

struct SampleMoments {
  std::size_t count = 0;
  double mean = 0;
  double variance = 0;     // unbiased, Σ(x − x̄)²/(n − 1)
  double se_mean = 0;      // √(variance/n)
  double se_variance = 0;  // √((m4 − (n−3)/(n−1) s⁴)/n), m4 the fourth central moment
};

/// Two passes (mean, then central sums), so large offsets cost no precision.  Needs n ≥ 2.
SampleMoments sample_moments(std::span<const double> x);
/// The same of x − y, element by element, without storing the differences (ΔE = E(t) − E(0)).
SampleMoments sample_moments_of_differences(std::span<const double> x, std::span<const double> y);

/// The smallest and the largest value of a sample (±∞ for an empty one); throws if a value is
/// NaN.
std::pair<double, double> sample_range(std::span<const double> x);

/// Counts in `bins` equal bins on [lo, hi); samples outside are counted only in `total`, so
/// densities stay normalized against the whole sample.
struct Histogram {
  double lo = 0, hi = 1;
  std::vector<std::size_t> counts;
  std::size_t total = 0;

  double width() const { return (hi - lo) / double(counts.size()); }
  double edge(std::size_t i) const { return lo + double(i) * width(); }
  double center(std::size_t i) const { return lo + (double(i) + 0.5) * width(); }
  /// counts[i] / (total · width): an estimate of the probability density.
  double density(std::size_t i) const { return double(counts[i]) / (double(total) * width()); }
};

Histogram histogram(std::span<const double> x, double lo, double hi, std::size_t bins);

/// Kolmogorov–Smirnov distance sup_x |F̂(x) − F(x)| between the sample's empirical CDF and `cdf`.
double ks_distance(std::span<const double> x, const std::function<double(double)>& cdf);
/// Asymptotic probability that a sample of size n drawn from `cdf` itself lies at least
/// `distance` away: Kolmogorov's Q(√n D) with Stephens' small-n correction √n + 0.12 + 0.11/√n.
double ks_p_value(double distance, std::size_t n);

/// Σ_i |p̂_i − p_i| over the histogram's bins: p̂_i = counts[i]/total, p_i = ∫ density over bin i
/// (Gauss–Kronrod).  Equals ∫|ĥ − η| dE when η is constant within each bin.
struct HistogramL1 {
  double distance = 0;
  /// E[Σ|p̂_i − p_i|] if the sample were drawn from the density itself: counts[i] is then
  /// Binomial(total, p_i), whose mean absolute deviation is De Moivre's closed form (see
  /// binomial_mean_absolute_deviation).  A distance well above this is a real discrepancy.
  double expected_from_noise = 0;
};

HistogramL1 histogram_l1(const Histogram& h, const std::function<double(double)>& density);
/// The same with p_i = cdf(b_i) − cdf(a_i): for a CDF known exactly, or a numerical η's
/// piecewise-linear one (fokker_planck.hpp's cdf_of), whose density jumps at every cell edge.
HistogramL1 histogram_l1_cdf(const Histogram& h, const std::function<double(double)>& cdf);

/// E|X − n p| for X ~ Binomial(n, p): 2 k C(n, k) pᵏ (1 − p)^{n−k+1} with k = ⌊n p⌋ + 1
/// (De Moivre; Diaconis & Zabell 1991), evaluated in logarithms.  ≈ √(2 n p (1 − p)/π) for large n p.
double binomial_mean_absolute_deviation(std::size_t n, double p);

}  // namespace billiards::analysis
