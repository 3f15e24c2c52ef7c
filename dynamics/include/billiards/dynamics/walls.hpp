// Walls prepared for fast collision queries: each boundary piece with the quantities the
// hot loop needs precomputed, and the span tests shared by every flight model.  The scalar
// type is a parameter (double for ensembles; long double and MPFR for reference runs): the
// pieces' double coordinates convert exactly.
//
// Every wall kind supplies the same small set of queries: gap(x), the signed gap (> 0 beyond
// the wall's curve, on the side away from the region; 0 on it; for segments and arcs the
// signed distance to the supporting line or circle, for elliptic arcs the same in the
// ellipse's mapped units times its smaller semi-axis); normal_at, the region's outward unit
// normal; within_span; contact (the hit point projected onto the curve, and the normal
// there); curvature_at (signed, > 0 focusing); distance and may_be_near (for the independent
// point-in-region test); crossings (its ray-crossing count); and `slack`, its rounding
// tolerance in distance units.
//
// Span tests are CLOSED and slightly EXTENDED (by `slack`, a few hundred ulps of the
// coordinates in the scalar type's precision): a crossing computed just past the end of a
// piece is still accepted, so a trajectory through a joint is caught by at least one of the
// two pieces meeting there and can never slip between them.  Consecutive pieces share their
// joint point bit for bit.
#pragma once

#include "billiards/geometry/elliptic_arc.hpp"
#include "billiards/geometry/pieces.hpp"

#include <algorithm>
#include <utility>
#include <cmath>
#include <limits>

namespace billiards::dynamics {

using geometry::Vec2;
using geometry::Vec2T;
using geometry::cross;

/// Distance from x to the segment [p, q] (a point when p = q), in any dimension.
template <class V>
auto point_segment_distance(const V& x, const V& p, const V& q) {
  using Real = typename V::Scalar;
  const V d = q - p;
  const Real dd = d.squaredNorm();
  const Real s = dd > 0 ? std::clamp(Real((x - p).dot(d) / dd), Real(0), Real(1)) : Real(0);
  return Real((x - p - s * d).norm());
}

/// Relative slack of span tests, in units of the coordinate scale.
template <class Real>
inline const Real span_slack_ulps = 256 * std::numeric_limits<Real>::epsilon();

template <class Real>
struct BasicSegmentWall {
  using V = Vec2T<Real>;
  V a, b;
  V normal;    // outward unit normal (right of a→b)
  V dir;       // (b - a) / |b - a|²
  Real slack;  // absolute tolerance along the segment
  Real span_tol;      // slack |dir|: the tolerance in units of the segment's parameter
  V bound_center;     // a disk holding the segment and its span's slack
  Real bound_radius;

