#include "billiards/analysis/quadrature.hpp"

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace billiards::analysis {

namespace {

using Kronrod = boost::math::quadrature::gauss_kronrod<double, 15>;
using Gauss = boost::math::quadrature::gauss<double, 7>;

struct Interval {
  double a, b;
  Quadrature q;
};

/// K15 and its embedded G7 on [a, b].  Both node lists start at 0 and hold the non-negative
/// half; the Gauss nodes are the Kronrod nodes of even index.
Interval rule(const std::function<double(double)>& f, double a, double b) {
  const auto& x = Kronrod::abscissa();
  const auto& wk = Kronrod::weights();
  const auto& wg = Gauss::weights();
  const double c = (a + b) / 2, h = (b - a) / 2;
  const double fc = f(c);
  double kronrod = wk[0] * fc, gauss = wg[0] * fc;
  for (std::size_t i = 1; i < x.size(); ++i) {
    const double pair = f(c - h * x[i]) + f(c + h * x[i]);
    kronrod += wk[i] * pair;
    if (i % 2 == 0) gauss += wg[i / 2] * pair;
  }
  return {a, b, {h * kronrod, std::abs(h * (kronrod - gauss))}};
}

bool smaller_error(const Interval& l, const Interval& r) { return l.q.error < r.q.error; }

}  // namespace

Quadrature integrate_adaptive(const std::function<double(double)>& f, double a, double b, double tolerance) {
  constexpr std::size_t max_intervals = 2000;
  std::vector<Interval> heap{rule(f, a, b)};  // a max-heap on the error
  auto total = [&] {
    Quadrature sum;
    for (const Interval& i : heap) {
      sum.value += i.q.value;
      sum.error += i.q.error;
    }
    return sum;
  };
  auto converged = [&] {
    double error = 0, magnitude = 0;
    for (const Interval& i : heap) {
      error += i.q.error;
      magnitude += std::abs(i.q.value);
    }
    return error <= tolerance * magnitude;
  };
  while (!converged() && heap.size() < max_intervals) {
    std::pop_heap(heap.begin(), heap.end(), smaller_error);
    const Interval worst = heap.back();
    const double mid = (worst.a + worst.b) / 2;
    if (!(worst.a < mid && mid < worst.b)) break;  // no double left between its ends
    heap.back() = rule(f, worst.a, mid);
    std::push_heap(heap.begin(), heap.end(), smaller_error);
    heap.push_back(rule(f, mid, worst.b));
    std::push_heap(heap.begin(), heap.end(), smaller_error);
  }
  return total();
}

}  // namespace billiards::analysis
