// Boundary pieces of a 2-D billiard: line segments, circular arcs and elliptic arcs.
//
// Convention (as in CGAL's general polygons): every loop is traversed with the region on its
// LEFT.  The outer boundary therefore runs counter-clockwise and holes run clockwise.  The
// outward normal of the region (pointing out of the billiard, into the wall) is the RIGHT
// normal of the direction of travel.
#pragma once

#include "billiards/geometry/elliptic_arc.hpp"

#include <Eigen/Core>

#include <string>
#include <variant>
#include <vector>

namespace billiards::geometry {

template <class T>
using Vec2T = Eigen::Matrix<T, 2, 1>;
using Vec2 = Vec2T<double>;

inline constexpr double pi = 3.14159265358979323846;

/// z-component of the 2-D cross product.
template <class T>
inline T cross(const Vec2T<T>& a, const Vec2T<T>& b) { return a.x() * b.y() - a.y() * b.x(); }

/// std::visit over a Piece with one lambda per kind.
template <class... F>
struct overloaded : F... { using F::operator()...; };
template <class... F>
overloaded(F...) -> overloaded<F...>;

/// Where something was written in a shape file, for error messages.
struct SourceRef {
  std::string file;
  int line = 0;  // 1-based; 0 when unknown (e.g. built in code)
  std::string describe() const;  // "clover.yaml:12" or "<built in code>"
};

/// Straight wall from `a` to `b`, region on the left.
struct Segment {
  Vec2 a, b;
};

/// Circular arc from `source` to `target` (both on the circle), starting at polar angle
/// `start` around `center` and sweeping `sweep` radians.  sweep > 0 runs counter-clockwise,
/// so the region (on the left) lies INSIDE the circle: a focusing wall.  sweep < 0 runs
/// clockwise with the region OUTSIDE the circle: a dispersing wall (a scatterer).
/// A full circle has |sweep| = 2π and source == target.
struct Arc {
  Vec2 center;
  double radius = 0;
  double start = 0;
  double sweep = 0;
  Vec2 source, target;

  bool focusing() const { return sweep > 0; }
  /// Signed curvature seen from the region: +1/r focusing, -1/r dispersing.
  double curvature() const { return (sweep > 0 ? 1.0 : -1.0) / radius; }
  Vec2 point_at(double angle) const;
};

/// See elliptic_arc.hpp.
using Piece = std::variant<Segment, Arc, EllipticArc>;

Vec2 source_of(const Piece& p);
Vec2 target_of(const Piece& p);
double length_of(const Piece& p);
/// Signed curvature seen from the region at a point on the piece: 0 on segments, ±1/r on
/// arcs (Arc::curvature), ±ab/(a² sin²φ + b² cos²φ)^{3/2} on elliptic arcs; > 0 focusing.
double curvature_at(const Piece& p, const Vec2& on_piece);
/// Outward unit normal of the region at a point on the piece (projected onto its curve).
Vec2 outward_normal(const Piece& p, const Vec2& on_piece);
/// Point at arc-length fraction u ∈ [0, 1] along the piece.
Vec2 point_along(const Piece& p, double u);
const char* kind_of(const Piece& p);  // "segment", "arc" or "elliptic_arc"
/// A full circle or a full ellipse (a loop by itself).
bool is_closed_curve(const Piece& p);

/// A closed curve: pieces[i].target == pieces[i+1].source (cyclically), region on the left.
struct Loop {
  std::vector<Piece> pieces;
  std::vector<SourceRef> where;  // where each piece was written (same size as pieces)
  SourceRef origin;              // where the loop was written
};

/// The loop as a closed polyline for drawing: each piece gives its vertices up to, not
/// including, its target (the next piece's source); arcs get one every `arc_step` radians (at
/// least 4), elliptic arcs one every `arc_step` of eccentric anomaly (denser where the ellipse
/// bends most).
std::vector<Vec2> outline_of(const Loop& loop, double arc_step);

/// A 2-D billiard table: a bounded region = inside `outer` and outside every hole.
struct Region2 {
  std::string name;
  SourceRef origin;  // the shape file
  Loop outer;
  std::vector<Loop> holes;

  /// All loops, outer first.
  std::vector<const Loop*> loops() const;
  std::size_t piece_count() const;
};

}  // namespace billiards::geometry
