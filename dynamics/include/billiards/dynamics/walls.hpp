// Walls prepared for fast collision queries: each boundary piece with the quantities the
// hot loop needs precomputed, and the span tests shared by every flight model.  The scalar
// type is a parameter (double for ensembles; long double and MPFR for reference runs): the
// pieces' double coordinates convert exactly.
//
// Every wall kind supplies the same small set of queries: gap(x), the signed gap (> 0 beyond
// the wall's curve, on the side away from the region; 0 on it; for segments and arcs the
// signed distance to the supporting line or circle, for elliptic arcs the same in the
// ellipse's mapped units times its smaller semi-axis); normal_at, the region's outward unit
// normal; within_span; contact (the hit point of a flight moved onto the curve, and the normal
// there); curvature_at (signed, > 0 focusing); distance and may_be_near (for the independent
// point-in-region test); crossings (its ray-crossing count); and `slack`, its rounding
// tolerance in distance units.  For the certified scan of a driven flight, segments and arcs
// also supply `gap_along(q)`, their gap seen along the flight q (PlaneGap, SphereGap below: f,
// its rounding, the windows in which it can vanish, the sign of f'), and `may_meet_span(p, q,
// pad)`, whether a point near the segment [p, q] can be within the span.
//
// Span tests are CLOSED and slightly EXTENDED (by `slack`, a few hundred ulps of the
// coordinates in the scalar type's precision): a crossing computed just past the end of a
// piece is still accepted, so a trajectory through a joint is caught by at least one of the
// two pieces meeting there and can never slip between them.  Consecutive pieces share their
// joint point bit for bit.
#pragma once

#include "billiards/dynamics/certified_scan.hpp"
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

/// Distance from the segment [p, q] to the sphere (circle) of centre c and radius r: the
/// segment's distances from c fill [nearest, farthest].
template <class V, class Real>
Real segment_sphere_distance(const V& p, const V& q, const V& c, const Real& r) {
  using std::max;
  const Real nearest = point_segment_distance(c, p, q), farthest = max((p - c).norm(), (q - c).norm());
  return max({Real(nearest - r), Real(r - farthest), Real(0)});
}

/// Distance from the segment [p, q] to the plane through a with unit normal n (a lower bound
/// for any piece of it).
template <class V, class Real = typename V::Scalar>
Real segment_plane_distance(const V& p, const V& q, const V& n, const V& a) {
  using std::abs;
  using std::min;
  const Real fp = n.dot(p - a), fq = n.dot(q - a);
  return fp * fq <= 0 ? Real(0) : min(abs(fp), abs(fq));
}

namespace scan {

// The walls' gaps along a flight, in 2-D and 3-D: the wall geometry of the certified scan.

/// How far beyond the line (2-D) or plane (3-D) through `a` with outward unit normal `n` the
/// flight `q` is: f = n·(x − a), which lies within B = |n·F|/(mω²) of its guiding part
/// g_off + nu τ; `q` is a flight seen as a guiding line with bounded deviation
/// (forced_flight.hpp's Quiver).  A gap gives a scan of one wall everything it needs: f and its
/// rounding, the windows (the only times at which f can vanish) and a bound on the sign of f'
/// in a window.  Its numbers along the guide, window and sign of f' are driven_exit-inl.hpp's,
/// which the lock-step kernel runs too.
template <class Q, class V>
struct PlaneGap {
  using Real = typename Q::Real;
  using L = ScalarLanes<Real>;
  const Q& q;
  V n, a;
  PlaneGapLanes<Real> g;

