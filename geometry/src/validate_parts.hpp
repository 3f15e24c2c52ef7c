// Internal to validation (validate.cpp, validate_cgal.cpp, validate_conic_cgal.cpp): naming
// pieces in messages, and the exact arrangement checks, one per CGAL traits class.
#pragma once

#include "billiards/geometry/pieces.hpp"

#include <string>

namespace billiards::geometry::validation {

struct PieceId {
  int loop = 0, index = 0;  // loop 0 is the outer boundary, loop k is holes[k - 1]
};

inline const Loop& loop_of(const Region2& r, int k) { return k == 0 ? r.outer : r.holes[k - 1]; }
inline int loop_count(const Region2& r) { return 1 + int(r.holes.size()); }
inline const Piece& piece_of(const Region2& r, PieceId id) { return loop_of(r, id.loop).pieces[id.index]; }
inline const SourceRef& where_of(const Region2& r, PieceId id) { return loop_of(r, id.loop).where[id.index]; }

/// "segment", "arc", "elliptic arc", "circle" or "ellipse".
std::string noun_of(const Piece& p);
/// "(0.5, 1.25)".
std::string text(const Vec2& q);
[[noreturn]] void fail(const SourceRef& at, const std::string& message);
/// "the segment at line 3 and the arc at line 5 <how>", worded for one loop, a hole against
/// the outer boundary, or two holes; reported at the line of the later piece.
[[noreturn]] void fail_meeting(const Region2& r, PieceId a, PieceId b, const std::string& how);
/// Whether q is (within tol) a joint at which pieces a and b follow each other.
bool is_joint(const Region2& r, PieceId a, PieceId b, const Vec2& q, double tol);

/// Outer loop counter-clockwise, holes clockwise (the loops must be simple).
void check_orientation(const Region2& r);

/// Simple and disjoint loops, holes inside the outer loop and not nested, decided exactly on
/// one CGAL arrangement of every piece: with the circle–segment traits (segments and circular
/// arcs) or with the conic traits (any piece; CORE algebraic numbers, slower).  Between the
/// two, check_orientation.
void check_arrangement_circle_segment(const Region2& r, double tol);
void check_arrangement_conic(const Region2& r, double tol);

}  // namespace billiards::geometry::validation
