// The paper's uniform periodic drive F cos(ω t + φ) in 3-D (Appendix B holds in any d), with
// the certified exit times of the 2-D flights (certified_scan.hpp) against planes, mesh
// triangles and spheres.
#pragma once

#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics3/walls3.hpp"

namespace billiards::dynamics3 {

/// State under the drive: the drive's phase, reduced to [0, 2π) in two doubles, with its sine
/// and cosine (as in 2-D, dynamics::BasicDrivenState).
struct DrivenState3 : State3 {
  dynamics::Phase phase;
  double sin_phase = 0, cos_phase = 1;
  void set_phase(const dynamics::Phase& theta);
};

/// The free flight in 3-D, for the ensemble code (dynamics/ensemble.hpp): straight lines,
/// searched by Table3::collision(state).
struct FreeFlight3 {
  using Scalar = double;
  using State = State3;
  static constexpr bool conserves_energy = true;
  State start(const State3& s) const { return s; }
  State advance(const State& s, double t) const { return {s.x + s.v * (t - s.t), s.v, t}; }
};

}  // namespace billiards::dynamics3

template <>
inline constexpr bool billiards::dynamics::is_straight<billiards::dynamics3::FreeFlight3> = true;

namespace billiards::dynamics3 {

struct PeriodicDriveFlight3 {
  using Scalar = double;
  using State = DrivenState3;
  static constexpr bool conserves_energy = false;
  Vec3 accel;         // F / m
  double omega;       // ω
  double phase0 = 0;  // the drive's phase at t = 0

  State start(const State3& s) const;
  /// v(t) = v_s + (F/mω)[sin θ(t) − sin θ_s],
  /// x(t) = x_s + [v_s − (F/mω) sin θ_s](t − t_s) − (F/mω²)[cos θ(t) − cos θ_s].
  State advance(const State& s, double t) const;
  double exit_time(const State& s, const PlaneWall& w, double t_end) const;
  /// Through the triangle's plane within its span (widened by its slack, as for straight
  /// flights, so that neighbours overlap at their shared edge and nothing slips between them).
  double exit_time(const State& s, const TriangleWall& w, double t_end) const;
  double exit_time(const State& s, const SphereWall& w, double t_end) const;
};

}  // namespace billiards::dynamics3
