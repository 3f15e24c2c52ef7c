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

#include "billiards/dynamics/flight.hpp"

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <type_traits>

namespace billiards::dynamics {

/// The drive's phase θ = ω t + phase is kept reduced to [0, 2π) in a type wider than double:
/// long double for the hardware types, the reference type itself for MPFR.  A plain double
/// ω t at ω = 2560π, t = 1e4 would keep only 8 digits.
template <class Real>
using PhaseOf = std::conditional_t<std::is_floating_point_v<Real>, long double, Real>;

/// θ reduced to [0, 2π).
template <class P>
P reduce_phase(P theta) {
  using std::fmod;
  const P two_pi = boost::math::constants::two_pi<P>();
  theta = fmod(theta, two_pi);
  return theta < 0 ? P(theta + two_pi) : theta;
}

/// θ + ω τ (for set_phase to reduce), to the rounding of the phase type even when ωτ is 10¹⁰
/// (a flight of 10⁸ periods, as a particle nearly at rest can make): ωτ in the phase type
/// would keep only ~1e-10 rad there.  Beyond 2²⁰ rad, in hardware types, ωτ is split into its
/// rounding p and the exact remainder (fma), and only p is reduced (exactly, by fmod); the
/// representation error of 2π then shifts the phase by the same small multiple for every τ in
/// a period, a slightly different ω rather than noise.
template <class P, class Real>
P advance_phase(const P& theta, const Real& omega, const Real& tau) {
  if constexpr (std::is_floating_point_v<Real>) {
    using std::fma;
    const Real p = omega * tau;
    if (p < 0x1p20) return theta + P(omega) * P(tau);  // (to 1e-13 rad, as always)
    return theta + reduce_phase(P(p)) + P(fma(omega, tau, -p));
  } else {
    return theta + P(omega) * P(tau);
  }
}

/// State under a periodic drive: the state plus the drive's phase.
template <class Real>
struct BasicDrivenState : BasicState<Real> {
  PhaseOf<Real> phase = 0;
  /// sin and cos of `phase`, from which every exit-time search starts: computed once per
  /// flight instead of once per wall.  Set them with the phase (set_phase).
  Real sin_phase = 0, cos_phase = 1;
  void set_phase(const PhaseOf<Real>& theta) {
    using std::cos;
    using std::sin;
    phase = reduce_phase(theta);
    sin_phase = sin(Real(phase));
    cos_phase = cos(Real(phase));
  }
};
using DrivenState = BasicDrivenState<double>;

/// Uniform periodic drive F cos(ω t + phase) on a particle of mass m (U = 0).
template <class Real>
struct BasicPeriodicDriveFlight {
  using Scalar = Real;
  using State = BasicDrivenState<Real>;
  static constexpr bool conserves_energy = false;

  Vec2T<Real> accel;  // F / m
  Real omega;         // ω
  Real phase0 = 0;    // the drive's phase at t = 0

  State start(const BasicState<Real>& s) const;
  /// Appendix B: v(t) = v_s + (F/mω)[sin θ(t) − sin θ_s],
  /// x(t) = x_s + [v_s − (F/mω) sin θ_s](t − t_s) − (F/mω²)[cos θ(t) − cos θ_s].
  State advance(const State& s, const Real& t) const;
  Real exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const;
  Real exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const;
};
using PeriodicDriveFlight = BasicPeriodicDriveFlight<double>;

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
  /// y(t) = y_s + ẏ (t − t_s); x = y − d(t).
  State advance(const State& s, const Real& t) const;
  /// ḋ, the walls' velocity at the state's time.
  Vec2T<Real> wall_velocity(const State& s) const { return -accel / omega * s.sin_phase; }
  Real exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const;
  Real exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const;
};
using QuiveringWallFlight = BasicQuiveringWallFlight<double>;

/// Reflection off a moving wall: v' = v − 2((v − ḋ)·n)n (overloads collision.hpp's bounce).
template <class Real>
void bounce(const BasicQuiveringWallFlight<Real>& flight, BasicDrivenState<Real>& s, const BasicHit<Real>& hit) {
  s = flight.advance(s, hit.t);
  s.x = hit.point;
  s.v -= 2 * (s.v - flight.wall_velocity(s)).dot(hit.normal) * hit.normal;
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