  explicit BasicSegmentWall(const geometry::Segment& s) : a(s.a.cast<Real>()), b(s.b.cast<Real>()) {
    const V d = b - a;
    normal = V(d.y(), -d.x()).normalized();  // right of travel = out of the region
    dir = d / d.squaredNorm();
    using std::max;
    slack = span_slack_ulps<Real> * max({Real(a.template lpNorm<Eigen::Infinity>()),
                                         Real(b.template lpNorm<Eigen::Infinity>()), Real(d.norm())});
    span_tol = slack * dir.norm();
    bound_center = (a + b) / 2;
    bound_radius = d.norm() / 2 + slack;
  }
  /// Is p (on the supporting line, to rounding) within the segment, ends included?
  bool within_span(const V& p) const {
    const Real s = (p - a).dot(dir);
    return s >= -span_tol && s <= 1 + span_tol;
  }
  /// The point of the segment nearest p: a hit point computed near a corner may lie past the
  /// end by up to the span slack, beyond the neighbouring wall; projected, it never does.
  V project(const V& p) const {
    const Real s = (p - a).dot(dir);
    if (s <= 0) return a;
    if (s >= 1) return b;
    return p - normal * normal.dot(p - a);  // (not a + s (b − a), which rounds along the wall too)
  }
  /// Distance from p to the segment.
  Real distance(const V& p) const { return point_segment_distance(p, a, b); }
  /// Can p be within `tol` of the segment?  Its line's distance bounds the segment's from below
  /// with no square root or division; false only beyond 2 tol, far past either's rounding.
  bool may_be_near(const V& p, double tol) const {
    using std::abs;
    return abs(normal.dot(p - a)) <= 2 * tol;
  }
  /// Signed number of times the horizontal ray from p to +∞ crosses the segment upward
  /// (half-open rule on y, so that a vertex is counted once).
  int crossings(const V& p) const {
    const bool up = a.y() <= p.y() && b.y() > p.y();
    const bool down = b.y() <= p.y() && a.y() > p.y();
    if (!up && !down) return 0;
    const Real side = cross(V(b - a), V(p - a));  // > 0: p left of a→b
    return up ? (side > 0 ? 1 : 0) : (side < 0 ? -1 : 0);
  }
  Real gap(const V& p) const { return normal.dot(p - a); }
  Real curvature_at(const V&) const { return 0; }
  V normal_at(const V&) const { return normal; }
  std::pair<V, V> contact(const V& p) const { return {project(p), normal}; }
  /// Distance from the segment [p, q] to this one (to rounding): zero when they cross, else
  /// the least distance from an end of one to the other.
  Real distance(const V& p, const V& q) const {
    using std::min;
    const Real fp = normal.dot(p - a), fq = normal.dot(q - a), ga = cross(V(q - p), V(a - p)), gb = cross(V(q - p), V(b - p));
    if (fp * fq <= 0 && ga * gb <= 0) return 0;
    return min({distance(p), distance(q), point_segment_distance(a, p, q), point_segment_distance(b, p, q)});
  }
};

template <class Real>
struct BasicArcWall {
  using V = Vec2T<Real>;
  V center;
  Real radius, radius2;
  V from, to;          // endpoints relative to the centre, in counter-clockwise order
  double ccw_extent;   // counter-clockwise angle from `from` to `to`, in (0, 2π]
  bool focusing;       // region inside the circle (sweep > 0)
  bool full;           // a whole circle
  Real slack;          // absolute tolerance (distance units)
  V bound_center;      // a disk holding the arc and its span's slack: the one on its chord
  Real bound_radius;   // (Thales) up to a half circle, else the circle's own

