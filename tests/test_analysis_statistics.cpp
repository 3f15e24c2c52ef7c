// Ensemble statistics against values by hand and against known distributions sampled with a
// fixed seed: each standard error and each noise level must match the spread it predicts.
#include "billiards/analysis/statistics.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

using namespace billiards;

namespace {

/// Mean and standard deviation of a list of replicate results.
std::pair<double, double> spread(const std::vector<double>& v) {
  const auto m = analysis::sample_moments(v);
  return {m.mean, std::sqrt(m.variance)};
}

std::vector<double> exponential_sample(std::mt19937_64& rng, std::size_t n, double rate = 1) {
  std::exponential_distribution<double> dist(rate);
  std::vector<double> x(n);
  for (double& v : x) v = dist(rng);
  return x;
}

/// The Kolmogorov–Smirnov distance by its definition: a sweep over the sorted sample with F at
/// every value (what ks_distance computes without most of those evaluations).
double ks_by_sweep(std::vector<double> x, const std::function<double(double)>& cdf) {
  std::sort(x.begin(), x.end());
  const double n = double(x.size());
  double d = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double F = cdf(x[i]);
    d = std::max({d, F - double(i) / n, double(i + 1) / n - F});
  }
  return d;
}

}  // namespace

TEST_CASE("sample moments by hand, and unaffected by a large offset") {
  // x = 1, 2, 3, 4, 10: mean 4, deviations −3 −2 −1 0 6, Σd² = 50, Σd⁴ = 1394.
  std::vector<double> x{1, 2, 3, 4, 10};
  auto m = analysis::sample_moments(x);
  CHECK(m.count == 5);
  CHECK(m.mean == Approx(4).epsilon(1e-15));
  CHECK(m.variance == Approx(12.5).epsilon(1e-15));
  CHECK(m.se_mean == Approx(std::sqrt(2.5)).epsilon(1e-15));
  // (m4 − (n−3)/(n−1) s⁴)/n = (278.8 − 78.125)/5
  CHECK(m.se_variance == Approx(std::sqrt(40.135)).epsilon(1e-14));
  for (double& v : x) v += 1e9;
  m = analysis::sample_moments(x);
  CHECK(m.variance == Approx(12.5).epsilon(1e-9));
}

TEST_CASE("moments of differences: those of the differences stored, to the bit; unequal sizes refused") {
  // x − y = 1, 2, 3, 4, 10 (the case above) with y far from zero and not a multiple of it.
  const std::vector<double> y{1e6 + 0.1, -3.3, 7.7e3, 0.25, -1e5 - 0.7};
  std::vector<double> x(y.size()), d(y.size());
  const double by_hand[] = {1, 2, 3, 4, 10};
  for (std::size_t i = 0; i < y.size(); ++i) x[i] = y[i] + by_hand[i], d[i] = x[i] - y[i];
  const auto m = analysis::sample_moments_of_differences(x, y), stored = analysis::sample_moments(d);
  CHECK(m.count == 5);
  CHECK(m.mean == stored.mean);
  CHECK(m.variance == stored.variance);
  CHECK(m.se_mean == stored.se_mean);
  CHECK(m.se_variance == stored.se_variance);
  CHECK(m.variance == Approx(12.5).epsilon(1e-9));
  CHECK_THROWS_AS(analysis::sample_moments_of_differences(x, std::vector<double>(4)), std::invalid_argument);
}

TEST_CASE("standard errors equal the spread of replicate means and variances (exponential, n = 100)") {
  // For Exp(1), μ4 = 9σ⁴: the variance's standard error is twice the Gaussian √(2/(n−1)) σ²,
  // so a Gaussian-only formula would fail here.
  std::mt19937_64 rng(12345);
  const int replicates = 4000;
  std::vector<double> means, variances;
  double se_mean2 = 0, se_var2 = 0;
  for (int r = 0; r < replicates; ++r) {
    const auto m = analysis::sample_moments(exponential_sample(rng, 100));
    means.push_back(m.mean);
    variances.push_back(m.variance);
    se_mean2 += m.se_mean * m.se_mean / replicates;
    se_var2 += m.se_variance * m.se_variance / replicates;
  }
  const auto [mean_of_means, sd_of_means] = spread(means);
  const auto [mean_of_variances, sd_of_variances] = spread(variances);
  CHECK(mean_of_means == Approx(1).epsilon(0.01));
  CHECK(mean_of_variances == Approx(1).epsilon(0.02));  // unbiased
  CHECK(std::sqrt(se_mean2) == Approx(sd_of_means).epsilon(0.05));
  CHECK(std::sqrt(se_var2) == Approx(sd_of_variances).epsilon(0.10));
  CHECK(sd_of_variances == Approx(std::sqrt((9 - 97.0 / 99) / 100)).epsilon(0.10));  // the exact value, 0.283
}

