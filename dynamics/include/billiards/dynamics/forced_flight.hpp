// Flights under a uniform force: the static force F (parabolas) and the paper's periodic drive
// F cos(ω t + phase) (Appendix B), both in closed form between collisions, in any scalar type
// (forced_flight.cpp instantiates double, long double and precision.hpp's Reference).
//
// Exit times are certified: for each wall, f(τ) measures how far beyond the wall the particle
// is (n·(x − a) for a segment; ±(|x − c|² − r²) for an arc), and M bounds |f''| over the next
// step.  From any point the earliest possible zero of f is the positive root of
// |f| − σ f' s − M s²/2 (σ = sign f), so stepping by it can never jump over a root.  Far from
// the wall the steps are long; near a simple root they converge like Newton's iteration from
// the safe side.  M is |n·F|/m for a segment, whatever ω is, so the cost per collision does
// not grow with ω.  A zero where f' ≤ 0 (a touch, or an inward crossing) is not a collision.
#pragma once

#include "billiards/dynamics/certified_scan.hpp"
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/flight.hpp"
#include "billiards/dynamics/phase.hpp"

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <tuple>
#include <type_traits>
#include <utility>

namespace billiards::dynamics {

/// State under a periodic drive: the state plus the drive's phase.
template <class Real, int D = 2>
struct BasicDrivenState : BasicState<Real, D> {
  PhaseOf<Real> phase = 0;
  /// sin and cos of `phase`, from which every exit-time search starts: computed once per
  /// flight instead of once per wall.  Set them with the phase (set_phase).
  Real sin_phase = 0, cos_phase = 1;
  void set_phase(const PhaseOf<Real>& theta) {
    phase = reduce_phase(theta);
    std::tie(sin_phase, cos_phase) = sin_cos(Real(phase));
  }
  /// The same with a sine and cosine already known.
  void set_phase(const PhaseOf<Real>& theta, const std::pair<Real, Real>& sin_cos) {
    phase = reduce_phase(theta);
    std::tie(sin_phase, cos_phase) = sin_cos;
  }
};
using DrivenState = BasicDrivenState<double>;
using DrivenState3 = BasicDrivenState<double, 3>;

/// The exit-time searches of one driven flight (lab or quivering walls) from one state: the
/// guiding line and the bounds that every wall's search starts from are computed once per
/// flight, not once per wall (`collision` asks the flight for it with `scan_from(s)`).  It
/// refers to the flight and the state, which must outlive it.
template <class Flight>
struct DrivenScan {
  using Real = typename Flight::Scalar;
  scan::Quiver<Flight, BasicDrivenState<Real>> quiver;
  Real exit_time(const BasicSegmentWall<Real>& w, const Real& t_end) const;
  Real exit_time(const BasicArcWall<Real>& w, const Real& t_end) const;
  Real exit_time(const BasicEllipticArcWall<Real>& w, const Real& t_end) const;
  /// The first wall of the table the flight leaves through before t_end (the hit's t, wall and
  /// the flight's state there; wall −1 if none).  The walls' windows — the only stretches of the flight in which
  /// they can be hit — are searched in the order in which they open, so a wall whose window
  /// opens after the collision found is never sampled; in a window where the sign of f' is
  /// certain, the root is found by a bracketed Newton iteration instead of the certified scan.
  FlightHit<Flight> first_hit(const BasicTable<Real>& table, const Real& t_end) const;
};

/// Uniform periodic drive F cos(ω t + phase) on a particle of mass m (U = 0), in 2-D or (in
/// double) 3-D: Appendix B holds in any dimension.
template <class Real, int D = 2>
struct BasicPeriodicDriveFlight {
  using Scalar = Real;
  using State = BasicDrivenState<Real, D>;
  static constexpr bool conserves_energy = false;

  VecN<Real, D> accel;  // F / m
  Real omega;           // ω
  Real phase0 = 0;      // the drive's phase at t = 0

