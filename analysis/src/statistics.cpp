#include "billiards/analysis/statistics.hpp"

#include "billiards/analysis/quadrature.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace billiards::analysis {

namespace {

/// The moments of the n values value(0), ..., value(n − 1).
template <class Value>
SampleMoments moments_of(std::size_t count, Value value) {
  if (count < 2) throw std::invalid_argument("sample_moments needs at least two values");
  const double n = double(count);
  double sum = 0;
  for (std::size_t i = 0; i < count; ++i) sum += value(i);
  const double mean = sum / n;
  double m2 = 0, m4 = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double v = value(i), d2 = (v - mean) * (v - mean);
    m2 += d2;
    m4 += d2 * d2;
  }
  const double variance = m2 / (n - 1);
  m4 /= n;
  // Var(s²) = (μ4 − (n−3)/(n−1) σ⁴)/n for any distribution with a fourth moment; clamp the
  // estimate, which can dip below zero for tiny samples.
  const double var_of_var = (m4 - (n - 3) / (n - 1) * variance * variance) / n;
  return {count, mean, variance, std::sqrt(variance / n), std::sqrt(std::max(0.0, var_of_var))};
}

}  // namespace

SampleMoments sample_moments(std::span<const double> x) {
  return moments_of(x.size(), [x](std::size_t i) { return x[i]; });
}

SampleMoments sample_moments_of_differences(std::span<const double> x, std::span<const double> y) {
  if (x.size() != y.size()) throw std::invalid_argument("sample_moments_of_differences: samples of unequal sizes");
  return moments_of(x.size(), [x, y](std::size_t i) { return x[i] - y[i]; });
}

std::pair<double, double> sample_range(std::span<const double> x) {
  // Four running extremes: one chain of dependent min and max per value would be
  // latency-bound.
  std::array<double, 4> lo, hi;
  lo.fill(INFINITY), hi.fill(-INFINITY);
  bool nan = false;
  const auto take = [&](std::size_t k, double v) {
    nan |= std::isnan(v);
    lo[k] = std::min(lo[k], v), hi[k] = std::max(hi[k], v);
  };
  std::size_t i = 0;
  for (; i + 4 <= x.size(); i += 4)
    for (std::size_t k = 0; k < 4; ++k) take(k, x[i + k]);
  for (; i < x.size(); ++i) take(0, x[i]);
  if (nan) throw std::invalid_argument("a sample with NaN");
  return {std::ranges::min(lo), std::ranges::max(hi)};
}

Histogram histogram(std::span<const double> x, double lo, double hi, std::size_t bins) {
  if (!(hi > lo) || bins == 0) throw std::invalid_argument("histogram needs hi > lo and at least one bin");
  Histogram h{lo, hi, std::vector<std::size_t>(bins, 0), x.size()};
  const double width = h.width(), per_width = 1 / width;
  for (double v : x) {
    if (!(v >= lo && v < hi)) continue;
    // The bin is ⌊(v − lo)/width⌋.  A product by 1/width is within a few ulps of that quotient:
    // its floor is the quotient's unless it lies that near an integer, where the quotient
    // decides (a bin's edge, rarely met but for v = lo).
    const double u = (v - lo) * per_width;
    auto i = std::size_t(u);
    if (const double f = u - double(i), slack = 0x1p-40 * u; !(f > slack && f < 1 - slack))
      i = std::size_t((v - lo) / width);
    ++h.counts[std::min(bins - 1, i)];  // ((v − lo)/width can round up to `bins` for v just below hi)
  }
  return h;
}

namespace {

/// The Kolmogorov–Smirnov distance without evaluating the CDF at every value.  At the i-th
/// smallest of n values x the empirical CDF steps from i/n to (i+1)/n, so the distance is the
/// largest of F(x) − i/n and (i+1)/n − F(x).  For a non-decreasing F, values with ranks
/// [a, b) that lie in [lo, hi] have F(x) ∈ [F(lo), F(hi)]: none of their terms exceeds
/// max(F(hi) − a/n, b/n − F(lo)), and when that bound is below the distance found so far they
/// need no evaluation.  The values are tallied into buckets of equal width (one pass, no sort),
/// ranges of buckets are refined level by level while their bound stays above the distance,
/// and the buckets that still may hold the largest term (about 60 of 6·10⁴ at n = 10⁶)
/// are the only ones whose values are gathered (a second pass), sorted and bisected the same
/// way.  The terms evaluated are the same expressions as in a sweep over the sorted sample,
/// and the skipped ones are smaller, so the distance is the sweep's to the bit — as long as F,
/// as computed, never decreases by more than `margin` (rounding of a CDF is ~1e-15).  A few
/// 10³ evaluations of F for 10⁶ values instead of 10⁶.
class KsSearch {
 public:
  KsSearch(std::span<const double> x, const std::function<double(double)>& cdf)
      : x_(x), cdf_(&cdf), n_(double(x.size())) {}
  double distance() {
    if (x_.empty()) return 0;
    tally();
    refine_buckets();
    gather_leaves();
    bisect_leaves();
    return d_;
  }

 private:
  static constexpr double margin = 1e-10;
  struct Bucket {
    std::size_t first = 0, count = 0;      // the ranks of its values: [first, first + count)
    double lo = INFINITY, hi = -INFINITY;  // its smallest and largest value
  };
  /// A bucket that may hold the largest term: its values, once gathered, are
  /// leaf_values_[offset, offset + count); F at its smallest and largest value.
  struct Leaf {
    std::size_t bucket, offset;
    double F_lo, F_hi;
  };
  /// Could a value of rank in [a, b), with F between F_lo and F_hi, raise the distance?
  bool may_raise(double F_lo, double F_hi, std::size_t a, std::size_t b) const {
    return std::max(F_hi - double(a) / n_, double(b) / n_ - F_lo) > d_ - margin;
  }
  /// The terms of the value of rank i.
  double term_at(double x, std::size_t i) {
    const double F = (*cdf_)(x);
    d_ = std::max({d_, F - double(i) / n_, double(i + 1) / n_ - F});
    return F;
  }

