// Exit times of straight 3-D flights (see walls3.hpp for the rules).
#include "billiards/dynamics/walls3.hpp"

#include <gmpxx.h>

#include <algorithm>

namespace billiards::dynamics {

namespace {

int sphere_discriminant_sign_exact(const Vec3& x, const Vec3& c, const Vec3& v, double r) {
  // Doubles are dyadic rationals, so every step is exact.
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

/// r²|v|² − |f × v|², the cancellation-free b² − a c of the ray–sphere quadratic.
double sphere_discriminant(const Vec3& f, const Vec3& v, double r2) {
  return r2 * v.squaredNorm() - f.cross(v).squaredNorm();
}

}  // namespace

int sphere_discriminant_sign_filtered(const Vec3& x, const Vec3& c, const Vec3& v, double r) {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const Vec3 f = x - c;
  double spread2 = 0;  // Σ (|f_i v_j| + |f_j v_i|)², bounding the rounding of |f × v|²
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const double s = std::abs(f[i] * v[j]) + std::abs(f[j] * v[i]);
    spread2 += s * s;
  }
  const double r2v2 = r * r * v.squaredNorm();
  const double D = r2v2 - f.cross(v).squaredNorm();
  // Rounding of f (1 ulp each), of the products, the cross components, their squares and the
  // sums: well under 16 eps of the magnitudes; 32 for margin.  GMP decides what this cannot.
  const double bound = 32 * eps * (r2v2 + spread2);
  if (D > bound) return 1;
  if (D < -bound) return -1;
  return sphere_discriminant_sign_exact(x, c, v, r);
}

Ray::Ray(const Vec3& x, const Vec3& v) : origin(x), dir(v) {
  v.cwiseAbs().maxCoeff(&kz);
  kx = (kz + 1) % 3;
  ky = (kx + 1) % 3;
  if (v[kz] < 0) std::swap(kx, ky);  // keeps the winding of the sheared triangle
  sx = v[kx] / v[kz];
  sy = v[ky] / v[kz];
  sz = 1 / v[kz];
}

TriangleWall::TriangleWall(const Vec3& a, const Vec3& b, const Vec3& c, double slack_)
    : p{a, b, c}, normal((b - a).cross(c - a).normalized()), slack(slack_) {
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    edge_normal[k] = (p[(k + 1) % 3] - p[k]).cross(normal).normalized();
    longest = std::max(longest, (p[(k + 1) % 3] - p[k]).norm());
  }
  span_slack = slack * longest / (b - a).cross(c - a).norm();  // slack / smallest altitude
}

double straight_exit_time(const State3& s, const PlaneWall& w, double t_end) {
  const double rate = w.normal.dot(s.v);
  if (!(rate > 0)) return never;
  const double beyond = w.normal.dot(s.x) - w.offset;
  if (beyond > w.slack) return never;
  const double t = s.t + (beyond >= 0 ? 0.0 : -beyond / rate);
  return t <= t_end ? t : never;
}

double straight_exit_time(const State3& s, const Ray& ray, const TriangleWall& w, double t_end) {
  const double beyond = w.normal.dot(s.x - w.p[0]);
  if (beyond > w.slack) return never;  // elsewhere in a non-convex region
  if (beyond >= 0) return w.normal.dot(s.v) > 0 && w.within_span(s.x) ? s.t : never;
  // Strictly on the region's side: the watertight test, for crossings ahead only.  An outward
  // crossing has all edge functions ≤ 0 and det < 0 (counter-clockwise seen from outside).
  const Vec3 a = w.p[0] - ray.origin, b = w.p[1] - ray.origin, c = w.p[2] - ray.origin;
  const double ax = a[ray.kx] - ray.sx * a[ray.kz], ay = a[ray.ky] - ray.sy * a[ray.kz];
  const double bx = b[ray.kx] - ray.sx * b[ray.kz], by = b[ray.ky] - ray.sy * b[ray.kz];
  const double cx = c[ray.kx] - ray.sx * c[ray.kz], cy = c[ray.ky] - ray.sy * c[ray.kz];
  const double u = cx * by - cy * bx, v = ax * cy - ay * cx, e = bx * ay - by * ax;
  const double det = u + v + e;
  // Barycentric coordinates u/det, v/det, e/det ≥ −span_slack: the exact watertight test,
  // widened by the slack so that a crossing within rounding of an edge is also caught by the
  // triangle on whose side the particle starts (the neighbour may be tested at dt = 0).
  if (!(det < 0) || std::max({u, v, e}) > -w.span_slack * det) return never;
  const double T = ray.sz * (u * a[ray.kz] + v * b[ray.kz] + e * c[ray.kz]);
  // beyond < 0 puts the crossing ahead; a negative T/det is rounding.
  const double t = s.t + std::max(0.0, T / det);
  return t <= t_end ? t : never;
}

double straight_exit_time(const State3& s, const SphereWall& w, double t_end) {
  // |f + v τ|² − r² = a τ² + 2 b τ + c with f = x − centre (as for 2-D full circles).
  const Vec3 f = s.x - w.center;
  const double a = s.v.squaredNorm(), b = f.dot(s.v), c = f.squaredNorm() - w.radius2;
  const double near = 2 * w.radius * w.slack;  // c ≈ 2 r × (distance beyond the sphere)
  double dt;
  if (w.focusing) {
    if (b >= 0 && c >= 0) return c <= near ? s.t : never;  // on the sphere moving out: now
    // Outside the sphere (escaped) and moving in: a miss or a graze is no exit.
    if (c > 0 && sphere_discriminant_sign_filtered(s.x, w.center, s.v, w.radius) <= 0) return never;
    const double root = std::sqrt(std::max(0.0, sphere_discriminant(f, s.v, w.radius2)));
    dt = b <= 0 ? (root - b) / a : -c / (b + root);
  } else {
    if (b >= 0) return never;  // moving away from the ball
    if (c <= 0) {
      if (c < -near) return never;  // deep inside the ball: not near it
      dt = 0;
    } else {
      // A miss or an exact tangency (a touch, not a crossing) is no collision.
      if (sphere_discriminant_sign_filtered(s.x, w.center, s.v, w.radius) <= 0) return never;
      dt = c / (std::sqrt(std::max(0.0, sphere_discriminant(f, s.v, w.radius2))) - b);
    }
  }
  const double t = s.t + dt;
  return t <= t_end ? t : never;
}

}  // namespace billiards::dynamics