  PlaneGap(const Q& q_, const V& n_, const V& a_, const Real& slack) : q(q_), n(n_), a(a_) {
    g = plane_gap<L>(q.lanes(), n.dot(q.flight.accel), n.dot(q.u), n.dot(q.g0 - a), slack);
  }
  /// The rounding level of f at τ.
  Real tolerance(const Real& tau) const { return scan::tolerance<L>(g, tau); }
  Sample<Real, V> sample(const Real& tau) const {
    const auto [x, v] = q.at(tau);
    return {n.dot(x - a), n.dot(v), g.n_a, never, x};
  }
  Taylor<Real, V, typename Q::Mark> taylor(const Real& tau) const {
    const auto m = q.motion(tau);
    return {n.dot(m.x - a), n.dot(m.v), n.dot(m.a), m.x, band(tau), {m.th, m.sin_th, m.cos_th}};
  }
  /// The level below which |f| (as `taylor` gives it) is within the rounding band at τ.
  Real band(const Real& tau) const { return scan::band<L>(g, tau); }
  /// The rounding of f itself at τ (the band without the walls' slack): a root known to that
  /// level is as good as a polished one.
  Real rounding(const Real& tau) const { return scan::rounding<L>(g, tau); }
  Real jerk_bound(const Window<Real>& w) const { return scan::jerk_bound<L>(g, q.lanes(), w.margin); }
  /// First time ≥ τ at which the guide comes within the margin (B and rounding) of the wall, or
  /// +∞: before it f cannot vanish.
  Real window_start(const Real& tau) const {
    const Real margin = g.B + tolerance(tau), guide = g.g_off + g.nu * tau;
    return guide < 0 ? reach_linear(tau, guide, g.nu, Real(-margin))
                     : reach_linear(tau, Real(-guide), Real(-g.nu), Real(-margin));
  }
  /// When the guide, from the window's start, is twice the margin away (so that the scan leaves
  /// the window for good), or tau_end.
  Real window_end(const Real& start, const Real& tau_end) const {
    using std::min;
    if (g.nu == 0) return start;
    const Real margin = g.B + tolerance(start), guide = g.g_off + g.nu * start;
    return min(Real(start + ((g.nu > 0 ? 2 : -2) * margin - guide) / g.nu), tau_end);
  }
  /// The window until `horizon` into out; returns their number (0 or 1).
  int windows(const Real& horizon, Window<Real>* out) const {
    return append_window(0, out, window<L>(g, q.lanes(), horizon, true));
  }
  int slope_sign(const Window<Real>&) const { return int(scan::slope_sign<L>(g, q.lanes())); }
};

/// The same for the circle (2-D) or sphere (3-D) of centre c and radius r, the region inside it
/// when `focusing`: f = ±(|x − c| − r), where |x − c| lies within δ of the guide's distance
/// from c.  Its numbers along the guide, windows, sign of f' and Taylor samples are
/// driven_exit-inl.hpp's, which the lock-step kernel runs too.
template <class Q, class V>
struct SphereGap {
  using Real = typename Q::Real;
  using L = ScalarLanes<Real>;
  const Q& q;
  V c;
  SphereGapLanes<Real> g;