  State start(const BasicState<Real, D>& s) const;
  /// Appendix B: v(t) = v_s + (F/mω)[sin θ(t) − sin θ_s],
  /// x(t) = x_s + [v_s − (F/mω) sin θ_s](t − t_s) − (F/mω²)[cos θ(t) − cos θ_s];
  /// sin θ(t) and cos θ(t) from `near` when it is known (a sample of a root search).
  State advance(const State& s, const Real& t, const scan::PhaseSample<Real>& near = {}) const;
  DrivenScan<BasicPeriodicDriveFlight> scan_from(const State& s) const requires(D == 2) { return {{*this, s}}; }
  /// The oscillation segment guide ± F/(mω²) that holds the position at time t of the flight
  /// from s (no sine or cosine: the ensemble's every-flight check looks it up first).
  std::pair<VecN<Real, D>, VecN<Real, D>> sweep(const State& s, const Real& t) const {
    return scan::oscillation_segment(s, scan::guiding_velocity(*this, s), drive_amplitudes(accel, omega).first,
                                     Real(t - s.t));
  }
  Real exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const requires(D == 2) {
    return scan_from(s).exit_time(w, t_end);
  }
  Real exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const requires(D == 2) {
    return scan_from(s).exit_time(w, t_end);
  }
  double exit_time(const State& s, const PlaneWall& w, double t_end) const requires(D == 3);
  /// Through the triangle's plane within its span (widened by its slack, as for straight
  /// flights, so that neighbours overlap at their shared edge and nothing slips between them).
  double exit_time(const State& s, const TriangleWall& w, double t_end) const requires(D == 3);
  double exit_time(const State& s, const SphereWall& w, double t_end) const requires(D == 3);
};
using PeriodicDriveFlight = BasicPeriodicDriveFlight<double>;
using PeriodicDriveFlight3 = BasicPeriodicDriveFlight<double, 3>;

/// The same drive seen from the frame y = x + d(t), d(t) = F cos(ω t + phase)/(mω²), the
/// paper's "quivering walls" (section 6): there ÿ = ẍ − F cos θ/m = 0, so the particle flies
/// in straight lines and the walls translate rigidly by d(t), with velocity
/// ḋ = −F sin θ/(mω).  A collision reverses the normal velocity relative to the wall,
/// v' = v − 2((v − ḋ)·n)n (`bounce` below).  The state's x is the position relative to the
/// walls (= the lab position: the transform is exact, so hits, normals and containment tests
/// use the table as it is); its v is the free particle's velocity ẏ = ẋ + ḋ, which differs
/// from the lab velocity by −F sin θ/(mω).  Its kinetic energy ½m|ẏ|² is this picture's
/// energy; it equals the lab's whenever sin θ = 0.  Exit times use the lab flight's certified
/// scan (the gap between a line and a translating wall is the same function of time).
template <class Real>
struct BasicQuiveringWallFlight {
  using Scalar = Real;
  using State = BasicDrivenState<Real>;
  static constexpr bool conserves_energy = false;

  Vec2T<Real> accel;  // F / m
  Real omega;         // ω
  Real phase0 = 0;    // the drive's phase at t = 0

  /// s: position relative to the walls and free velocity ẏ (at phase0 = 0 and t = 0, ḋ = 0
  /// and ẏ is the lab velocity).
  State start(const BasicState<Real>& s) const { return BasicPeriodicDriveFlight<Real>{accel, omega, phase0}.start(s); }
  /// y(t) = y_s + ẏ (t − t_s); x = y − d(t) (`near` as for the lab flight).
  State advance(const State& s, const Real& t, const scan::PhaseSample<Real>& near = {}) const;
  /// ḋ, the walls' velocity at the state's time.
  Vec2T<Real> wall_velocity(const State& s) const { return -drive_amplitudes(accel, omega).second * s.sin_phase; }
  /// The lab flight's scan, seen from the walls: guiding velocity ẏ, velocity relative to the
  /// walls ẏ − ḋ.
  DrivenScan<BasicQuiveringWallFlight> scan_from(const State& s) const {
    return {{*this, s, s.v, s.v - wall_velocity(s)}};
  }
  /// As for the lab flight (the position relative to the walls lies on it).
  std::pair<Vec2T<Real>, Vec2T<Real>> sweep(const State& s, const Real& t) const {
    return scan::oscillation_segment(s, s.v, drive_amplitudes(accel, omega).first, Real(t - s.t));
  }
  Real exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const {
    return scan_from(s).exit_time(w, t_end);
  }
  Real exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const {
    return scan_from(s).exit_time(w, t_end);
  }
};
using QuiveringWallFlight = BasicQuiveringWallFlight<double>;

/// Reflection off a moving wall: v' = v − 2((v − ḋ)·n)n/(n·n), divided by n·n as the lab's
/// (overloads collision.hpp's bounce; `HitT` as there).
template <class Real, class HitT>
void bounce(const BasicQuiveringWallFlight<Real>& flight, BasicDrivenState<Real>& s, const HitT& hit) {
  s = state_at(flight, s, hit);
  s.x = hit.point;
  s.v = reflect(s.v, hit.normal, Real(2 * (s.v - flight.wall_velocity(s)).dot(hit.normal)));
}

/// A static uniform force F on a particle of mass m: parabolic flights.
template <class Real>
struct BasicConstantForceFlight {
  using Scalar = Real;
  using State = BasicState<Real>;
  static constexpr bool conserves_energy = false;  // kinetic energy changes between collisions

  Vec2T<Real> accel;  // F / m

  State start(const State& s) const { return s; }
  State advance(const State& s, const Real& t) const;
  Real exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const;
  Real exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const;
};
using ConstantForceFlight = BasicConstantForceFlight<double>;

}  // namespace billiards::dynamics
