// Exit times of a straight flight (flight.hpp's BasicFreeFlight), in the header so that the
// searches of the 2-D tables inline them (collision.hpp; 10% fewer instructions per collision
// than a call, measured with callgrind in the clover).  Both are closed forms; the only
// delicate quantity is the sign of the circle discriminant at grazing incidence, which in
// double is decided by a filtered predicate (double with a forward error bound, exact
// rationals when the bound cannot decide), and in the reference types by their own precision.
#pragma once

#include "billiards/dynamics/flight.hpp"
#include "billiards/dynamics/straight_exit.hpp"

#include <cmath>
#include <type_traits>

namespace billiards::dynamics {

/// A straight flight's start and its walls as straight_exit.hpp's searches take them: the
/// numbers read in place.
template <class Real>
RayLanes<const Real&> ray_lanes(const BasicState<Real, 2>& s) {
  return {s.x.x(), s.x.y(), s.v.x(), s.v.y(), s.t, s.v.squaredNorm()};
}
template <class Real, int Dim>
inline Real BasicFreeFlight<Real, Dim>::exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const
  requires(Dim == 2) {
  ScalarLanes<Real> scalar;
  return straight_exit_time(scalar, ray_lanes(s), segment_lanes(w), t_end);
}

template <class Real, int Dim>
inline Real BasicFreeFlight<Real, Dim>::exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const
  requires(Dim == 2) {
  ScalarLanes<Real> scalar;
  return straight_exit_time(scalar, ray_lanes(s), arc_lanes(w), t_end);
}

/// Through an elliptic arc: the mapped flight's exit through the arc's unit arc.
template <class Real, int Dim>
inline Real BasicFreeFlight<Real, Dim>::exit_time(const State& s, const BasicEllipticArcWall<Real>& w,
                                                  const Real& t_end) const requires(Dim == 2) {
  ScalarLanes<Real> scalar;
  return straight_exit_time(scalar, mapped_ray<ScalarLanes<Real>>(ray_lanes(s), ellipse_map_lanes(w)), arc_lanes(w.unit),
                            t_end);
}

}  // namespace billiards::dynamics