  SphereGap(const Q& q_, const V& c_, const Real& r, bool focusing, const Real& slack) : q(q_), c(c_) {
    const V q0 = q.g0 - c;
    g = sphere_gap<L>(q.lanes(), r, Real(focusing ? 1 : -1), slack, q0.dot(q.u), q0.squaredNorm(),
                      Real(q0.template lpNorm<1>() * q.u.template lpNorm<1>()), (q.s.x - c).template lpNorm<1>(),
                      q.rounding_rate);
  }
  Real tolerance(const Real& tau) const { return scan::tolerance<L>(g, tau); }
  Sample<Real, V> sample(const Real& tau) const {
    const auto [x, v] = q.at(tau);
    const V p = x - c;
    const Real rho = p.norm(), f = g.sign * (rho - g.r);
    if (rho < g.r / 2) {
      // Nearer the centre than the wall, f'' is unbounded (at the centre p̂·v is 0/0), but
      // |f'| ≤ |v|: the Lipschitz bound |f(τ + s) − f(τ)| ≤ |v| s + A s²/2, as a sample moving
      // towards zero at |v| with M = A, steps through safely, ~|f|/|v| at a time.
      const Real speed = v.norm();
      return {f, f < 0 ? speed : Real(-speed), q.accel_norm, never, x};
    }
    // d²|p|/dt² = (|v|² − (p̂·v)²)/|p| + p̂·a ≤ V²/|p| + A; valid while |p| ≥ ρ/2.
    const Real Vb = q.speed_bound;
    return {f, g.sign * p.dot(v) / rho, 2 * Vb * Vb / rho + q.accel_norm, rho / (2 * Vb), x};
  }
  /// ±(|p|² − r²) and its derivatives (|p| − r ≤ tol is certain when ||p|² − r²| ≤ `band`).
  Taylor<Real, V, typename Q::Mark> taylor(const Real& tau) const {
    const auto m = q.motion(tau);
    const V p = m.x - c;
    const auto t = scan::taylor<L>(g, p.squaredNorm(), p.dot(m.v), m.v.squaredNorm(), p.dot(m.a));
    return {t.f, t.df, t.d2f, m.x, band(tau), {m.th, m.sin_th, m.cos_th}};
  }
  Real band(const Real& tau) const { return scan::band<L>(g, tau); }
  Real rounding(const Real& tau) const { return scan::rounding<L>(g, tau); }
  Real jerk_bound(const Window<Real>& w) const { return scan::jerk_bound<L>(g, q.lanes(), w.margin); }
  Real window_start(const Real& tau) const {
    using std::max;
    const V gd = q.guide(tau) - c;
    const Real margin = q.delta + tolerance(tau);
    return gd.squaredNorm() < g.r * g.r ? reach_radius(tau, gd, q.u, max(Real(0), Real(g.r - margin)), true)
                                        : reach_radius(tau, gd, q.u, Real(g.r + margin), false);
  }
  Real window_end(const Real& start, const Real& tau_end) const {
    using std::max;
    using std::min;
    const V gd = q.guide(start) - c;
    const Real margin = q.delta + tolerance(start);
    return min({reach_radius(start, gd, q.u, Real(g.r + 2 * margin), true),
                reach_radius(start, gd, q.u, max(Real(0), Real(g.r - 2 * margin)), false), tau_end});
  }
  /// The windows until `horizon` into out; returns their number.  A guide standing still has
  /// one, the whole flight.
  int windows(const Real& horizon, Window<Real>* out) const {
    if (!(q.uu > 0)) return append_window(0, out, Real(0), horizon, Real(q.delta + tolerance(horizon)), false, horizon);
    WindowLanes<Real, bool> first, second;
    scan::windows<L>(g, q.lanes(), horizon, true, first, second);
    return append_window(append_window(0, out, first), out, second);
  }
  int slope_sign(const Window<Real>& w) const {
    return int(scan::slope_sign<L>(g, q.lanes(), w.start, w.end, w.margin));
  }
};

}  // namespace scan

/// Relative slack of span tests, in units of the coordinate scale.
template <class Real>
inline const Real span_slack_ulps = 256 * std::numeric_limits<Real>::epsilon();

/// A contact point and normal in lanes of one number (straight_exit-inl.hpp's), as the walls
/// return them.
template <class Real>
std::pair<Vec2T<Real>, Vec2T<Real>> pair_of(const ContactLanes<Real>& c) {
  return {{c.x, c.y}, {c.nx, c.ny}};
}

