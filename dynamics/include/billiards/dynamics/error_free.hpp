// Error-free transformations of doubles (Knuth, Dekker): the exact sum and product of two
// doubles as a rounded result and its exact error (the run's clock, state.hpp; the drive's
// phase, phase.hpp).
#pragma once

#include "billiards/dynamics/phase_constants.hpp"

#include <utility>

namespace billiards::dynamics::detail {

/// a + b = s + e exactly (Knuth's TwoSum).
inline std::pair<double, double> two_sum(double a, double b) {
  const double s = a + b, bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}
/// a + b = s + e exactly when |a| ≥ |b| or a = 0 (Dekker's FastTwoSum).
inline std::pair<double, double> fast_two_sum(double a, double b) {
  const double s = a + b;
  return {s, b - (s - a)};
}
/// a·b = p + e exactly for |a|, |b| < 2⁹⁹⁵ (Dekker's product on Veltkamp's halves).  Not a fused multiply-add: x86-64 without -mfma calls one from libm, and
/// these are the same bits on any processor (the build forbids contraction: CMakeLists.txt).
inline std::pair<double, double> two_prod(double a, double b) {
  auto split = [](double x) {
    const double c = phase_constants::split * x, high = c - (c - x);
    return std::pair{high, x - high};
  };
  const auto [ah, al] = split(a);
  const auto [bh, bl] = split(b);
  const double p = a * b;
  return {p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
}

}  // namespace billiards::dynamics::detail
