// Validation of a 2-D region with CGAL's exact circle-segment arrangements.
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
// Orientation is the sign of the Green's-theorem area (the loops are simple by then, so it is
// far above the rounding).  Nesting is decided exactly by ray casting on the arrangement's
// edges; the loops are disjoint by then, so the test point is on no other loop.
#include "billiards/geometry/validate.hpp"

#include "billiards/geometry/input_error.hpp"
#include "billiards/geometry/measures.hpp"

#include <CGAL/Arr_circle_segment_traits_2.h>
#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace billiards::geometry {

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Base_traits = CGAL::Arr_circle_segment_traits_2<Kernel>;
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<Base_traits, int>;  // data: piece number
using Arrangement = CGAL::Arrangement_2<Traits>;
using XCurve = Traits::X_monotone_curve_2;
using Point = Traits::Point_2;

/// Distance to a joint, relative to the table's diameter, within which a common point of the
/// two pieces meeting there is that joint (rounding displaces it by at most ~1e-15).
constexpr double joint_tolerance = 1e-9;

// ---------------------------------------------------------------- naming pieces in messages

struct PieceId {
  int loop = 0, index = 0;  // loop 0 is the outer boundary, loop k is holes[k - 1]
};

const Loop& loop_of(const Region2& r, int k) { return k == 0 ? r.outer : r.holes[k - 1]; }
int loop_count(const Region2& r) { return 1 + int(r.holes.size()); }
const Piece& piece_of(const Region2& r, PieceId id) { return loop_of(r, id.loop).pieces[id.index]; }
const SourceRef& where_of(const Region2& r, PieceId id) { return loop_of(r, id.loop).where[id.index]; }

bool is_full_circle(const Piece& p) {
  const auto* a = std::get_if<Arc>(&p);
  return a && std::abs(a->sweep) >= 2 * pi;
}

/// "segment at line 12", "circle at line 20".
std::string name_of(const Region2& r, PieceId id) {
  const Piece& p = piece_of(r, id);
  return fmt::format("{} at line {}", is_full_circle(p) ? "circle" : kind_of(p), where_of(r, id).line);
}

std::string text(const Vec2& q) { return fmt::format("({:.9g}, {:.9g})", q.x(), q.y()); }

Vec2 to_vec(const Point& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y())}; }

[[noreturn]] void fail(const SourceRef& at, const std::string& message) {
  throw InputError(at.file, at.line, message);
}

// ---------------------------------------------------------------- (1) pieces and closure

bool finite(const Piece& p) {
  const auto ok = [](const Vec2& v) { return v.allFinite(); };
  if (const auto* s = std::get_if<Segment>(&p)) return ok(s->a) && ok(s->b);
  const auto& a = std::get<Arc>(p);
  return ok(a.center) && ok(a.source) && ok(a.target) && std::isfinite(a.radius) && std::isfinite(a.start) &&
         std::isfinite(a.sweep);
}

void check_piece(const Piece& p, const SourceRef& at) {
  if (!finite(p)) fail(at, fmt::format("the {} has a coordinate that is not a finite number", kind_of(p)));
  const auto* a = std::get_if<Arc>(&p);
  if (a && !(a->radius > 0)) fail(at, "the arc's radius must be positive");
  if (!(length_of(p) > 0)) fail(at, fmt::format("zero-length {}: it must have a positive length", kind_of(p)));
  if (a && std::abs(a->sweep) > 2 * pi) fail(at, "the arc sweeps more than a full turn");
  if (a && a->source == a->target && !is_full_circle(p))
    fail(at, "the arc starts and ends at the same point: a full circle needs a sweep of ±2π");
}

void check_loop(const Loop& loop, const char* what) {
  const int n = int(loop.pieces.size());
  if (loop.where.size() != loop.pieces.size())
    throw std::invalid_argument("validate: every piece of a loop needs its SourceRef in loop.where");
  if (n == 0) fail(loop.origin, fmt::format("the {} has no pieces", what));
  for (int i = 0; i < n; ++i) check_piece(loop.pieces[i], loop.where[i]);
  for (int i = 0; i < n; ++i) {
    const Piece &p = loop.pieces[i], &next = loop.pieces[(i + 1) % n];
    if (is_full_circle(p) && n > 1) fail(loop.where[i], "a full circle must be a loop by itself");
    if (target_of(p) != source_of(next))
      fail(loop.where[i], fmt::format("the loop is not closed: this {} ends at {} but the {} at line {} begins at {}",
                                      kind_of(p), text(target_of(p)), kind_of(next), loop.where[(i + 1) % n].line,
                                      text(source_of(next))));
  }
}

