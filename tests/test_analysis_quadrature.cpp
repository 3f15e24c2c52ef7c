// Adaptive Gauss–Kronrod: exact where the rule is exact, and an error estimate that bounds the
// true error after refinement (Boost's own adaptive estimate is unscaled).
#include "billiards/analysis/quadrature.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace billiards;

TEST_CASE("a polynomial of degree 13 is exact in one Gauss-Kronrod panel") {
  // G7 and K15 are both exact up to degree 13: their difference is rounding.
  const auto q = analysis::integrate_adaptive([](double x) { return 14 * std::pow(x, 13); }, 0, 2);
  CHECK(q.value == Approx(std::pow(2.0, 14)).epsilon(1e-15));
  CHECK(q.error < 1e-10);
}

TEST_CASE("a peaked integrand: refined where needed, and the estimate bounds the true error") {
  // Runge's function: ∫₋₁¹ dx/(1 + 100x²) = atan(10)/5.
  const double exact = std::atan(10.0) / 5;
  for (double tolerance : {1e-4, 1e-8, 1e-12}) {
    INFO("tolerance = " << tolerance);
    const auto q = analysis::integrate_adaptive([](double x) { return 1 / (1 + 100 * x * x); }, -1, 1, tolerance);
    CHECK(std::abs(q.value - exact) <= q.error);
    CHECK(q.error <= tolerance * exact);
  }
}

TEST_CASE("a square-root kink at a subinterval's end converges") {
  // ∫₀^{5/6} √(5/6 − x) dx = (2/3)(5/6)^{3/2}: the shape of γ_E(x) at a turning point, with the
  // kink at the end as the wall quadrature arranges.
  const double exact = 2.0 / 3 * std::pow(5.0 / 6, 1.5);
  const auto q =
      analysis::integrate_adaptive([](double x) { return std::sqrt(std::max(0.0, 5.0 / 6 - x)); }, 0, 5.0 / 6, 1e-13);
  CHECK(std::abs(q.value - exact) <= q.error);
  CHECK(q.error <= 1e-13 * exact);
}

TEST_CASE("an integrand that cancels to zero still terminates") {
  const auto q = analysis::integrate_adaptive([](double x) { return std::sin(x); }, -3, 3);
  CHECK(std::abs(q.value) < 1e-14);
  CHECK(q.error < 1e-9);
}
