// A particle's state and the record of one collision, in any scalar type (double for
// ensembles, long double or MPFR (precision.hpp) for reference trajectories) and dimension
// (2 by default; 3 for 3-D tables).
#pragma once

#include "billiards/dynamics/error_free.hpp"
#include "billiards/geometry/pieces.hpp"

#include <limits>
#include <tuple>
#include <utility>

namespace billiards::dynamics {

using geometry::Vec2;
using geometry::Vec2T;
/// A vector of D coordinates in the scalar type Real.
template <class Real, int D>
using VecN = Eigen::Matrix<Real, D, 1>;

/// "No collision": the exit time of a flight that never leaves through a wall.
inline constexpr double never = std::numeric_limits<double>::infinity();

/// The absolute time of a run, to which each flight's own time is added when it ends.  A flight
/// is computed on its own clock (its state's t starts at 0), so its hit time, position and
/// velocity are resolved to the flight's rounding, not to ulp(t): in one double at t ≈ 1e5 a
/// position would be quantized to 1e-11 of a unit of speed.  In double the clock is the
/// unevaluated sum hi + lo of two doubles (106 bits), so the absolute time of any event is
/// exact to the rounding of the flight times themselves, and no rounding accumulates over
/// 10⁹ flights; in other scalar types (long double, MPFR references) a plain sum.
template <class Real>
struct BasicClock {
  Real t = 0;
  BasicClock() = default;
  explicit BasicClock(const Real& start) : t(start) {}
  void add(const Real& dt) { t += dt; }
  /// The absolute time τ after the clock's time, and the time from it to the absolute time T.
  Real after(const Real& tau) const { return t + tau; }
  Real until(const Real& T) const { return T - t; }
};
template <>
struct BasicClock<double> {
  double hi = 0, lo = 0;
  BasicClock() = default;
  explicit BasicClock(double start) : hi(start) {}
  /// Adds a flight's time, exactly to the 106 bits of hi + lo.
  void add(double dt) {
    const auto sum = detail::clock_after_flight(detail::Unevaluated<double>{hi, lo}, dt);
    hi = sum.hi, lo = sum.lo;
  }
  /// hi + lo + τ and T − (hi + lo), each rounded once (to within an ulp); `never` stays never.
  double after(double tau) const {
    const auto [s, e] = detail::two_sum(hi, tau);
    return tau == never ? never : s + (e + lo);
  }
  double until(double T) const {
    return T == never ? never : detail::clock_until<detail::Doubles>(detail::Unevaluated<double>{hi, lo}, T);
  }
};
using Clock = BasicClock<double>;

/// Position, velocity and time of one particle.  Flights that need more (the drive's phase)
/// carry it in their own state type derived from this one.
template <class Real, int D = 2>
struct BasicState {
  static constexpr int dimension = D;
  VecN<Real, D> x = VecN<Real, D>::Zero();
  VecN<Real, D> v = VecN<Real, D>::Zero();
  Real t = 0;  // in a run, the time on the flight's own clock (0 at its start: BasicClock)
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