/// Diameter of the box around every piece: the length the tolerance is relative to.
double diameter(const Region2& r) {
  Vec2 lo = Vec2::Constant(INFINITY), hi = -lo;
  for (const Loop* loop : r.loops())
    for (const Piece& p : loop->pieces) {
      const auto [a, b] = bounding_box(p);
      lo = lo.cwiseMin(a);
      hi = hi.cwiseMax(b);
    }
  return (hi - lo).norm();
}

/// The CGAL model goes through each arc's source and target, the simulator uses its centre,
/// radius and angles: they must agree.
void check_arc_ends(const Region2& r, double tol) {
  for (const Loop* loop : r.loops())
    for (std::size_t i = 0; i < loop->pieces.size(); ++i) {
      const auto* a = std::get_if<Arc>(&loop->pieces[i]);
      if (a && ((a->point_at(a->start) - a->source).norm() > tol ||
                (a->point_at(a->start + a->sweep) - a->target).norm() > tol))
        fail(loop->where[i], "the arc's ends are not the points of its circle at its start and end angles");
    }
}

// ---------------------------------------------------------------- (2, 3) simple and disjoint

Traits::Curve_2 to_cgal(const Piece& p, int number) {
  const auto exact = [](const Vec2& v) { return Kernel::Point_2(v.x(), v.y()); };
  if (const auto* s = std::get_if<Segment>(&p)) return {Kernel::Segment_2(exact(s->a), exact(s->b)), number};
  const auto& a = std::get<Arc>(p);
  if (is_full_circle(p)) {
    const Kernel::FT r(a.radius);
    return {Kernel::Circle_2(exact(a.center), r * r, a.sweep > 0 ? CGAL::COUNTERCLOCKWISE : CGAL::CLOCKWISE),
            number};
  }
  // Three collinear points (an arc too flat for doubles) give a segment.
  return {Base_traits::Curve_2(exact(a.source), exact(point_along(p, 0.5)), exact(a.target)), number};
}

/// All pieces in one arrangement, each curve tagged with its index in `ids`.
Arrangement arrangement_of(const Region2& r, std::vector<PieceId>& ids) {
  std::vector<Traits::Curve_2> curves;
  for (int k = 0; k < loop_count(r); ++k)
    for (int i = 0; i < int(loop_of(r, k).pieces.size()); ++i) {
      curves.push_back(to_cgal(loop_of(r, k).pieces[i], int(ids.size())));
      ids.push_back({k, i});
    }
  Arrangement arr;
  CGAL::insert(arr, curves.begin(), curves.end());
  return arr;
}

/// Whether q is (within tol) a joint at which pieces a and b follow each other.
bool is_joint(const Region2& r, PieceId a, PieceId b, const Vec2& q, double tol) {
  if (a.loop != b.loop) return false;
  const Loop& loop = loop_of(r, a.loop);
  const int n = int(loop.pieces.size());
  const auto ends_at_q_before = [&](int i, int j) {
    return (i + 1) % n == j && (target_of(loop.pieces[i]) - q).norm() <= tol;
  };
  return ends_at_q_before(a.index, b.index) || ends_at_q_before(b.index, a.index);
}

/// "the segment at line 3 and the arc at line 5 <how>", worded for one loop, a hole against
/// the outer boundary, or two holes; reported at the line of the later piece.
[[noreturn]] void fail_meeting(const Region2& r, PieceId a, PieceId b, const std::string& how) {
  if (std::tie(b.loop, b.index) < std::tie(a.loop, a.index)) std::swap(a, b);
  const std::string pair = fmt::format("the {} and the {} {}", name_of(r, a), name_of(r, b), how);
  const int hole_line = loop_of(r, b.loop).origin.line;
  if (a.loop == b.loop) fail(where_of(r, b), pair);
  if (a.loop == 0)
    fail(where_of(r, b), fmt::format("the hole at line {} is not strictly inside the outer boundary: {}; a hole must "
                                     "lie strictly inside, apart from other walls",
                                     hole_line, pair));
  fail(where_of(r, b), fmt::format("the holes at lines {} and {} overlap or touch: {}; a hole must lie strictly "
                                   "inside, apart from other walls",
                                   loop_of(r, a.loop).origin.line, hole_line, pair));
}