/// `gap_sample` of a wall whose gap is ±(ρ − R), ρ the distance from its centre in units that
/// lengthen no vector (an arc: |x − c| and its radius; an elliptic arc: m |u|, u = L(x − c),
/// and m, its smaller semi-axis: m L lengthens no vector), with ρ ρ' = `rho_rate`, for a flight
/// of speed V and acceleration within A.  Over h the flight moves by at most V h + A h²/2:
/// h = ρ/(2(V + A)) keeps that within ρ/2 while h ≤ 2 (a short step keeps the bound small),
/// beyond that the positive root of V h + A h²/2 = ρ/2, which is shorter.  So ρ stays above ρ/2
/// and |v| below V + A h, and |f''| ≤ 2 (V + A h)²/ρ + A.  Nearer the centre than R/2 (where f'' is unbounded and ρ' is 0/0 at
/// the centre), the Lipschitz bound |f'| ≤ |v| ≤ V + A τ instead.
template <class Real, class V>
[[gnu::always_inline]] inline scan::Sample<Real, V> radial_gap_sample(bool focusing, const Real& R, const Real& rho, const Real& rho_rate,
                                        const Real& speed, const Real& A, const V& x) {
  using std::sqrt;
  const Real sign = focusing ? 1 : -1, f = sign * (rho - R);
  if (rho < R / 2) return {f, f < 0 ? speed : Real(-speed), A, Real(never), x};
  Real h = rho / (2 * (speed + A) + Real(1e-300));  // (1e-300: a particle at rest)
  if (h > 2 && A > 0) h = rho / (speed + sqrt(speed * speed + A * rho));
  const Real vmax = speed + A * h;
  return {f, sign * rho_rate / rho, 2 * vmax * vmax / rho + A, h, x};
}

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
  bool within_span(const V& p) const { return dynamics::within_span(ScalarLanes<Real>{}, segment_lanes(*this), p.x(), p.y()); }
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
  /// The gap at a point x of a flight with velocity v and acceleration within A, its rate, and
  /// the bound on its second derivative: what the certified scan needs of a wall to search a
  /// flight that has no closed form for it (scan::gap_crossing).
  scan::Sample<Real, V> gap_sample(const V& x, const V& v, const Real& A) const {
    return {gap(x), normal.dot(v), A, Real(never), x};
  }
  template <class Q>
  scan::PlaneGap<Q, V> gap_along(const Q& q) const { return {q, normal, a, slack}; }
  /// Can a point within `pad` of the segment [p, q] lie in the span?  The span is an
  /// intersection of half-planes, whose linear functions take their extremes over [p, q] at p
  /// or q; false only when certainly not.
  bool may_meet_span(const V& p, const V& q, const Real& pad) const {
    return scan::may_meet_span<ScalarLanes<Real>>(segment_lanes(*this), Real(dir.norm()), pad, p.x(), p.y(), q.x(), q.y());
  }
  Real curvature_at(const V&) const { return 0; }
  V normal_at(const V&) const { return normal; }
  /// The point of the segment nearest p and the normal (segment_contact, which says why).
  std::pair<V, V> contact(const V& p, const V&) const {
    return pair_of(segment_contact<ScalarLanes<Real>>(segment_lanes(*this), b.x(), b.y(), p.x(), p.y()));
  }
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
  Real span_tol;       // slack × radius: within_span's tolerance on its cross products
  Real near;           // 2 radius × slack: within rounding of the circle, in units of |x − c|² − r²

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
    set_slack(slack);
  }
  /// Sets the slack and the tolerances made from it.
  void set_slack(const Real& s) {
    slack = s;
    span_tol = slack * radius;
    near = 2 * radius * slack;
  }
  /// Is p (on the circle, to rounding) within the arc, ends included?
  bool within_span(const V& p) const { return dynamics::within_span(ScalarLanes<Real>{}, arc_lanes(*this), p.x(), p.y()); }
  /// Where the flight through the hit point p with velocity v meets the circle, and the
  /// region's outward unit normal there.  Hit points computed along a chord are off the circle
  /// by rounding; left there, a whispering-gallery orbit (10⁴ bounces at a grazing angle)
  /// random-walks outward until it is beyond the circle by more than the slack, and escapes.
  /// The point moves along the flight, by one Newton step of |u + s v|² = r² (u = p − c, with
  /// |u|² − r² never rounded near r²), so that the angular momentum about the centre, u × v,
  /// keeps to rounding: the hit time's own rounding is biased (the chord is a quotient of dot
  /// products near |v|²), and a radial projection turned that bias along v into one of the
  /// angular momentum, −0.1 ε per bounce at steep incidence.  Where the step is not short
  /// (`short_step`: grazing incidence, or a point off the circle by more than rounding), the
  /// radial projection.
  /// (arc_contact, straight_exit-inl.hpp, written once for this and the lock-step search.)
  std::pair<V, V> contact(const V& p, const V& v) const {
    return pair_of(arc_contact(ScalarLanes<Real>{}, arc_lanes(*this), slack, p.x(), p.y(), v.x(), v.y()));
  }
  /// The point of the circle nearest p, and the region's outward unit normal there.  One
  /// square root and one division give both (the normal alone, (p − c)/r, took two divisions).
  std::pair<V, V> radial_contact(const V& p) const {
    return pair_of(dynamics::radial_contact<ScalarLanes<Real>>(arc_lanes(*this), p.x(), p.y()));
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
  scan::Sample<Real, V> gap_sample(const V& x, const V& v, const Real& A) const {
    const V p = x - center;
    return radial_gap_sample(focusing, radius, Real(p.norm()), Real(p.dot(v)), Real(v.norm()), A, x);
  }
  template <class Q>
  scan::SphereGap<Q, V> gap_along(const Q& q) const { return {q, center, radius, focusing, slack}; }
  /// As for segments; the span of an arc longer than a half circle is a union of half-planes
  /// (driven_exit-inl.hpp).
  bool may_meet_span(const V& p, const V& q, const Real& pad) const {
    const V a = p - center, b = q - center;
    return scan::may_meet_span<ScalarLanes<Real>>(arc_lanes(*this), slack, pad, a.x(), a.y(), b.x(), b.y());
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

/// The numbers of segments and arcs as straight_exit-inl.hpp and driven_exit-inl.hpp read them
/// (read in place).
template <class Real>
ArcLanes<const Real&, bool> arc_lanes(const BasicArcWall<Real>& w) {
  return {w.center.x(), w.center.y(), w.radius, w.radius2, w.near, w.span_tol, w.from.x(), w.from.y(),
          w.to.x(),     w.to.y(),     w.focusing, w.full, w.ccw_extent <= geometry::pi};
}
template <class Real>
SegmentLanes<const Real&> segment_lanes(const BasicSegmentWall<Real>& w) {
  return {w.a.x(), w.a.y(), w.normal.x(), w.normal.y(), w.dir.x(), w.dir.y(), w.slack, w.span_tol};
}


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
    unit.set_slack(unit_slack);
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
  /// In mapped units scaled by the smaller semi-axis m: ρ = m |u|, ρ ρ' = m² u·Lv.
  scan::Sample<Real, V> gap_sample(const V& x, const V& v, const Real& A) const {
    using std::min;
    const Real m = min(a, b);
    const V u = to_unit(x);
    return radial_gap_sample(focusing, m, Real(m * u.norm()), Real(m * m * u.dot(map * v)), Real(v.norm()), A, x);
  }
  /// Where the flight through the hit point p with velocity v meets the ellipse, and the
  /// region's outward unit normal there: as for arcs, one Newton step along the flight in
  /// mapped units (the map keeps lines), or, where the step is not short, the radial
  /// projection in mapped units.
  std::pair<V, V> contact(const V& p, const V& v) const {
    const V u = to_unit(p), w = map * v;
    const Real rate = 2 * u.dot(w), s = -((u.x() * u.x() - 1) + u.y() * u.y()) / rate;
    if (!short_step(ScalarLanes<Real>{}, s, rate, v.x(), v.y(), w.x(), w.y(), slack)) return radial_contact(p);
    const V q = p + s * v;
    return {q, normal_through(to_unit(q))};
  }
  /// The point of the ellipse on the ray from its centre through p (in mapped units, the
  /// radial projection, as for arcs), and the region's outward unit normal there.
  std::pair<V, V> radial_contact(const V& p) const {
    using std::sqrt;
    const V u = to_unit(p);
    const V n = u * Real(1 / sqrt(u.squaredNorm()));
    return {center + inverse * n, normal_through(n)};
  }
  V normal_at(const V& p) const { return radial_contact(p).second; }
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
  /// The region's outward unit normal at the point of mapped coordinates u, ∝ Lᵀ u.
  V normal_through(const V& u) const {
    const V normal = (map.transpose() * u).normalized();
    return focusing ? normal : V(-normal);
  }
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

/// An elliptic arc's map as straight_exit-inl.hpp reads it (read in place).
template <class Real>
EllipseMapLanes<const Real&> ellipse_map_lanes(const BasicEllipticArcWall<Real>& w) {
  return {w.center.x(), w.center.y(), w.map(0, 0), w.map(0, 1), w.map(1, 0), w.map(1, 1)};
}

using SegmentWall = BasicSegmentWall<double>;
using ArcWall = BasicArcWall<double>;
using EllipticArcWall = BasicEllipticArcWall<double>;

}  // namespace billiards::dynamics
