// A particle's state and the record of one collision.
#pragma once

#include "billiards/geometry/pieces.hpp"

namespace billiards::dynamics {

using geometry::Vec2;

/// Position, velocity and time of one particle.  Flights that need more (the drive's phase)
/// carry it in their own state type derived from this one.
struct State {
  Vec2 x = Vec2::Zero();
  Vec2 v = Vec2::Zero();
  double t = 0;
};

/// Where and when a flight leaves the region through a wall.
struct Hit {
  double t = 0;                     // absolute time of the collision
  int wall = -1;                    // index into Table::walls()
  Vec2 point = Vec2::Zero();        // collision point (on the wall, to rounding)
  Vec2 normal = Vec2::Zero();       // outward unit normal of the region at `point`
  bool found() const { return wall >= 0; }
};

}  // namespace billiards::dynamics
