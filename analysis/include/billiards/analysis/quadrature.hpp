// Globally adaptive Gauss–Kronrod quadrature that returns a usable error estimate.
//
// Boost's gauss_kronrod<>::integrate (1.74) reports each subinterval's error on the reference
// interval [−1, 1], unscaled, so after refinement its estimate is inflated by 1/(half-width)
// and means little.  This routine takes Boost's 15-point Kronrod nodes and weights with their
// embedded 7-point Gauss rule and always splits the subinterval with the largest |K15 − G7|
// (as QUADPACK's QAG does).
#pragma once

#include <functional>

namespace billiards::analysis {

struct Quadrature {
  double value = 0;
  double error = 0;  // Σ |K15 − G7| over the final subintervals: an upper estimate for smooth f
};

/// ∫_a^b f, refined until error ≤ tolerance · Σ|∫ over each subinterval| (so an integrand whose
/// parts cancel still terminates) or until 2000 subintervals.
///
/// Like every Gauss rule it never samples the ends of a subinterval: a kink between a
/// subinterval's end and its outermost node (0.4% of its width) is invisible to the estimate.
/// Integrate piecewise between known kinks.
Quadrature integrate_adaptive(const std::function<double(double)>& f, double a, double b, double tolerance = 1e-10);

}  // namespace billiards::analysis