void check_no_overlap(const Region2& r, const Arrangement& arr, const std::vector<PieceId>& ids) {
  for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
    const auto& data = e->curve().data();
    if (data.size() < 2) continue;
    const int a = *data.begin(), b = *std::next(data.begin());
    fail_meeting(r, ids[a], ids[b],
                 fmt::format("overlap from {} to {}", text(to_vec(e->curve().left())),
                             text(to_vec(e->curve().right()))));
  }
}

/// Every vertex lies on one piece (CGAL's split of an arc into x-monotone parts) or is the
/// joint of two consecutive pieces.
void check_vertices(const Region2& r, const Arrangement& arr, const std::vector<PieceId>& ids, double tol) {
  for (auto v = arr.vertices_begin(); v != arr.vertices_end(); ++v) {
    std::vector<int> at;  // the pieces through v
    auto he = v->incident_halfedges();
    const auto first = he;
    do {
      const auto& data = he->curve().data();
      at.insert(at.end(), data.begin(), data.end());
    } while (++he != first);
    std::sort(at.begin(), at.end());
    at.erase(std::unique(at.begin(), at.end()), at.end());
    const Vec2 q = to_vec(v->point());
    for (std::size_t i = 0; i < at.size(); ++i)
      for (std::size_t j = i + 1; j < at.size(); ++j)
        if (!is_joint(r, ids[at[i]], ids[at[j]], q, tol))
          fail_meeting(r, ids[at[i]], ids[at[j]], "cross or touch at " + text(q));
  }
}

// ---------------------------------------------------------------- (4) orientation, (3) nesting

constexpr const char* outer_runs_clockwise =
    "the outer boundary runs clockwise: list its pieces counter-clockwise (region on the left)";

void check_orientation(const Region2& r) {
  if (!(signed_area(r.outer) > 0))
    fail(r.outer.origin, outer_runs_clockwise);
  for (const Loop& hole : r.holes)
    if (!(signed_area(hole) < 0))
      fail(hole.origin, "the hole runs counter-clockwise: list its pieces clockwise (region on the left)");
}

/// Whether p, which is on no curve of the loop, is inside it: parity of the loop's crossings
/// with the upward vertical ray from p, exact.  A curve counts when p.x ∈ [left.x, right.x), so
/// a ray through a vertex counts it once, or twice where the loop turns back.
bool inside(const Point& p, const std::vector<XCurve>& loop) {
  const Traits traits;
  const auto compare_x = traits.compare_x_2_object();
  const auto compare_y_at_x = traits.compare_y_at_x_2_object();
  bool in = false;
  for (const XCurve& c : loop) {
    if (traits.is_vertical_2_object()(c)) continue;
    if (compare_x(traits.construct_min_vertex_2_object()(c), p) != CGAL::LARGER &&
        compare_x(p, traits.construct_max_vertex_2_object()(c)) == CGAL::SMALLER &&
        compare_y_at_x(p, c) == CGAL::SMALLER)
      in = !in;
  }
  return in;
}

void check_nesting(const Region2& r, const Arrangement& arr, const std::vector<PieceId>& ids) {
  std::vector<std::vector<XCurve>> curves(loop_count(r));
  std::vector<Point> on(loop_count(r));  // a point on each loop
  for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
    const int k = ids[*e->curve().data().begin()].loop;
    curves[k].push_back(e->curve());
    on[k] = e->source()->point();
  }
  for (int k = 1; k < loop_count(r); ++k) {
    const SourceRef& at = loop_of(r, k).origin;
    if (!inside(on[k], curves[0])) fail(at, "the hole is not inside the outer boundary");
    for (int g = 1; g < loop_count(r); ++g)
      if (g != k && inside(on[k], curves[g]))
        fail(at, fmt::format("the hole lies inside the hole at line {}", loop_of(r, g).origin.line));
  }
}

}  // namespace

void validate(const Region2& region) {
  for (int k = 0; k < loop_count(region); ++k) check_loop(loop_of(region, k), k == 0 ? "outer boundary" : "hole");
  const double tol = joint_tolerance * diameter(region);
  check_arc_ends(region, tol);
  std::vector<PieceId> ids;
  const Arrangement arr = arrangement_of(region, ids);
  try {
    check_no_overlap(region, arr, ids);
    check_vertices(region, arr, ids, tol);
  } catch (const InputError& e) {
    // Pieces listed clockwise make arcs bulge the wrong way and cross: say so (a figure-eight,
    // of zero area, is only crossed).
    if (signed_area(region.outer) < 0) throw InputError(e.file(), e.line(), e.message() + "; " + outer_runs_clockwise);
    throw;
  }
  check_orientation(region);
  check_nesting(region, arr, ids);
}

}  // namespace billiards::geometry
