// The exit time of a straight 3-D flight through a plane or a sphere in double:
// straight_exit3-inl.hpp's algorithms with the traits of one number, and the flight and the
// walls as they read them (walls3.cpp's scalar search, free_lockstep.cpp's kernel walls).
#pragma once

#include "billiards/dynamics/scalar_lanes.hpp"
#include "billiards/dynamics/walls3.hpp"

namespace billiards::dynamics {

#include "billiards/dynamics/straight_exit3-inl.hpp"

/// The flight's start and the walls, the numbers read in place (a sphere's `near` computed).
inline Ray3Lanes<const double&> ray3_lanes(const State3& s) {
  return {s.x.x(), s.x.y(), s.x.z(), s.v.x(), s.v.y(), s.v.z(), s.t, s.v.squaredNorm()};
}
inline PlaneLanes<const double&> plane_lanes(const PlaneWall& w) {
  return {w.normal.x(), w.normal.y(), w.normal.z(), w.offset, w.slack};
}
inline SphereLanes<double, bool> sphere_lanes(const SphereWall& w) {
  return {w.center.x(), w.center.y(), w.center.z(), w.radius, w.radius2, 2 * w.radius * w.slack, w.focusing};
}

}  // namespace billiards::dynamics
