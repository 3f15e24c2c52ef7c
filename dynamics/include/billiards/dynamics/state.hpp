// A particle's state and the record of one collision, in any scalar type: double for
// ensembles, long double or MPFR (precision.hpp) for reference trajectories.
#pragma once

#include "billiards/geometry/pieces.hpp"

namespace billiards::dynamics {

using geometry::Vec2;
using geometry::Vec2T;

/// Position, velocity and time of one particle.  Flights that need more (the drive's phase)
/// carry it in their own state type derived from this one.
template <class Real>
struct BasicState {
  Vec2T<Real> x = Vec2T<Real>::Zero();
  Vec2T<Real> v = Vec2T<Real>::Zero();
  Real t = 0;
};
using State = BasicState<double>;

/// A wall of a table: its kind (the position of its type in the table's list of wall kinds)
/// and its index among the walls of that kind.
struct WallId {
  int kind = -1, index = -1;
  bool valid() const { return kind >= 0; }
  friend bool operator==(const WallId&, const WallId&) = default;
  template <class Stream>
  friend Stream& operator<<(Stream& out, const WallId& w) {
    out << w.kind << ':' << w.index;
    return out;
  }
};

/// Where and when a flight leaves the region through a wall.
template <class Real>
struct BasicHit {
  Real t = 0;                                   // absolute time of the collision
  WallId wall;                                  // the wall (invalid: none met)
  Vec2T<Real> point = Vec2T<Real>::Zero();      // collision point (on the wall, to rounding)
  Vec2T<Real> normal = Vec2T<Real>::Zero();     // outward unit normal of the region at `point`
  bool found() const { return wall.valid(); }
};
using Hit = BasicHit<double>;

}  // namespace billiards::dynamics
