// Walls prepared for fast collision queries: each boundary piece with the quantities the
// hot loop needs precomputed, and the span tests shared by every flight model.
//
// Span tests are CLOSED and slightly EXTENDED (by `slack`, a few hundred ulps of the
// coordinates): a crossing computed just past the end of a piece is still accepted, so a
// trajectory through a joint is caught by at least one of the two pieces meeting there and
// can never slip between them.  Consecutive pieces share their joint point bit for bit.
#pragma once

#include "billiards/geometry/pieces.hpp"

#include <cmath>
#include <limits>

namespace billiards::dynamics {

using geometry::Vec2;
using geometry::cross;

/// Relative slack of span tests, in units of the coordinate scale.
inline constexpr double span_slack_ulps = 256 * std::numeric_limits<double>::epsilon();

struct SegmentWall {
  Vec2 a, b;
  Vec2 normal;   // outward unit normal (right of a→b)
  Vec2 dir;      // (b - a) / |b - a|²
  double slack;  // absolute tolerance along the segment

  explicit SegmentWall(const geometry::Segment& s);
  /// Is p (on the supporting line, to rounding) within the segment, ends included?
  bool within_span(const Vec2& p) const {
    const double s = (p - a).dot(dir);
    const double tol = slack * dir.norm();
    return s >= -tol && s <= 1 + tol;
  }
};

struct ArcWall {
  Vec2 center;
  double radius, radius2;
  Vec2 from, to;        // endpoints relative to the centre, in counter-clockwise order
  double ccw_extent;    // counter-clockwise angle from `from` to `to`, in (0, 2π]
  bool focusing;        // region inside the circle (sweep > 0)
  bool full;            // a whole circle
  double slack;         // absolute tolerance (distance units)

  explicit ArcWall(const geometry::Arc& a);
  /// Is p (on the circle, to rounding) within the arc, ends included?
  bool within_span(const Vec2& p) const {
    if (full) return true;
    const Vec2 u = p - center;
    const double tol = slack * radius;
    if (ccw_extent <= geometry::pi) return cross(from, u) >= -tol && cross(u, to) >= -tol;
    // More than a half circle: inside unless strictly within the complementary arc (< π).
    return !(cross(to, u) > tol && cross(u, from) > tol);
  }
  /// Outward unit normal of the region at p.
  Vec2 normal_at(const Vec2& p) const {
    const Vec2 u = (p - center) / radius;
    return focusing ? Vec2(u) : Vec2(-u);
  }
};

}  // namespace billiards::dynamics
