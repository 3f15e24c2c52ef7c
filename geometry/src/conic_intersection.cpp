// Intersections of two ellipses.  Parametrise A by its eccentric anomaly φ; B's implicit
// function along it, g(φ) = |M(x_A(φ) − c_B)|² − 1 with M = diag(1/a_B, 1/b_B)·R(−θ_B), is a
// trigonometric polynomial of degree 2 (a quartic in tan(φ/2)): at most four roots, g′ at
// most four sign changes.  The critical points of g are bracketed on a fine grid and solved by
// TOMS 748; between consecutive ones g is monotone, so each such interval holds at most one
// crossing, again found by TOMS 748.  A critical point where the curves are within `tol` is a
// tangency (a double root): it is reported once as a touching point, and the roots that
// rounding puts beside it (in the monotone intervals next to it) are not crossings.
#include "conic_intersection.hpp"

#include <boost/math/tools/toms748_solve.hpp>

#include <cmath>

namespace billiards::geometry {

namespace {

/// Critical points of g closer than 2π/grid can be missed (g then has a near-triple root: the
/// curves osculate), far below any deliberate shape.
constexpr int grid = 2048;

/// The affine map q = M(x − c) taking the ellipse onto the unit circle, with its centre c.
struct ToUnitCircle {
  Eigen::Matrix2d M;
  Vec2 c;
  explicit ToUnitCircle(const EllipticArc& e) : c(e.center) {
    const double cs = std::cos(e.angle), sn = std::sin(e.angle);
    M << cs / e.semi_axes.x(), sn / e.semi_axes.x(), -sn / e.semi_axes.y(), cs / e.semi_axes.y();
  }
  /// |g(x)|/|∇g(x)| with g = |q|² − 1.
  double distance(const Vec2& x) const {
    const Vec2 q = M * (x - c);
    return std::abs(q.squaredNorm() - 1) / (2 * (M.transpose() * q).norm());
  }
};

/// B's implicit function along A, with its derivative.
struct Along {
  const EllipticArc& a;
  ToUnitCircle b;

  Along(const EllipticArc& a, const EllipticArc& b) : a(a), b(b) {}
  double g(double phi) const { return (b.M * (a.point_at(phi) - b.c)).squaredNorm() - 1; }
  double dg(double phi) const { return 2 * (b.M * (a.point_at(phi) - b.c)).dot(b.M * a.tangent_at(phi)); }
};

/// The root of f in [lo, hi], where f(lo) and f(hi) differ in sign (or one is zero).
template <class F>
double root_between(F f, double lo, double hi) {
  const double f_lo = f(lo), f_hi = f(hi);
  if (f_lo == 0) return lo;
  if (f_hi == 0) return hi;
  std::uintmax_t iterations = 100;
  const auto [x0, x1] = boost::math::tools::toms748_solve(f, lo, hi, f_lo, f_hi,
                                                          boost::math::tools::eps_tolerance<double>(), iterations);
  return (x0 + x1) / 2;
}

/// The critical points of g in [0, 2π), increasing.
std::vector<double> critical_points(const Along& along) {
  std::vector<double> out;
  const auto dg = [&](double phi) { return along.dg(phi); };
  double lo = 0, d_lo = dg(0);
  for (int i = 1; i <= grid; ++i) {
    const double hi = 2 * pi * i / grid, d_hi = dg(hi);
    if (d_lo == 0) out.push_back(lo);
    else if ((d_lo < 0) != (d_hi < 0) && d_hi != 0) out.push_back(root_between(dg, lo, hi));
    lo = hi;
    d_lo = d_hi;
  }
  return out;
}

}  // namespace

double distance_estimate(const EllipticArc& e, const Vec2& p) { return ToUnitCircle(e).distance(p); }

Meetings meetings(const EllipticArc& a, const EllipticArc& b, double tol) {
  const Along along(a, b);
  const auto g = [&](double phi) { return along.g(phi); };
  const std::vector<double> crit = critical_points(along);
  Meetings m;
  const int n = int(crit.size());
  std::vector<bool> touch(n);
  for (int i = 0; i < n; ++i) {
    touch[i] = along.b.distance(a.point_at(crit[i])) <= tol;
    if (touch[i]) m.touching.push_back(a.point_at(crit[i]));
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    if (touch[i] || touch[j]) continue;
    const double lo = crit[i], hi = j > i ? crit[j] : crit[j] + 2 * pi;
    if ((g(lo) < 0) != (g(hi) < 0)) m.crossing.push_back(a.point_at(root_between(g, lo, hi)));
  }
  return m;
}

}  // namespace billiards::geometry
