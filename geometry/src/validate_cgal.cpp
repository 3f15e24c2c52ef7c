// Validation of a 2-D region with CGAL's exact circle-segment arrangement traits.
//
// Scheme.  Doubles are dyadic rationals, so every segment is exact in CGAL.  An arc is handed
// to CGAL as the circular arc through three rational points: its two joints (shared bit for bit
// with its neighbours, so every loop closes exactly) and its midpoint.  That circle may differ
// from the declared one by rounding (the clover's centres are irrational), so two arcs declared
// tangent at a joint can cross a second time within ~√ε of it; intersection points within
// `joint_tolerance` of the declared joint of two consecutive pieces are therefore that joint.
// Every other intersection (CGAL's sweep, exact) is a crossing or a touch, and an error.
#include "billiards/geometry/validate.hpp"

#include "billiards/geometry/input_error.hpp"
#include "billiards/geometry/measures.hpp"

#include <CGAL/Arr_circle_segment_traits_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Surface_sweep_2_algorithms.h>

#include <cmath>
#include <fmt/format.h>

namespace billiards::geometry {

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Traits = CGAL::Arr_circle_segment_traits_2<Kernel>;
using Curve = Traits::Curve_2;
using RPoint = Kernel::Point_2;

/// Relative distance (to the table's size) within which an intersection is a declared joint.
constexpr double joint_tolerance = 1e-6;

RPoint rational(const Vec2& p) { return RPoint(p.x(), p.y()); }

Curve to_cgal(const Piece& p) {
  if (const auto* s = std::get_if<Segment>(&p)) return Curve(Kernel::Segment_2(rational(s->a), rational(s->b)));
  const auto& a = std::get<Arc>(p);
  if (std::abs(a.sweep) >= 2 * pi) {
    const Kernel::FT r(a.radius);
    return Curve(Kernel::Circle_2(rational(a.center), r * r));
  }
  return Curve(rational(a.source), rational(point_along(p, 0.5)), rational(a.target));
}

/// Distance from q to the piece (to its circle within the arc's angular range).
double distance(const Piece& p, const Vec2& q) {
  if (const auto* s = std::get_if<Segment>(&p)) {
    const Vec2 d = s->b - s->a;
    const double t = std::clamp((q - s->a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (q - (s->a + t * d)).norm();
  }
  const auto& a = std::get<Arc>(p);
  double angle = std::atan2(q.y() - a.center.y(), q.x() - a.center.x()) - a.start;
  angle = a.sweep > 0 ? std::fmod(angle + 4 * pi, 2 * pi) : -std::fmod(-angle + 4 * pi, 2 * pi);
  if (std::abs(angle) <= std::abs(a.sweep)) return std::abs((q - a.center).norm() - a.radius);
  return std::min((q - a.source).norm(), (q - a.target).norm());
}

struct PieceId {
  int loop, index;
};

std::string describe(const Region2& r, const PieceId& id) {
  const Loop& loop = id.loop == 0 ? r.outer : r.holes[id.loop - 1];
  return fmt::format("{} at line {}", kind_of(loop.pieces[id.index]), loop.where[id.index].line);
}

const Loop& loop_of(const Region2& r, int k) { return k == 0 ? r.outer : r.holes[k - 1]; }

void check_pieces(const Region2& r) {
  for (int k = 0; k <= int(r.holes.size()); ++k) {
    const Loop& loop = loop_of(r, k);
    const int n = int(loop.pieces.size());
    for (int i = 0; i < n; ++i) {
      const Piece& p = loop.pieces[i];
      const SourceRef& at = loop.where[i];
      if (length_of(p) == 0) throw InputError(at.file, at.line, "zero-length piece");
      if (target_of(p) != source_of(loop.pieces[(i + 1) % n]))
        throw InputError(at.file, at.line,
                         fmt::format("the loop is not closed: this {} does not end where the piece at line {} begins",
                                     kind_of(p), loop.where[(i + 1) % n].line));
    }
  }
}

/// Pieces meet only at the declared joints of consecutive pieces.
void check_simple(const Region2& r, double size) {
  std::vector<Curve> curves;
  std::vector<PieceId> ids;
  for (int k = 0; k <= int(r.holes.size()); ++k)
    for (int i = 0; i < int(loop_of(r, k).pieces.size()); ++i) {
      curves.push_back(to_cgal(loop_of(r, k).pieces[i]));
      ids.push_back({k, i});
    }
  std::vector<Traits::Point_2> points;
  Traits traits;
  CGAL::compute_intersection_points(curves.begin(), curves.end(), std::back_inserter(points), false, traits);
  const double tol = joint_tolerance * size;
  for (const auto& point : points) {
    const Vec2 q(CGAL::to_double(point.x()), CGAL::to_double(point.y()));
    std::vector<PieceId> at;
    for (const PieceId& id : ids)
      if (distance(loop_of(r, id.loop).pieces[id.index], q) <= tol) at.push_back(id);
    if (at.size() == 2 && at[0].loop == at[1].loop) {
      const Loop& loop = loop_of(r, at[0].loop);
      const int n = int(loop.pieces.size()), i = at[0].index, j = at[1].index;
      const int first = (j == (i + 1) % n) ? i : (i == (j + 1) % n ? j : -1);
      if (first >= 0 && (target_of(loop.pieces[first]) - q).norm() <= tol) continue;  // their joint
    }
    if (at.size() < 2) continue;  // not attributable in double: CGAL's split of one piece
    const SourceRef& where = loop_of(r, at[1].loop).where[at[1].index];
    const char* verb = at[0].loop == at[1].loop ? "cross or touch" : "meet (a hole must lie strictly inside, apart from other walls)";
    throw InputError(where.file, where.line,
                     fmt::format("the {} and the {} {} at ({:.9g}, {:.9g})", describe(r, at[0]), describe(r, at[1]),
                                 verb, q.x(), q.y()));
  }
}

/// Winding number of the loop around p (p not on it): + for counter-clockwise loops.
int winding(const Loop& loop, const Vec2& p) {
  // Sum of the signed angles subtended by each piece, from sampled points: exact enough since
  // p is away from the loop (the loops were shown disjoint).
  double total = 0;
  for (const Piece& piece : loop.pieces) {
    const int n = std::holds_alternative<Segment>(piece) ? 1 : 64;
    for (int i = 0; i < n; ++i) {
      const Vec2 a = point_along(piece, double(i) / n) - p, b = point_along(piece, double(i + 1) / n) - p;
      total += std::atan2(cross(a, b), a.dot(b));
    }
  }
  return int(std::lround(total / (2 * pi)));
}

void check_orientation_and_nesting(const Region2& r) {
  if (!(signed_area(r.outer) > 0))
    throw InputError(r.outer.origin.file, r.outer.origin.line,
                     "the outer boundary runs clockwise: list its pieces counter-clockwise (region on the left)");
  for (std::size_t h = 0; h < r.holes.size(); ++h) {
    const Loop& hole = r.holes[h];
    const SourceRef& at = hole.origin;
    if (!(signed_area(hole) < 0))
      throw InputError(at.file, at.line, "the hole runs counter-clockwise: list its pieces clockwise (region on the left)");
    const Vec2 p = point_along(hole.pieces[0], 0.5);
    if (winding(r.outer, p) != 1) throw InputError(at.file, at.line, "the hole is not inside the outer boundary");
    for (std::size_t g = 0; g < r.holes.size(); ++g)
      if (g != h && winding(r.holes[g], p) != 0)
        throw InputError(at.file, at.line,
                         fmt::format("the hole lies inside the hole at line {}", r.holes[g].origin.line));
  }
}

}  // namespace

void validate(const Region2& region) {
  check_pieces(region);
  const auto m = measures_of(region);
  check_simple(region, (m.bbox_hi - m.bbox_lo).norm());
  check_orientation_and_nesting(region);
}

}  // namespace billiards::geometry