  explicit BasicArcWall(const geometry::Arc& arc)
      : center(arc.center.cast<Real>()), radius(arc.radius), radius2(radius * radius),
        ccw_extent(std::abs(arc.sweep)), focusing(arc.sweep > 0), full(std::abs(arc.sweep) >= 2 * geometry::pi) {
    // Store the endpoints in counter-clockwise order so one span test serves both senses.
    const V s = arc.source.cast<Real>() - center, t = arc.target.cast<Real>() - center;
    from = focusing ? s : t;
    to = focusing ? t : s;
    using std::max;
    slack = span_slack_ulps<Real> * max(radius, Real(center.template lpNorm<Eigen::Infinity>()));
    const bool chord = !full && ccw_extent <= geometry::pi;
    bound_center = chord ? V(center + (from + to) / 2) : center;
    bound_radius = (chord ? Real((to - from).norm() / 2) : radius) + slack;
  }
  /// Is p (on the circle, to rounding) within the arc, ends included?
  bool within_span(const V& p) const {
    if (full) return true;
    const V u = p - center;
    const Real tol = slack * radius;
    if (ccw_extent <= geometry::pi) return cross(from, u) >= -tol && cross(u, to) >= -tol;
    // More than a half circle: inside unless strictly within the complementary arc (< π).
    return !(cross(to, u) > tol && cross(u, from) > tol);
  }
  /// The point of the circle nearest p, and the region's outward unit normal there.  Hit
  /// points computed along a chord are off the circle by rounding; left there, a
  /// whispering-gallery orbit (10⁴ bounces at a grazing angle) random-walks outward until it is
  /// beyond the circle by more than the slack, and escapes.  One square root and one division
  /// give both (the normal alone, (p − c)/r, took two divisions).
  std::pair<V, V> contact(const V& p) const {
    using std::sqrt;
    const V u = p - center;
    const V n = u * Real(1 / sqrt(u.squaredNorm()));
    return {center + radius * n, focusing ? V(n) : V(-n)};
  }
  /// Distance from p to the arc: to the circle where p's radial projection is within the span,
  /// else to the nearer end.
  Real distance(const V& p) const {
    using std::abs;
    using std::min;
    const V u = p - center;
    const Real rho = u.norm();
    if (rho > 0 && within_span(V(center + radius / rho * u))) return abs(rho - radius);
    return min(Real((p - center - from).norm()), Real((p - center - to).norm()));
  }
  /// Distance from the segment [p, q] to the arc (to rounding): zero when the segment meets the
  /// circle within the span; otherwise the nearest points are an end of the arc and a point of
  /// [p, q], or an end of [p, q] or the foot of the perpendicular from the centre and its
  /// nearest point of the arc.
  Real distance(const V& p, const V& q) const {
    using std::clamp;
    using std::min;
    using std::sqrt;
    const V d = q - p, pc = p - center;
    const Real dd = d.squaredNorm(), b = pc.dot(d), disc = b * b - dd * (pc.squaredNorm() - radius2);
    if (dd > 0 && disc >= 0) {
      for (const Real& root : {Real(-sqrt(disc)), Real(sqrt(disc))}) {
        const Real s = (root - b) / dd;
        if (s >= 0 && s <= 1 && within_span(V(p + s * d))) return 0;
      }
    }
    const Real s = dd > 0 ? clamp(Real(-b / dd), Real(0), Real(1)) : Real(0);
    return min({distance(p), distance(q), distance(V(p + s * d)), point_segment_distance(V(center + from), p, q),
                point_segment_distance(V(center + to), p, q)});
  }
  /// Outward unit normal of the region at p.
  V normal_at(const V& p) const {
    const V u = (p - center) / radius;
    return focusing ? V(u) : V(-u);
  }
  Real gap(const V& p) const {
    const Real d = (p - center).norm() - radius;
    return focusing ? d : Real(-d);
  }
  /// Signed curvature seen from the region (geometry::Arc::curvature).
  Real curvature_at(const V&) const { return (focusing ? Real(1) : Real(-1)) / radius; }
  /// Can p be within `tol` of the arc?  Its circle's distance bounds the arc's from below.
  bool may_be_near(const V& p, double tol) const {
    using std::max;
    const Real d2 = (p - center).squaredNorm();
    const Real outer = radius + 2 * tol, inner = max(Real(0), Real(radius - 2 * tol));
    return d2 <= outer * outer && d2 >= inner * inner;
  }
  /// Signed number of times the horizontal ray from p to +∞ crosses the arc upward: it meets
  /// the circle at most twice.
  int crossings(const V& p) const {
    using std::sqrt;
    const Real dy = p.y() - center.y();
    const Real h2 = radius2 - dy * dy;
    if (h2 <= 0) return 0;
    const Real h = sqrt(h2);
    int n = 0;
    for (const int sx : {-1, 1}) {
      const V q(center.x() + sx * h, p.y());
      if (q.x() <= p.x() || !within_span(q)) continue;
      // Travelling counter-clockwise the circle goes up on its right half (sx = +1).
      const int ccw_up = sx > 0 ? 1 : -1;
      n += focusing ? ccw_up : -ccw_up;
    }
    return n;
  }
};

/// An elliptic arc, seen through the affine map u = L (x − c) that takes its ellipse to the
/// unit circle (L = diag(1/a, 1/b) R(−angle)).  There it is the circular arc `unit` (centre 0,
/// radius 1), and a flight whose law is covariant under L — a straight line, a parabola, the
/// drive: uniform accelerations map to uniform accelerations — is a flight of the same kind,
/// so its exit time through this arc is the mapped flight's exit time through `unit` (time is
/// not mapped).  `unit`'s slack is this wall's in mapped units: the rounding of L (x − c) is
/// that of x − c divided by the smaller semi-axis.
template <class Real>
struct BasicEllipticArcWall {
  using V = Vec2T<Real>;
  using M = Eigen::Matrix<Real, 2, 2>;
  V center;
  M map, inverse;      // L and L⁻¹ = R(angle) diag(a, b)
  Real a, b;           // semi-axes
  bool focusing;       // region inside the ellipse (sweep > 0)
  Real slack;          // absolute tolerance (distance units)
  BasicArcWall<Real> unit;
  V bound_center;      // a disk holding the arc and its span's slack
  Real bound_radius;

