// Flights under a uniform force: the static force F (parabolas) and the paper's periodic drive
// F cos(ω t + phase) (Appendix B), both in closed form between collisions.
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

#include <cmath>

namespace billiards::dynamics {

/// State under a periodic drive: the drive's phase θ = ω t + phase, kept reduced to [0, 2π) in
/// extended precision.  A plain double ω t at ω = 2560π, t = 1e4 would keep only 8 digits.
struct DrivenState : State {
  long double phase = 0;
  /// sin and cos of `phase`, from which every exit-time search starts: computed once per
  /// flight instead of once per wall.  Set them with the phase (set_phase).
  double sin_phase = 0, cos_phase = 1;
  void set_phase(long double theta);
};

/// Uniform periodic drive F cos(ω t + phase) on a particle of mass m (U = 0).
struct PeriodicDriveFlight {
  using Scalar = double;
  using State = DrivenState;
  static constexpr bool conserves_energy = false;

  Vec2 accel;           // F / m
  double omega;         // ω
  double phase0 = 0;    // the drive's phase at t = 0

  State start(const dynamics::State& s) const;
  /// Appendix B: v(t) = v_s + (F/mω)[sin θ(t) − sin θ_s],
  /// x(t) = x_s + [v_s − (F/mω) sin θ_s](t − t_s) − (F/mω²)[cos θ(t) − cos θ_s].
  State advance(const State& s, double t) const;
  double exit_time(const State& s, const SegmentWall& w, double t_end) const;
  double exit_time(const State& s, const ArcWall& w, double t_end) const;
};

/// A static uniform force F on a particle of mass m: parabolic flights.
struct ConstantForceFlight {
  using Scalar = double;
  using State = dynamics::State;
  static constexpr bool conserves_energy = false;  // kinetic energy changes between collisions

  Vec2 accel;  // F / m

  State start(const State& s) const { return s; }
  State advance(const State& s, double t) const;
  double exit_time(const State& s, const SegmentWall& w, double t_end) const;
  double exit_time(const State& s, const ArcWall& w, double t_end) const;
};

/// θ reduced to [0, 2π), in extended precision.
inline long double reduce_phase(long double theta) {
  constexpr long double two_pi = 6.283185307179586476925286766559005768L;
  theta = std::fmod(theta, two_pi);
  return theta < 0 ? theta + two_pi : theta;
}

}  // namespace billiards::dynamics
