#include "billiards/dynamics/predicates.hpp"

#include <gmpxx.h>

namespace billiards::dynamics {

int circle_discriminant_sign_exact(const Vec2& x, const Vec2& c, const Vec2& v, double r) {
  // Doubles are dyadic rationals, so every step below is exact.
  const mpq_class fx = mpq_class(x.x()) - c.x(), fy = mpq_class(x.y()) - c.y();
  const mpq_class vx(v.x()), vy(v.y()), rr(r);
  const mpq_class fxv = fx * vy - fy * vx;
  const mpq_class D = rr * rr * (vx * vx + vy * vy) - fxv * fxv;
  return sgn(D);
}

}  // namespace billiards::dynamics
