#include "billiards/analysis/statistics.hpp"

#include "billiards/analysis/quadrature.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace billiards::analysis {

SampleMoments sample_moments(std::span<const double> x) {
  if (x.size() < 2) throw std::invalid_argument("sample_moments needs at least two values");
  const double n = double(x.size());
  double sum = 0;
  for (double v : x) sum += v;
  const double mean = sum / n;
  double m2 = 0, m4 = 0;
  for (double v : x) {
    const double d2 = (v - mean) * (v - mean);
    m2 += d2;
    m4 += d2 * d2;
  }
  const double variance = m2 / (n - 1);
  m4 /= n;
  // Var(s²) = (μ4 − (n−3)/(n−1) σ⁴)/n for any distribution with a fourth moment; clamp the
  // estimate, which can dip below zero for tiny samples.
  const double var_of_var = (m4 - (n - 3) / (n - 1) * variance * variance) / n;
  return {x.size(), mean, variance, std::sqrt(variance / n), std::sqrt(std::max(0.0, var_of_var))};
}

Histogram histogram(std::span<const double> x, double lo, double hi, std::size_t bins) {
  if (!(hi > lo) || bins == 0) throw std::invalid_argument("histogram needs hi > lo and at least one bin");
  Histogram h{lo, hi, std::vector<std::size_t>(bins, 0), x.size()};
  for (double v : x) {
    if (!(v >= lo && v < hi)) continue;
    // (v − lo)/width can round up to `bins` for v just below hi.
    const auto i = std::min(bins - 1, std::size_t((v - lo) / h.width()));
    ++h.counts[i];
  }
  return h;
}

double ks_distance(std::span<const double> x, const std::function<double(double)>& cdf) {
  std::vector<double> sorted(x.begin(), x.end());
  std::sort(sorted.begin(), sorted.end());
  const double n = double(sorted.size());
  double d = 0;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    // The empirical CDF steps from i/n to (i+1)/n at the i-th smallest value.
    const double F = cdf(sorted[i]);
    d = std::max({d, F - double(i) / n, double(i + 1) / n - F});
  }
  return d;
}

double ks_p_value(double distance, std::size_t n) {
  const double root_n = std::sqrt(double(n));
  const double t = (root_n + 0.12 + 0.11 / root_n) * distance;
  if (t <= 0) return 1;
  constexpr double pi = std::numbers::pi;
  double sum = 0;
  if (t < 1.18) {
    // Jacobi's dual series converges fast for small t: 1 − √(2π)/t Σ exp(−(2k−1)²π²/(8t²)).
    for (int k = 1; k <= 6; ++k) sum += std::exp(-(2 * k - 1) * (2 * k - 1) * pi * pi / (8 * t * t));
    return std::clamp(1 - std::sqrt(2 * pi) / t * sum, 0.0, 1.0);
  }
  for (int k = 1; k <= 6; ++k) sum += (k % 2 ? 2 : -2) * std::exp(-2.0 * k * k * t * t);
  return std::clamp(sum, 0.0, 1.0);
}

double binomial_mean_absolute_deviation(std::size_t n, double p) {
  const double k = std::floor(double(n) * p) + 1;
  if (p <= 0 || k > double(n)) return 0;  // X is then constant (p = 0 or p = 1)
  const double N = double(n);
  const double log_mad = std::log(2 * k) + std::lgamma(N + 1) - std::lgamma(k + 1) - std::lgamma(N - k + 1) +
                         k * std::log(p) + (N - k + 1) * std::log1p(-p);
  return std::exp(log_mad);
}

namespace {

/// The L1 distance and its noise level, with p_i = probability(a_i, b_i) for bin i = [a_i, b_i).
HistogramL1 histogram_l1_of(const Histogram& h, const std::function<double(double, double)>& probability) {
  HistogramL1 out;
  const double total = double(h.total);
  for (std::size_t i = 0; i < h.counts.size(); ++i) {
    // Rounding (in a quadrature, or a difference of CDFs) must not push p outside [0, 1].
    const double p = std::clamp(probability(h.edge(i), h.edge(i + 1)), 0.0, 1.0);
    out.distance += std::abs(double(h.counts[i]) / total - p);
    out.expected_from_noise += binomial_mean_absolute_deviation(h.total, p) / total;
  }
  return out;
}

}  // namespace

HistogramL1 histogram_l1(const Histogram& h, const std::function<double(double)>& density) {
  return histogram_l1_of(h, [&](double a, double b) { return integrate_adaptive(density, a, b).value; });
}

HistogramL1 histogram_l1_cdf(const Histogram& h, const std::function<double(double)>& cdf) {
  return histogram_l1_of(h, [&](double a, double b) { return cdf(b) - cdf(a); });
}

}  // namespace billiards::analysis