  /// The bucket of a value (monotonic in x: rounding never puts a larger value into an earlier
  /// bucket).
  std::size_t bucket_of(double v) const {
    return scale_ > 0 ? std::min(buckets_.size() - 1, std::size_t((v - lo_) * scale_)) : 0;
  }
  /// Buckets of equal width between the smallest and the largest value, about 16 values each:
  /// how many values fall into each, and their extremes.
  void tally() {
    const auto [lo, hi] = sample_range(x_);
    const std::size_t count = std::clamp<std::size_t>(x_.size() / 16, 1, std::size_t(1) << 16);
    lo_ = lo;
    scale_ = hi > lo && std::isfinite(double(count) / (hi - lo)) ? double(count) / (hi - lo) : 0;
    buckets_.resize(count);
    for (double v : x_) {
      Bucket& b = buckets_[bucket_of(v)];
      ++b.count, b.lo = std::min(b.lo, v), b.hi = std::max(b.hi, v);
    }
    std::size_t first = 0;
    for (std::size_t j = 0; j < count; ++j) {
      buckets_[j].first = first, first += buckets_[j].count;
      if (buckets_[j].count > 0) filled_.push_back(j);
    }
  }
  const Bucket& filled(std::size_t j) const { return buckets_[filled_[j]]; }

  /// Ranges [j0, j1) of filled buckets, level by level (the coarse levels bring the distance
  /// near its value early, so that finer ranges are skipped); F at each range's two extreme
  /// values.  A single bucket that may still raise the distance becomes a leaf.
  void refine_buckets() {
    struct Range {
      std::size_t j0, j1;
      double F_lo, F_hi;
    };
    const std::size_t last = filled_.size() - 1;
    std::vector<Range> level{{0, filled_.size(), term_at(filled(0).lo, 0), term_at(filled(last).hi, x_.size() - 1)}};
    while (!level.empty()) {
      std::vector<Range> finer;
      for (const auto& r : level) {
        const Bucket &a = filled(r.j0), &b = filled(r.j1 - 1);
        if (!may_raise(r.F_lo, r.F_hi, a.first, b.first + b.count)) continue;
        if (r.j1 - r.j0 == 1) {
          leaves_.push_back({filled_[r.j0], 0, r.F_lo, r.F_hi});
          continue;
        }
        const std::size_t mid = (r.j0 + r.j1) / 2;
        const Bucket &left = filled(mid - 1), &right = filled(mid);
        finer.push_back({r.j0, mid, r.F_lo, term_at(left.hi, left.first + left.count - 1)});
        finer.push_back({mid, r.j1, term_at(right.lo, right.first), r.F_hi});
      }
      level = std::move(finer);
    }
  }

  /// The leaves' values, each leaf's together, from one pass over the sample.
  void gather_leaves() {
    constexpr auto none = std::numeric_limits<std::size_t>::max();
    std::vector<std::size_t> leaf_of(buckets_.size(), none), next(leaves_.size());
    std::size_t size = 0;
    for (std::size_t l = 0; l < leaves_.size(); ++l) {
      leaf_of[leaves_[l].bucket] = l;
      next[l] = leaves_[l].offset = size;
      size += buckets_[leaves_[l].bucket].count;
    }
    leaf_values_.resize(size);
    for (double v : x_)
      if (const std::size_t l = leaf_of[bucket_of(v)]; l != none) leaf_values_[next[l]++] = v;
  }
  /// Each leaf that still may raise the distance, sorted: its values between the first and the
  /// last (whose F are known) by bisection.
  void bisect_leaves() {
    for (const auto& leaf : leaves_) {
      const Bucket& b = buckets_[leaf.bucket];
      if (!may_raise(leaf.F_lo, leaf.F_hi, b.first, b.first + b.count)) continue;
      double* v = leaf_values_.data() + leaf.offset;
      std::sort(v, v + b.count);
      bisect(v - b.first, b.first, b.first + b.count - 1, leaf.F_lo, leaf.F_hi);
    }
  }
  /// The values of ranks strictly between i and j, sorted values by rank sorted[·], F(x_i) and
  /// F(x_j) given.
  void bisect(const double* sorted, std::size_t i, std::size_t j, double F_i, double F_j) {
    if (j - i < 2 || sorted[i] == sorted[j]) return;  // (equal values: the ends' terms are the largest)
    if (!may_raise(F_i, F_j, i + 1, j)) return;
    const std::size_t mid = i + (j - i) / 2;
    const double F_mid = term_at(sorted[mid], mid);
    bisect(sorted, i, mid, F_i, F_mid);
    bisect(sorted, mid, j, F_mid, F_j);
  }

  std::span<const double> x_;
  const std::function<double(double)>* cdf_;
  double n_;
  double d_ = 0;
  double lo_ = 0, scale_ = 0;  // the buckets' origin and their number per unit of x
  std::vector<Bucket> buckets_;
  std::vector<std::size_t> filled_;  // the non-empty buckets, in order of value
  std::vector<Leaf> leaves_;
  std::vector<double> leaf_values_;
};

}  // namespace

double ks_distance(std::span<const double> x, const std::function<double(double)>& cdf) {
  return KsSearch(x, cdf).distance();
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
