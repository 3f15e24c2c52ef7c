// A particle's state and the record of one collision, in any scalar type (double for
// ensembles, long double or MPFR (precision.hpp) for reference trajectories) and dimension
// (2 by default; 3 for 3-D tables).
#pragma once

#include "billiards/geometry/pieces.hpp"

#include <limits>

namespace billiards::dynamics {

using geometry::Vec2;
using geometry::Vec2T;
/// A vector of D coordinates in the scalar type Real.
template <class Real, int D>
using VecN = Eigen::Matrix<Real, D, 1>;

/// "No collision": the exit time of a flight that never leaves through a wall.
inline constexpr double never = std::numeric_limits<double>::infinity();

/// Position, velocity and time of one particle.  Flights that need more (the drive's phase)
/// carry it in their own state type derived from this one.
template <class Real, int D = 2>
struct BasicState {
  static constexpr int dimension = D;
  VecN<Real, D> x = VecN<Real, D>::Zero();
  VecN<Real, D> v = VecN<Real, D>::Zero();
  Real t = 0;
};
using State = BasicState<double>;
using State3 = BasicState<double, 3>;

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

/// A table of dimension D (table.hpp, table3.hpp).
template <class Real, int D = 2>
class BasicTable;

/// Where and when a flight leaves the region through a wall.
template <class Real, int D = 2>
struct BasicHit {
  Real t = 0;                                   // absolute time of the collision
  WallId wall;                                  // the wall (invalid: none met)
  VecN<Real, D> point = VecN<Real, D>::Zero();  // collision point (on the wall, to rounding)
  VecN<Real, D> normal = VecN<Real, D>::Zero(); // outward unit normal of the region at `point`
  bool found() const { return wall.valid(); }
};
using Hit = BasicHit<double>;
using Hit3 = BasicHit<double, 3>;

}  // namespace billiards::dynamics
