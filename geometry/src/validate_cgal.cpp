// Validation of a 2-D region with CGAL's exact circle-segment arrangements (tables of segments
// and circular arcs; validate_conic_cgal.cpp extends the model to elliptic arcs).
//
// Model.  Coordinates are doubles, i.e. exact dyadic rationals, so every segment is exact in
// CGAL.  An arc becomes the circular arc through three rational points: its source, the double
// nearest its midpoint, and its target.  Consecutive CGAL curves thus share their joint bit for
// bit, every loop closes exactly, and no irrational centre (the clover's) or radius is needed;
// the curve differs from the declared arc by rounding only.  A full circle has no joint: it
// keeps its centre and squared radius, both rational.
//
// Tangent joints.  Two pieces declared tangent at a joint are tangent in CGAL only up to that
// rounding, so their curves may cross a second time beside the joint.  Both curves go through
// the exact joint, so that second point is off by the rounding times a geometric factor (about
// R₁R₂/(|R₁ ∓ R₂|·chord)), not by its square root: at most 1e-15 of the table's diameter,
// measured over random clovers, stadiums, cusped triangles and four-centre ovals (radii equal to
// 1e-6) at scales 1e-6 to 1e6.  A common point of two consecutive pieces within
// `joint_tolerance` of a joint they share is therefore taken to be that joint; every other
// common point of two pieces is an error, even one 1e-6 of the table away from a joint.
//
// Algorithm.  All loops go into one Arrangement_2 (an exact sweep, O((n + k) log n)) whose
// curves carry the number of their user piece (Arr_consolidated_curve_data_traits_2): CGAL's
// splits of arcs into x-monotone parts, and overlaps, keep that attribution.  Every vertex is
// then checked: one piece (a split, not a corner), or two consecutive pieces at their joint.
// Unlike CGAL::compute_intersection_points, which returns bare points and (unless told to
// report every curve end) skips points where only curve ends meet, this names the pieces
// exactly and sees a loop passing twice through one point, or a hole's corner on an outer one.
//
// The checks themselves are generic in the traits: arrangement_checks_cgal.hpp.
//
// Orientation is the sign of the Green's-theorem area (the loops are simple by then, so it is
// far above the rounding).  Nesting is decided exactly by ray casting on the arrangement's
// edges; the loops are disjoint by then, so the test point is on no other loop.
#include "arrangement_checks_cgal.hpp"

#include <CGAL/Arr_circle_segment_traits_2.h>
#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

namespace billiards::geometry::validation {

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Base_traits = CGAL::Arr_circle_segment_traits_2<Kernel>;
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<Base_traits, int>;  // data: piece number

Traits::Curve_2 to_cgal(const Piece& p, int number, const SourceRef&) {
  const auto exact = [](const Vec2& v) { return Kernel::Point_2(v.x(), v.y()); };
  if (const auto* s = std::get_if<Segment>(&p)) return {Kernel::Segment_2(exact(s->a), exact(s->b)), number};
  const auto& a = std::get<Arc>(p);
  if (is_closed_curve(p)) {
    const Kernel::FT r(a.radius);
    return {Kernel::Circle_2(exact(a.center), r * r, a.sweep > 0 ? CGAL::COUNTERCLOCKWISE : CGAL::CLOCKWISE),
            number};
  }
  // Three collinear points (an arc too flat for doubles) give a segment.
  return {Base_traits::Curve_2(exact(a.source), exact(point_along(p, 0.5)), exact(a.target)), number};
}

}  // namespace

void check_arrangement_circle_segment(const Region2& r, double tol) {
  ArrangementChecks<Traits>::run(r, tol, to_cgal);
}

}  // namespace billiards::geometry::validation
