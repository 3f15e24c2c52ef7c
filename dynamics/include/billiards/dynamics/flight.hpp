// Flight models: how a particle moves between collisions.
//
// A flight model M is a small value type with
//   using Scalar = ...;                     // double, or long double / MPFR for references
//   using State = ...;                      // derives from dynamics::BasicState<Scalar, D>
//   State start(const dynamics::State& s) const;              // a particle's initial state
//   State advance(const State& s, Scalar t) const;            // state at time t ≥ s.t
//   Scalar exit_time(const State& s, const Wall& w, Scalar t_end) const;  // for every wall kind
//   static constexpr bool conserves_energy;
// Closed forms where they exist (straight lines and parabolas through segments and arcs,
// circles through segments and arcs, and the 3-D primitives' own), and for every other wall
// kind a template that scans the wall's gap along the flight (`scanned_exit_time` below: the
// wall's `gap_sample`, the flight's motion and a bound on its acceleration), so that a new
// wall kind works with every flight before any closed form is written for it.
// A flight under a uniform acceleration `accel` (or none) is covariant under affine maps:
// `elliptic_exit_time` below gives its exit times through elliptic arcs from those through
// circular arcs.
// exit_time returns the first time t in [s.t, t_end] at which the trajectory starting from s
// crosses the wall OUTWARD (from the region's side to the wall's side) at a point within the
// wall's span, or +infinity if there is none.  A particle already (numerically) on the wall
// side and moving outward collides at once (t = s.t); one on the wall side moving inward does
// not collide with that wall (DynamO's "stable" rule).  A touch without crossing is not a
// collision.
//
// The collision finder (collision.hpp) is generic over M, so a free scene compiles to the
// straight-line code only: there is no drive in it, not even a branch.
#pragma once

#include "billiards/dynamics/state.hpp"
#include "billiards/dynamics/walls.hpp"
#include "billiards/dynamics/walls3.hpp"

#include <limits>
#include <type_traits>

namespace billiards::dynamics {

/// The exit time through w of the flight from s at(τ) → (x, v) τ after s, with acceleration
/// at most A and within reach(τ) of s.x: the certified scan of the wall's gap
/// (scan::gap_crossing).  The flights' fallback for a wall kind they have no closed form for.
template <class Real, class State, class Wall, class At, class Reach>
Real scanned_exit_time(const State& s, const Wall& w, const Real& t_end, At at, const Real& A, Reach reach) {
  const Real tau = scan::gap_crossing(w, at, A, reach, Real(s.x.template lpNorm<Eigen::Infinity>()), Real(t_end - s.t));
  return tau == never ? Real(never) : Real(s.t + tau);
}

/// The last parameter of a flight's scanning `exit_time` template where the flight's closed
/// forms are instantiated member by member (free_flight.cpp, magnetic_flight.cpp): always
/// defaulted, it keeps the template apart from those explicit instantiations, which would
/// otherwise name either.
struct Scanned {};

/// A 3-D straight flight's exit times from one state: the sheared ray of the watertight
/// triangle test (walls3.hpp) is computed once per flight, not once per triangle (`collision`
/// asks the flight for it with `scan_from(s)`).
struct StraightScan3 {
  const State3& s;
  Ray ray;
  explicit StraightScan3(const State3& st) : s(st), ray(st.x, st.v) {}
  double exit_time(const PlaneWall& w, double t_end) const { return straight_exit_time(s, w, t_end); }
  double exit_time(const TriangleWall& w, double t_end) const { return straight_exit_time(s, ray, w, t_end); }
  double exit_time(const SphereWall& w, double t_end) const { return straight_exit_time(s, w, t_end); }
  /// Through a wall kind with no closed form here: the scan of its gap along the line.
  template <class Wall>
  double exit_time(const Wall& w, double t_end) const {
    const double V = s.v.norm();
    return scanned_exit_time(s, w, t_end, [this](double tau) { return std::pair{Vec3(s.x + s.v * tau), s.v}; }, 0.0,
                             [V](double tau) { return V * tau; });
  }
};

/// Straight flight at constant velocity (no force), in any scalar type (free_flight.cpp
/// instantiates double, long double and precision.hpp's Reference) and dimension (3-D: double).
template <class Real, int D = 2>
struct BasicFreeFlight {
  using Scalar = Real;
  using State = BasicState<Real, D>;
  static constexpr bool conserves_energy = true;

  State start(const State& s) const { return s; }
  State advance(const State& s, const Real& t) const {
    State r = s;
    r.x = s.x + s.v * (t - s.t);
    r.t = t;
    return r;
  }
  /// The closed forms (free_flight.hpp, always inlined: the hot loop of free ensembles).
  [[gnu::always_inline]] Real exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const requires(D == 2);
  [[gnu::always_inline]] Real exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const requires(D == 2);
  [[gnu::always_inline]] Real exit_time(const State& s, const BasicEllipticArcWall<Real>& w, const Real& t_end) const
    requires(D == 2);
  /// Through a wall kind with no closed form here: the scan of its gap along the line.
  template <class Wall>
  Real exit_time(const State& s, const Wall& w, const Real& t_end, Scanned = {}) const requires(D == 2) {
    const Real V = s.v.norm();
    return scanned_exit_time(s, w, t_end, [&](const Real& tau) { return std::pair{Vec2T<Real>(s.x + s.v * tau), s.v}; },
                             Real(0), [V](const Real& tau) { return Real(V * tau); });
  }
  StraightScan3 scan_from(const State& s) const requires(D == 3) { return StraightScan3(s); }
  template <class Wall>
  double exit_time(const State& s, const Wall& w, double t_end) const requires(D == 3) {
    return scan_from(s).exit_time(w, t_end);
  }
};
using FreeFlight = BasicFreeFlight<double>;
using FreeFlight3 = BasicFreeFlight<double, 3>;

/// Is the flight model's law covariant under affine maps x ↦ L (x − c)?  Straight flights are,
/// and so are flights under a uniform acceleration (`accel`, mapped to L accel); a flight in a
/// position-dependent field is not, nor one in a magnetic field (`omega_c`), with or without an
/// `accel`: L maps its circles to ellipses.
template <class Flight>
concept affine_covariant = std::is_base_of_v<BasicFreeFlight<typename Flight::Scalar, Flight::State::dimension>, Flight> ||
                           (requires(Flight f) { f.accel = f.accel; } && !requires(Flight f) { f.omega_c; });

/// The flight seen through the wall's map u = L (x − c) (time is not mapped).
template <affine_covariant Flight, class Wall>
Flight mapped(Flight flight, const Wall& w) {
  if constexpr (requires { flight.accel; }) flight.accel = w.map * flight.accel;
  return flight;
}
template <class State, class Wall>
State mapped_state(State s, const Wall& w) {
  s.x = w.to_unit(s.x);
  s.v = w.map * s.v;
  return s;
}

/// The exit time of an affine-covariant flight through an elliptic arc: the mapped flight's
/// through the arc's unit arc (walls.hpp).
template <affine_covariant Flight>
typename Flight::Scalar elliptic_exit_time(const Flight& flight, const typename Flight::State& s,
                                           const BasicEllipticArcWall<typename Flight::Scalar>& w,
                                           const typename Flight::Scalar& t_end) {
  return mapped(flight, w).exit_time(mapped_state(s, w), w.unit, t_end);
}

/// Does the flight model move in straight lines?  (Their search costs the same with or without
/// a horizon.)
template <class Flight>
inline constexpr bool is_straight =
    std::is_same_v<Flight, BasicFreeFlight<typename Flight::Scalar, Flight::State::dimension>>;

}  // namespace billiards::dynamics