TEST_CASE("histogram: bins by hand, half-open range, out-of-range samples still normalize") {
  const std::vector<double> x{0.0, 0.1, 0.49, 0.5, 0.99, 1.0, -0.2, 7};
  const auto h = analysis::histogram(x, 0, 1, 2);
  CHECK(h.counts == std::vector<std::size_t>{3, 2});
  CHECK(h.total == 8);
  CHECK(h.width() == 0.5);
  CHECK(h.center(1) == 0.75);
  CHECK(h.density(0) == Approx(3 / (8 * 0.5)));
  CHECK_THROWS(analysis::histogram(x, 1, 1, 2));
}

TEST_CASE("Kolmogorov-Smirnov distance by hand and its p-value against Kolmogorov's table") {
  // {0.1, 0.5, 0.9} against U(0, 1): the largest gap is 1/3 − 0.1 = 0.9 − 2/3 = 7/30.
  const std::vector<double> x{0.9, 0.1, 0.5};
  CHECK(analysis::ks_distance(x, [](double u) { return u; }) == Approx(7.0 / 30).epsilon(1e-14));
  // Kolmogorov's distribution: P(√n D > t) = 0.5, 0.1, 0.05, 0.01 at t = 0.8276, 1.2238, 1.3581,
  // 1.6276 (n → ∞; D chosen so that the small-n correction gives exactly t).
  const std::size_t n = 100000000;
  auto p_at = [&](double t) { return analysis::ks_p_value(t / (1e4 + 0.12 + 0.11 / 1e4), n); };
  CHECK(p_at(0.8276) == Approx(0.5).epsilon(2e-4));
  CHECK(p_at(1.2238) == Approx(0.1).epsilon(2e-3));
  CHECK(p_at(1.3581) == Approx(0.05).epsilon(2e-3));
  CHECK(p_at(1.6276) == Approx(0.01).epsilon(2e-3));
  CHECK(p_at(1.18 - 1e-12) == Approx(p_at(1.18 + 1e-12)).epsilon(1e-10));  // the two series meet
}

TEST_CASE("Kolmogorov-Smirnov under the null: p-values uniform; a 5% wrong rate is rejected") {
  std::mt19937_64 rng(2024);
  auto cdf = [](double E) { return E > 0 ? -std::expm1(-E) : 0.0; };
  const int samples = 1000;
  int below_10 = 0, below_50 = 0;
  for (int r = 0; r < samples; ++r) {
    const double p = analysis::ks_p_value(analysis::ks_distance(exponential_sample(rng, 50), cdf), 50);
    below_10 += p < 0.1;
    below_50 += p < 0.5;
  }
  CHECK(std::abs(below_10 / double(samples) - 0.1) < 0.03);  // binomial sd 0.0095
  CHECK(std::abs(below_50 / double(samples) - 0.5) < 0.05);  // binomial sd 0.016
  const auto big = exponential_sample(rng, 100000, 1.05);
  CHECK(analysis::ks_p_value(analysis::ks_distance(big, cdf), big.size()) < 1e-10);
}

TEST_CASE("Kolmogorov-Smirnov distance: the sweep over every sorted value to the bit, with ~1% of its CDF calls") {
  std::mt19937_64 rng(7);
  std::size_t calls = 0;
  const std::function<double(double)> exponential = [&calls](double E) {
    ++calls;
    return E > 0 ? -std::expm1(-E) : 0.0;
  };
  const std::function<double(double)> normal = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
  auto check = [&](const std::vector<double>& x, const std::function<double(double)>& cdf) {
    INFO("n = " << x.size());
    CHECK(analysis::ks_distance(x, cdf) == ks_by_sweep(x, cdf));
  };
  // The null, a wrong rate, a spike of equal values (particles that met no wall keep E0),
  // values of both signs, and samples too small to bucket.
  for (std::size_t n : {1, 2, 3, 17, 1000, 100000}) check(exponential_sample(rng, n), exponential);
  check(exponential_sample(rng, 50000, 1.02), exponential);
  auto spiked = exponential_sample(rng, 40000);
  for (std::size_t i = 0; i < spiked.size(); i += 3) spiked[i] = 0.5;
  check(spiked, exponential);
  std::normal_distribution<double> gauss;
  std::vector<double> mixed(30000);
  for (double& v : mixed) v = gauss(rng);
  check(mixed, normal);
  std::vector<double> repeated(5000);
  for (std::size_t i = 0; i < repeated.size(); ++i) repeated[i] = double(i % 7);  // seven values, ties only
  check(repeated, exponential);
  // The bounds spare almost every evaluation (the sweep makes one per value).
  const auto big = exponential_sample(rng, 200000);
  calls = 0;
  analysis::ks_distance(big, exponential);
  CHECK(calls < big.size() / 20);
  CHECK_THROWS(analysis::ks_distance(std::vector<double>{1, NAN, 2}, exponential));
}