  explicit BasicEllipticArcWall(const geometry::EllipticArc& e)
      : center(e.center.cast<Real>()), a(e.semi_axes.x()), b(e.semi_axes.y()), focusing(e.sweep > 0),
        unit(unit_arc(e)) {
    using std::cos;
    using std::max;
    using std::min;
    using std::sin;
    const Real c = cos(Real(e.angle)), s = sin(Real(e.angle));
    inverse << c * a, -s * b, s * a, c * b;
    map << c / a, s / a, -s / b, c / b;
    slack = span_slack_ulps<Real> * max({a, b, Real(center.template lpNorm<Eigen::Infinity>())});
    const Real unit_slack = slack / min(a, b);
    unit.bound_radius += unit_slack - unit.slack;
    unit.slack = unit_slack;
    bound_center = center;
    bound_radius = max(a, b) + slack;
  }
  V to_unit(const V& x) const { return map * (x - center); }
  Real gap(const V& p) const {
    using std::min;
    const Real d = min(a, b) * (to_unit(p).norm() - 1);
    return focusing ? d : Real(-d);
  }
  bool within_span(const V& p) const { return unit.within_span(to_unit(p)); }
  /// The point of the ellipse on the ray from its centre through p (in mapped units, the
  /// radial projection, as for arcs), and the region's outward unit normal there, ∝ Lᵀ u.
  std::pair<V, V> contact(const V& p) const {
    using std::sqrt;
    const V u = to_unit(p);
    const V n = u * Real(1 / sqrt(u.squaredNorm()));
    const V normal = (map.transpose() * n).normalized();
    return {center + inverse * n, focusing ? normal : V(-normal)};
  }
  V normal_at(const V& p) const { return contact(p).second; }
  /// Signed curvature seen from the region: ab / (a² sin² φ + b² cos² φ)^{3/2} at the point of
  /// eccentric anomaly φ.
  Real curvature_at(const V& p) const {
    using std::sqrt;
    const V u = to_unit(p);
    const Real s2 = u.y() * u.y() / u.squaredNorm(), c2 = 1 - s2, q = a * a * s2 + b * b * c2;
    return (focusing ? Real(1) : Real(-1)) * a * b / (q * sqrt(q));
  }
  /// Distances: lower bounds, the unit arc's in mapped units times the smaller semi-axis (L⁻¹
  /// stretches by at most the larger and at least the smaller), exact for circles.
  Real distance(const V& p) const {
    using std::min;
    return min(a, b) * unit.distance(to_unit(p));
  }
  Real distance(const V& p, const V& q) const {
    using std::min;
    return min(a, b) * unit.distance(to_unit(p), to_unit(q));
  }
  bool may_be_near(const V& p, double tol) const {
    using std::max;
    using std::min;
    const Real r2 = to_unit(p).squaredNorm(), t = 2 * tol / min(a, b);
    return r2 <= (1 + t) * (1 + t) && r2 >= max(Real(0), Real(1 - t)) * max(Real(0), Real(1 - t));
  }
  /// Signed number of times the horizontal ray from p to +∞ crosses the arc upward.  The ray
  /// maps to the ray u + s L e_x; at each crossing in the span, the counter-clockwise tangent
  /// L⁻¹ (−u_y, u_x) says whether the ellipse goes up.
  int crossings(const V& p) const {
    using std::sqrt;
    const V u = to_unit(p), d = map.col(0);
    const Real qa = d.squaredNorm(), qb = u.dot(d), qc = u.squaredNorm() - 1, disc = qb * qb - qa * qc;
    if (disc <= 0) return 0;
    int n = 0;
    for (const Real& root : {Real(-sqrt(disc)), Real(sqrt(disc))}) {
      const Real s = (root - qb) / qa;
      const V w = u + s * d;
      if (!(s > 0) || !unit.within_span(w)) continue;
      const Real up = inverse.row(1).dot(V(-w.y(), w.x()));
      if (up == 0) continue;
      n += (up > 0) == focusing ? 1 : -1;
    }
    return n;
  }

 private:
  static BasicArcWall<Real> unit_arc(const geometry::EllipticArc& e) {
    const double c = std::cos(e.angle), s = std::sin(e.angle);
    const auto to_unit = [&](const Vec2& x) {
      const Vec2 r = x - e.center;
      return Vec2((c * r.x() + s * r.y()) / e.semi_axes.x(), (-s * r.x() + c * r.y()) / e.semi_axes.y());
    };
    geometry::Arc arc;
    arc.center = Vec2::Zero();
    arc.radius = 1;
    arc.start = e.start;
    arc.sweep = e.sweep;
    arc.source = to_unit(e.source);
    arc.target = to_unit(e.target);
    return BasicArcWall<Real>(arc);
  }
};

using SegmentWall = BasicSegmentWall<double>;
using ArcWall = BasicArcWall<double>;
using EllipticArcWall = BasicEllipticArcWall<double>;

}  // namespace billiards::dynamics
