// Validation of a 2-D region: the checks that need no exact arithmetic (finite, consistent,
// closed loops; orientation; naming pieces in messages).  The exact checks run on a CGAL
// arrangement: validate_cgal.cpp (segments and circular arcs) or validate_conic_cgal.cpp (when
// a table has elliptic arcs).
#include "billiards/geometry/validate.hpp"

#include "billiards/geometry/input_error.hpp"
#include "billiards/geometry/measures.hpp"
#include "validate_parts.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <tuple>

namespace billiards::geometry {

namespace validation {

std::string noun_of(const Piece& p) {
  if (is_closed_curve(p)) return std::holds_alternative<Arc>(p) ? "circle" : "ellipse";
  return std::holds_alternative<EllipticArc>(p) ? "elliptic arc" : kind_of(p);
}

std::string text(const Vec2& q) { return fmt::format("({:.9g}, {:.9g})", q.x(), q.y()); }

void fail(const SourceRef& at, const std::string& message) { throw InputError(at.file, at.line, message); }

/// "segment at line 12", "circle at line 20".
static std::string name_of(const Region2& r, PieceId id) {
  return fmt::format("{} at line {}", noun_of(piece_of(r, id)), where_of(r, id).line);
}

void fail_meeting(const Region2& r, PieceId a, PieceId b, const std::string& how) {
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

bool is_joint(const Region2& r, PieceId a, PieceId b, const Vec2& q, double tol) {
  if (a.loop != b.loop) return false;
  const Loop& loop = loop_of(r, a.loop);
  const int n = int(loop.pieces.size());
  const auto ends_at_q_before = [&](int i, int j) {
    return (i + 1) % n == j && (target_of(loop.pieces[i]) - q).norm() <= tol;
  };
  return ends_at_q_before(a.index, b.index) || ends_at_q_before(b.index, a.index);
}

constexpr const char* outer_runs_clockwise =
    "the outer boundary runs clockwise: list its pieces counter-clockwise (region on the left)";

void check_orientation(const Region2& r) {
  if (!(signed_area(r.outer) > 0))
    fail(r.outer.origin, outer_runs_clockwise);
  for (const Loop& hole : r.holes)
    if (!(signed_area(hole) < 0))
      fail(hole.origin, "the hole runs counter-clockwise: list its pieces clockwise (region on the left)");
}

}  // namespace validation

namespace {

using namespace validation;

/// Distance to a joint, relative to the table's diameter, within which a common point of the
/// two pieces meeting there is that joint (rounding displaces it by at most ~1e-15).
constexpr double joint_tolerance = 1e-9;

// ---------------------------------------------------------------- (1) pieces and closure

bool shape_finite(const Arc& a) { return std::isfinite(a.radius); }
bool shape_finite(const EllipticArc& e) { return e.semi_axes.allFinite() && std::isfinite(e.angle); }

bool finite(const Piece& p) {
  return std::visit(overloaded{[](const Segment& s) { return s.a.allFinite() && s.b.allFinite(); },
                               [](const auto& arc) {
                                 return shape_finite(arc) && arc.center.allFinite() && arc.source.allFinite() &&
                                        arc.target.allFinite() && std::isfinite(arc.start) && std::isfinite(arc.sweep);
                               }},
                    p);
}

/// "segment", "arc" or "elliptic arc".
std::string kind_name(const Piece& p) { return std::holds_alternative<EllipticArc>(p) ? "elliptic arc" : kind_of(p); }

void check_piece(const Piece& p, const SourceRef& at) {
  const std::string kind = kind_name(p);
  if (!finite(p)) fail(at, fmt::format("the {} has a coordinate that is not a finite number", kind));
  const auto* a = std::get_if<Arc>(&p);
  const auto* e = std::get_if<EllipticArc>(&p);
  if (a && !(a->radius > 0)) fail(at, "the arc's radius must be positive");
  if (e && !(e->semi_axes.minCoeff() > 0)) fail(at, "the elliptic arc's semi-axes must be positive");
  if (!(length_of(p) > 0)) fail(at, fmt::format("zero-length {}: it must have a positive length", kind));
  if (std::holds_alternative<Segment>(p)) return;
  const double sweep = a ? a->sweep : e->sweep;
  if (std::abs(sweep) > 2 * pi) fail(at, fmt::format("the {} sweeps more than a full turn", kind));
  if (source_of(p) == target_of(p) && !is_closed_curve(p))
    fail(at, fmt::format("the {} starts and ends at the same point: a full {} needs a sweep of ±2π", kind,
                         a ? "circle" : "ellipse"));
}

void check_loop(const Loop& loop, const char* what) {
  const int n = int(loop.pieces.size());
  if (loop.where.size() != loop.pieces.size())
    throw std::invalid_argument("validate: every piece of a loop needs its SourceRef in loop.where");
  if (n == 0) fail(loop.origin, fmt::format("the {} has no pieces", what));
  for (int i = 0; i < n; ++i) check_piece(loop.pieces[i], loop.where[i]);
  for (int i = 0; i < n; ++i) {
    const Piece &p = loop.pieces[i], &next = loop.pieces[(i + 1) % n];
    if (is_closed_curve(p) && n > 1) fail(loop.where[i], fmt::format("a full {} must be a loop by itself", noun_of(p)));
    if (target_of(p) != source_of(next))
      fail(loop.where[i], fmt::format("the loop is not closed: this {} ends at {} but the {} at line {} begins at {}",
                                      kind_name(p), text(target_of(p)), kind_name(next), loop.where[(i + 1) % n].line,
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
/// axes and angles: they must agree.
void check_arc_ends(const Region2& r, double tol) {
  const auto ends_agree = [tol](const auto& arc) {
    return (arc.point_at(arc.start) - arc.source).norm() <= tol &&
           (arc.point_at(arc.start + arc.sweep) - arc.target).norm() <= tol;
  };
  for (const Loop* loop : r.loops())
    for (std::size_t i = 0; i < loop->pieces.size(); ++i) {
      const Piece& p = loop->pieces[i];
      const bool ok = std::visit(overloaded{[](const Segment&) { return true; }, ends_agree}, p);
      if (!ok)
        fail(loop->where[i], std::holds_alternative<Arc>(p)
                                 ? "the arc's ends are not the points of its circle at its start and end angles"
                                 : "the elliptic arc's ends are not the points of its ellipse at its start and end "
                                   "anomalies");
    }
}

bool has_elliptic_arc(const Region2& r) {
  for (const Loop* loop : r.loops())
    for (const Piece& p : loop->pieces)
      if (std::holds_alternative<EllipticArc>(p)) return true;
  return false;
}

}  // namespace

void validate(const Region2& region) {
  for (int k = 0; k < loop_count(region); ++k) check_loop(loop_of(region, k), k == 0 ? "outer boundary" : "hole");
  const double tol = joint_tolerance * diameter(region);
  check_arc_ends(region, tol);
  try {
    if (has_elliptic_arc(region))
      check_arrangement_conic(region, tol);
    else
      check_arrangement_circle_segment(region, tol);
  } catch (const InputError& e) {
    // Pieces listed clockwise make arcs bulge the wrong way and cross: say so (a figure-eight,
    // of zero area, is only crossed).
    if (signed_area(region.outer) < 0 && e.message().find("clockwise") == std::string::npos)
      throw InputError(e.file(), e.line(), e.message() + "; " + validation::outer_runs_clockwise);
    throw;
  }
}

}  // namespace billiards::geometry