TEST_CASE("histogram: each value in the bin of the quotient (v - lo)/width, also next to every edge") {
  // Widths that 1/width does not represent exactly, values drawn at random and the doubles on
  // either side of each bin's edge, against the bin counted by the quotient itself.
  std::mt19937_64 rng(5);
  for (auto [lo, hi, bins] : {std::tuple{0.0, 1.0, 3}, {-7.3, 11.9, 97}, {1e6 + 0.1, 1e6 + 0.7, 41}, {0.5, 4.5, 1000}}) {
    std::uniform_real_distribution<double> uniform(lo, hi);
    std::vector<double> x(20000);
    for (double& v : x) v = uniform(rng);
    const double width = (hi - lo) / bins;
    for (int b = 0; b <= bins; ++b) {
      const double edge = lo + b * width;
      for (double v : {std::nextafter(edge, -INFINITY), edge, std::nextafter(edge, INFINITY)}) x.push_back(v);
    }
    std::vector<std::size_t> expected(std::size_t(bins), 0);
    for (double v : x)
      if (v >= lo && v < hi) ++expected[std::min(std::size_t(bins) - 1, std::size_t((v - lo) / width))];
    INFO("[" << lo << ", " << hi << ") in " << bins);
    CHECK(analysis::histogram(x, lo, hi, std::size_t(bins)).counts == expected);
  }
}

TEST_CASE("sample range: std::minmax_element's extremes at every length and position; NaN refused") {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> gauss;
  for (std::size_t n : {1, 2, 3, 4, 5, 7, 8, 9, 1001}) {
    std::vector<double> x(n);
    for (double& v : x) v = gauss(rng);
    // The extremes placed at each residue mod 4 in turn (each running extreme and the tail).
    for (std::size_t at = 0; at < std::min<std::size_t>(n, 6); ++at) {
      std::swap(x[at], *std::min_element(x.begin(), x.end()));
      std::swap(x[n - 1 - at], *std::max_element(x.begin(), x.end()));
      const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
      INFO("n = " << n << ", at = " << at);
      CHECK(analysis::sample_range(x) == std::pair{*lo, *hi});
    }
    x[n / 2] = NAN;
    CHECK_THROWS(analysis::sample_range(x));
  }
  const auto [lo, hi] = analysis::sample_range({});
  CHECK((lo == INFINITY && hi == -INFINITY));
}

TEST_CASE("binomial mean absolute deviation: De Moivre's closed form against the direct sum") {
  for (auto [n, p] : {std::pair{4, 0.5}, {10, 0.3}, {50, 0.02}, {100, 0.999}, {7, 1.0 / 7}, {1, 0.5}}) {
    double direct = 0;
    for (int k = 0; k <= n; ++k) {
      const double pmf_log = std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) + k * std::log(p) +
                             (n - k) * std::log1p(-p);
      direct += std::exp(pmf_log) * std::abs(k - n * p);
    }
    INFO("n = " << n << ", p = " << p);
    CHECK(analysis::binomial_mean_absolute_deviation(n, p) == Approx(direct).epsilon(1e-12));
  }
  CHECK(analysis::binomial_mean_absolute_deviation(4, 0.5) == Approx(0.75).epsilon(1e-14));
  CHECK(analysis::binomial_mean_absolute_deviation(10, 0.0) == 0);
  CHECK(analysis::binomial_mean_absolute_deviation(10, 1.0) == 0);
  // Large n p: the normal limit √(2 n p (1 − p)/π).
  CHECK(analysis::binomial_mean_absolute_deviation(1000000, 0.3) ==
        Approx(std::sqrt(2 * 1e6 * 0.3 * 0.7 / M_PI)).epsilon(1e-5));
}

TEST_CASE("histogram L1 by hand, and its noise level equals the mean L1 of samples from the density") {
  {
    // counts 3, 1 on two halves of [0, 1) against the uniform density: |3/4 − 1/2| + |1/4 − 1/2|;
    // noise: 2 · E|Bin(4, 1/2) − 2|/4 = 2 · 0.75/4.
    const auto l1 = analysis::histogram_l1(analysis::histogram(std::vector<double>{0.1, 0.2, 0.3, 0.7}, 0, 1, 2),
                                           [](double) { return 1.0; });
    CHECK(l1.distance == Approx(0.5).epsilon(1e-12));
    CHECK(l1.expected_from_noise == Approx(0.375).epsilon(1e-12));
  }
  std::mt19937_64 rng(7);
  auto density = [](double E) { return std::exp(-E); };
  std::vector<double> distances;
  double expected = 0;
  for (int r = 0; r < 400; ++r) {
    const auto l1 = analysis::histogram_l1(analysis::histogram(exponential_sample(rng, 2000), 0, 5, 25), density);
    distances.push_back(l1.distance);
    expected = l1.expected_from_noise;  // the same for every replicate
  }
  const auto [mean_l1, sd_l1] = spread(distances);
  // sd_l1/√400 ≈ 0.6% of the mean; a normal-limit formula without √(2/π) would be 25% off.
  CHECK(mean_l1 == Approx(expected).epsilon(0.03));
  // A 20% wrong rate stands far above the noise of 20000 samples.
  const auto wrong = analysis::histogram_l1(analysis::histogram(exponential_sample(rng, 20000), 0, 5, 25),
                                            [](double E) { return 1.2 * std::exp(-1.2 * E); });
  CHECK(wrong.distance > 4 * wrong.expected_from_noise);
}
