// Walls prepared for fast collision queries: each boundary piece with the quantities the
// hot loop needs precomputed, and the span tests shared by every flight model.  The scalar
// type is a parameter (double for ensembles; long double and MPFR for reference runs): the
// pieces' double coordinates convert exactly.
//
// Span tests are CLOSED and slightly EXTENDED (by `slack`, a few hundred ulps of the
// coordinates in the scalar type's precision): a crossing computed just past the end of a
// piece is still accepted, so a trajectory through a joint is caught by at least one of the
// two pieces meeting there and can never slip between them.  Consecutive pieces share their
// joint point bit for bit.
#pragma once

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
  V bound_center;     // a disk holding the segment and its span's slack
  Real bound_radius;

  explicit BasicSegmentWall(const geometry::Segment& s) : a(s.a.cast<Real>()), b(s.b.cast<Real>()) {
    const V d = b - a;
    normal = V(d.y(), -d.x()).normalized();  // right of travel = out of the region
    dir = d / d.squaredNorm();
    using std::max;
    slack = span_slack_ulps<Real> * max({Real(a.template lpNorm<Eigen::Infinity>()),
                                         Real(b.template lpNorm<Eigen::Infinity>()), Real(d.norm())});
    bound_center = (a + b) / 2;
    bound_radius = d.norm() / 2 + slack;
  }
  /// Is p (on the supporting line, to rounding) within the segment, ends included?
  bool within_span(const V& p) const {
    const Real s = (p - a).dot(dir);
    const Real tol = slack * dir.norm();
    return s >= -tol && s <= 1 + tol;
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
};

using SegmentWall = BasicSegmentWall<double>;
using ArcWall = BasicArcWall<double>;

}  // namespace billiards::dynamics
