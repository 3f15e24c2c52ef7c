// Validation of a 2-D region with elliptic arcs: the checks of validate_cgal.cpp on an
// arrangement of conic arcs (CGAL's Arr_conic_traits_2 with CORE's exact rationals and
// algebraic numbers).
//
// Model.  As for circular arcs, every curve goes through rational points only, so that joints
// are shared bit for bit: a segment is exact; a circular arc is the conic arc through its
// source, its midpoint and its target (CGAL's three-point circular arc); an elliptic arc is the
// conic arc through its source, the doubles nearest its points at 1/4, 1/2 and 3/4 of its sweep
// in eccentric anomaly, and its target (CGAL's five-point conic arc).  Five points on an
// ellipse, each off it by rounding, determine a conic off the declared one by rounding times
// the conditioning of the five-point fit, which is moderate while the points are spread along
// the arc; an arc too flat for five non-collinear doubles is reported.  A full circle keeps its
// rational centre and squared radius; a full ellipse keeps the implicit equation
// (q₁/a)² + (q₂/b)² = 1, q = R(−angle)(x − center), expanded exactly in rationals from the
// doubles of its centre, axes and cos/sin of its angle (an ellipse whatever their rounding:
// 4rs − t² = 4(cos² + sin²)²/(a²b²) > 0).
//
// Tangent joints are accepted within the same tolerance as in validate_cgal.cpp.  Conic
// arrangements compute intersections as roots of degree-4 resultants in CORE's algebraic
// numbers: exact, and much slower than circle-segment arrangements, so tables without elliptic
// arcs never come here.
#include "arrangement_checks_cgal.hpp"

#include <CGAL/Arr_conic_traits_2.h>
#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/CORE_algebraic_number_traits.h>
#include <CGAL/Cartesian.h>

namespace billiards::geometry::validation {

namespace {

using Nt_traits = CGAL::CORE_algebraic_number_traits;
using Rational = Nt_traits::Rational;
using Rat_kernel = CGAL::Cartesian<Rational>;
using Alg_kernel = CGAL::Cartesian<Nt_traits::Algebraic>;
using Conic_traits = CGAL::Arr_conic_traits_2<Rat_kernel, Alg_kernel, Nt_traits>;
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<Conic_traits, int>;  // data: piece number
using Conic_arc = Conic_traits::Curve_2;

Rat_kernel::Point_2 exact(const Vec2& v) { return {Rational(v.x()), Rational(v.y())}; }

/// The full ellipse r x² + s y² + t xy + u x + v y + w = 0, exact in the doubles of `e`.
Conic_arc full_ellipse(const EllipticArc& e) {
  const Rational c(std::cos(e.angle)), s(std::sin(e.angle)), x0(e.center.x()), y0(e.center.y());
  const Rational ia = Rational(1) / (Rational(e.semi_axes.x()) * Rational(e.semi_axes.x()));
  const Rational ib = Rational(1) / (Rational(e.semi_axes.y()) * Rational(e.semi_axes.y()));
  const Rational A = c * c * ia + s * s * ib, B = s * s * ia + c * c * ib, C = 2 * c * s * (ia - ib);
  return Conic_arc(A, B, C, -2 * A * x0 - C * y0, -2 * B * y0 - C * x0, A * x0 * x0 + B * y0 * y0 + C * x0 * y0 - 1);
}

Conic_arc elliptic_arc(const EllipticArc& e, const SourceRef& at) {
  if (is_closed_curve(e)) return full_ellipse(e);
  const auto inner = [&](double f) { return exact(e.point_at(e.start + f * e.sweep)); };
  Conic_arc arc(exact(e.source), inner(0.25), inner(0.5), inner(0.75), exact(e.target));
  if (!arc.is_valid())
    fail(at, "the elliptic arc is too short or too flat for its conic to be fitted exactly through five points "
             "in double precision");
  return arc;
}

Traits::Curve_2 to_cgal(const Piece& p, int number, const SourceRef& at) {
  if (const auto* s = std::get_if<Segment>(&p)) return {Conic_arc(Rat_kernel::Segment_2(exact(s->a), exact(s->b))), number};
  if (const auto* e = std::get_if<EllipticArc>(&p)) return {elliptic_arc(*e, at), number};
  const auto& a = std::get<Arc>(p);
  if (is_closed_curve(p)) {
    const Rational r(a.radius);
    return {Conic_arc(Rat_kernel::Circle_2(exact(a.center), r * r)), number};
  }
  const Conic_arc arc(exact(a.source), exact(point_along(p, 0.5)), exact(a.target));
  // Three collinear points (an arc too flat for doubles) give a segment.
  return {arc.is_valid() ? arc : Conic_arc(Rat_kernel::Segment_2(exact(a.source), exact(a.target))), number};
}

}  // namespace

void check_arrangement_conic(const Region2& r, double tol) { ArrangementChecks<Traits>::run(r, tol, to_cgal); }

}  // namespace billiards::geometry::validation
