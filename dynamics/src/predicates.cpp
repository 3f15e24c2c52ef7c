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

int sphere_discriminant_sign_exact(const Eigen::Vector3d& x, const Eigen::Vector3d& c, const Eigen::Vector3d& v, double r) {
  // (Exact as above.)
  mpq_class f[3], w[3];
  for (int k = 0; k < 3; ++k) f[k] = mpq_class(x[k]) - c[k], w[k] = v[k];
  mpq_class cross2 = 0, v2 = 0;
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const mpq_class ck = f[i] * w[j] - f[j] * w[i];
    cross2 += ck * ck;
    v2 += w[k] * w[k];
  }
  const mpq_class rr(r);
  return sgn(rr * rr * v2 - cross2);
}

}  // namespace billiards::dynamics
