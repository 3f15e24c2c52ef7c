// Flights in a uniform magnetic field B perpendicular to the plane: circular arcs between
// collisions (the cyclotron motion), in any scalar type (magnetic_flight.cpp instantiates
// double, long double and precision.hpp's Reference).
//
// A charge q of mass m feels q v × B ẑ, so v̇ = −Ω J v with J the rotation by +90° and
// Ω = qB/m the signed cyclotron frequency (Ω > 0 turns clockwise).  With k = |Ω| and
// w0 = −sign(Ω) J v0 (the velocity turned towards the centre of gyration),
//   x(τ) = x0 + (sin kτ / k) v0 + ((1 − cos kτ) / k) w0,   v(τ) = cos kτ v0 + sin kτ w0,
// a circle of centre x0 + w0/k and radius r_c = |v0|/k run through in the period 2π/k.
//
// Exit times through segments and circular arcs are closed forms (docs/collisions.md): along
// the orbit, a wall's gap (the signed distance beyond a line, ±(|x − c|² − r²) for a circle) is
// F0 + B1 sin φ + B2 (1 − cos φ) in the angle turned φ = kτ, a quadratic form in
// (cos φ/2, sin φ/2).  Its zero with F increasing, in the stable root formula of the quadratic,
// is the outward crossing; there is one per turn, so the orbit leaves through the wall there or
// never.  Elliptic arcs are searched by the certified scan (a circle maps to an ellipse under
// the arc's affine map, so the mapped flight is not a magnetic flight).
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/flight.hpp"

namespace billiards::dynamics {

template <class Real>
struct BasicMagneticFlight;

/// The orbit of a magnetic flight from one state: what every wall's search starts from,
/// computed once per flight (`collision` asks the flight for it with `scan_from(s)`).  It
/// refers to the state, which must outlive it.
template <class Real>
struct Gyration {
  using V = Vec2T<Real>;
  const BasicState<Real>& s;
  Real k;         // |Ω|
  Real inv_k;     // 1/|Ω|
  V w0;           // v0 turned by a quarter turn towards the centre
  Real speed;     // |v0|
  V center;       // of gyration, x0 + w0/k
  Real radius;    // r_c = |v0|/k

  Gyration(const BasicMagneticFlight<Real>& flight, const BasicState<Real>& state);
  Real exit_time(const BasicSegmentWall<Real>& w, const Real& t_end) const;
  Real exit_time(const BasicArcWall<Real>& w, const Real& t_end) const;
  Real exit_time(const BasicEllipticArcWall<Real>& w, const Real& t_end) const;
  /// The first wall of the table the orbit leaves through before t_end, with the state there
  /// from the crossing's half angle where a closed form found it (no sine or cosine).
  FlightHit<BasicMagneticFlight<Real>> first_hit(const BasicTable<Real>& table, const Real& t_end) const;
  /// Position after turning by φ = 2ψ, from (cos ψ, sin ψ) ∝ u (no sine or cosine).
  V position_at_half_angle(const V& u) const;
  /// The last crossing a closed form returned (its time and half angle), for first_hit.
  mutable Real found_t = never;
  mutable V found_u = V::Zero();
  /// Can the orbit meet the wall's bounding disk before t_end?
  template <class Wall>
  bool may_reach(const Wall& w, const Real& t_end) const;
};

/// Flight in the uniform field: Ω = qB/m, the signed cyclotron frequency (≠ 0).
template <class Real>
struct BasicMagneticFlight {
  using Scalar = Real;
  using State = BasicState<Real>;
  static constexpr bool conserves_energy = true;
  static constexpr bool closes_orbits = true;  // a cyclotron circle, which may meet no wall

  Real omega_c;  // Ω = qB/m

  State start(const State& s) const { return s; }
  State advance(const State& s, const Real& t) const;
  Gyration<Real> scan_from(const State& s) const { return {*this, s}; }
  Real exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const {
    return scan_from(s).exit_time(w, t_end);
  }
  Real exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const {
    return scan_from(s).exit_time(w, t_end);
  }
  Real exit_time(const State& s, const BasicEllipticArcWall<Real>& w, const Real& t_end) const {
    return scan_from(s).exit_time(w, t_end);
  }
  Real period() const;
};
using MagneticFlight = BasicMagneticFlight<double>;

/// The field B and a uniform force F cos(ωt + φ0) on the charge (ω = 0: the static force
/// F cos φ0, whose E×B drift carries the centre of gyration across the field).  With 2-D
/// vectors as complex numbers (J = i), v̇ = −iΩ v + a cos(ωt + φ0), a = F/m, and from s (phase θ):
///   v(τ) = e^{−iΩτ} [v0 + (a/2)(e^{iθ} E(Ω + ω, τ) + e^{−iθ} E(Ω − ω, τ))],
/// E(λ, τ) = ∫₀^τ e^{iλs} ds = e^{iλτ/2} 2 sin(λτ/2)/λ, which is τ at the resonance λ = 0: the
/// same formula holds at ω = |Ω| without a division by zero (the energy then grows secularly).
/// x(τ) integrates it once more (docs/collisions.md).  Exit times through every wall kind: the
/// certified scan, with |v| bounded by |v0| + (|a|/2)(min(τ, 2/|Ω + ω|) + min(τ, 2/|Ω − ω|)).
/// The search needs a horizon (t_end finite): a bounded orbit may circle forever.
template <class Real>
struct BasicMagneticDriveFlight {
  using Scalar = Real;
  using State = BasicState<Real>;
  static constexpr bool conserves_energy = false;

  Real omega_c;        // Ω = qB/m
  Vec2T<Real> accel;   // F/m
  Real omega = 0;      // ω (0: a static force)
  Real phase0 = 0;     // φ0

  State start(const State& s) const { return s; }
  State advance(const State& s, const Real& t) const;
  Real exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const;
  Real exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const;
  Real exit_time(const State& s, const BasicEllipticArcWall<Real>& w, const Real& t_end) const;
  /// A bound on the speed over the next τ of the flight from s.
  Real speed_bound(const State& s, const Real& tau) const;
};
using MagneticDriveFlight = BasicMagneticDriveFlight<double>;

}  // namespace billiards::dynamics
