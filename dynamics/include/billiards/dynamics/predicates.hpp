// Predicates for the collision kernels.  Names say what they are: `_filtered` predicates
// return the exact sign of a polynomial in the double inputs, deciding in double when a
// forward error bound allows and in exact rational arithmetic (GMP) otherwise.
#pragma once

#include "billiards/geometry/pieces.hpp"

#include <cmath>
#include <limits>

namespace billiards::dynamics {

using geometry::Vec2;

/// b² − a c of the ray–circle quadratic in its cancellation-free form r²|v|² − (f × v)²,
/// f = x − centre (in the scalar type, not exact).
template <class Real>
inline Real circle_discriminant(const geometry::Vec2T<Real>& f, const geometry::Vec2T<Real>& v, const Real& r2) {
  const Real fxv = f.x() * v.y() - f.y() * v.x();
  return r2 * v.squaredNorm() - fxv * fxv;
}

/// Exact sign of r²|v|² − ((x − c) × v)² for the double inputs (r² = r·r taken exactly).
int circle_discriminant_sign_exact(const Vec2& x, const Vec2& c, const Vec2& v, double r);

/// Exact sign of the discriminant, filtered: the double value decides unless it lies within
/// a forward error bound covering the rounding of f = x − c, of r² and of the products and
/// the difference (the bound measured in ../shared/notes, doubled); then GMP decides.
/// `r2` is the kernel's rounded r·r, used only for the fast path.
inline int circle_discriminant_sign_filtered(const Vec2& x, const Vec2& c, const Vec2& v, double r,
                                             double r2) {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const Vec2 f = x - c;
  const double fxv = f.x() * v.y() - f.y() * v.x();
  const double spread = std::abs(f.x() * v.y()) + std::abs(f.y() * v.x());
  const double D = r2 * v.squaredNorm() - fxv * fxv;
  const double bound = 16 * eps * (r2 * v.squaredNorm() + spread * spread);
  if (D > bound) return 1;
  if (D < -bound) return -1;
  return circle_discriminant_sign_exact(x, c, v, r);
}

}  // namespace billiards::dynamics
