// Flights in a uniform magnetic field: circular arcs between collisions in 2-D (B perpendicular
// to the plane), helices in 3-D, in any scalar type in 2-D (magnetic_flight.cpp instantiates
// double, long double and precision.hpp's Reference) and in double in 3-D.
//
// A charge q of mass m feels q v × B, so v̇ = v × Ω with Ω = qB/m (in 2-D Ω ẑ, Ω the signed
// cyclotron frequency: Ω > 0 turns clockwise).  With k = |Ω|, b = Ω/k, the drift v∥ = (v0·b) b
// along the field, v⊥ = v0 − v∥ and w0 = v⊥ × b (v⊥ turned towards the centre of gyration),
//   x(τ) = x0 + v∥ τ + (sin kτ / k) v⊥ + ((1 − cos kτ) / k) w0,   v(τ) = v∥ + cos kτ v⊥ + sin kτ w0,
// a circle of centre x0 + w0/k and radius r_c = |v⊥|/k run through in the period 2π/k while
// the centre drifts along the field (in 2-D v∥ = 0: the circle closes).
//
// Exit times through segments and circular arcs are closed forms (docs/collisions.md): along
// the orbit, a wall's gap (the signed distance beyond a line, ±(|x − c|² − r²) for a circle) is
// F0 + B1 sin φ + B2 (1 − cos φ) in the angle turned φ = kτ, a quadratic form in
// (cos φ/2, sin φ/2).  Its zero with F increasing, in the stable root formula of the quadratic,
// is the outward crossing; there is one per turn, so the orbit leaves through the wall there or
// never (magnetic_exit-inl.hpp, written once for one number and for the lock-step lanes of
// magnetic_lockstep.hpp).  The same closed form serves a 3-D plane parallel to the field, and
// a plane across it is met at a linear rate.  Elliptic arcs (a circle maps to an ellipse under
// the arc's affine map, so the mapped flight is not a magnetic flight) and the other 3-D walls
// are searched by the certified scan, whose `earliest` follows the guiding axis
// x0 + w0/k + v∥ τ: the helix stays within r_c of it, so a wall farther than that is passed
// without sampling.
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/flight.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/magnetic_exit.hpp"
#include "billiards/dynamics/table3.hpp"

#include <type_traits>

namespace billiards::dynamics {

template <class Real, int D = 2>
struct BasicMagneticFlight;

/// Ω = qB/m as a flight keeps it: in 2-D the signed cyclotron frequency (the field is Ω ẑ), in
/// 3-D the vector.
template <class Real, int D>
using Cyclotron = std::conditional_t<D == 2, Real, VecN<Real, 3>>;

/// What the magnetic search reads of a 2-D wall beside its straight-flight view
/// (magnetic_exit-inl.hpp): its bounding disk, the rounding of a distance to it, its slack.
template <class Wall, class Real = typename Wall::V::Scalar>
ReachLanes<Real> reach_lanes(const Wall& w) {
  return {w.bound_center.x(), w.bound_center.y(), w.bound_radius, Real(16 * scan::eps<Real> * w.bound_radius), w.slack};
}

/// The orbit of a magnetic flight from one state: what every wall's search starts from,
/// computed once per flight (`collision` asks the flight for it with `scan_from(s)`).  It
/// refers to the state, which must outlive it.
template <class Real, int D = 2>
struct Gyration {
  using V = VecN<Real, D>;
  const BasicState<Real, D>& s;
  Real k;         // |Ω|
  Real inv_k;     // 1/|Ω|
  V axis;         // b = Ω/|Ω| (2-D: 0)
  V v_perp;       // v⊥, the velocity across the field (2-D: v0)
  V w0;           // v⊥ turned by a quarter turn towards the centre
  V drift;        // v∥, the velocity along the field (2-D: 0)
  Real speed;     // |v⊥|
  V center;       // of gyration, x0 + w0/k (in 3-D at the start: it drifts by v∥ τ)
  Real radius;    // r_c = |v⊥|/k
  Real rounding;  // of points on the circle: 16 ε (|centre|∞ + r_c) (2-D)

  Gyration(const BasicMagneticFlight<Real, D>& flight, const BasicState<Real, D>& state);
  /// Position and velocity τ after the start.
  std::pair<V, V> at(const Real& tau) const;
  Real period() const;

  Real exit_time(const BasicSegmentWall<Real>& w, const Real& t_end) const requires(D == 2);
  Real exit_time(const BasicArcWall<Real>& w, const Real& t_end) const requires(D == 2);
  /// Through a wall with no closed form (elliptic arcs; any kind): the certified scan of its
  /// gap (scan::gap_crossing, |a| = k |v⊥|), over one turn where the orbit closes (it holds
  /// every crossing the orbit will ever make), else while the guiding axis is within r_c of
  /// the wall's box (3-D; an unbounded box needs a horizon or a closed form).
  template <class Wall>
  Real exit_time(const Wall& w, const Real& t_end, Scanned = {}) const {
    using std::min;
    Real tau_end = t_end == never ? Real(never) : Real(t_end - s.t);
    if constexpr (D == 2) {
      if (!may_reach(w, t_end)) return never;
      tau_end = min(tau_end, period());
    } else {
      tau_end = min(tau_end, drift.isZero(0) ? period() : axis_leaves(w.box()));
      if (!(tau_end >= 0)) return never;
    }
    const Real tau = scan::gap_crossing(
        w, [this](const Real& t) { return at(t); }, Real(k * speed), [this](const Real& t) { return Real(drift.norm() * t + 2 * radius); },
        Real(s.x.template lpNorm<Eigen::Infinity>()), tau_end);
    return tau == never ? Real(never) : Real(s.t + tau);
  }
  /// When the guiding axis x0 + w0/k + v∥ τ leaves the box (lo, hi) grown by r_c, for good
  /// (3-D); −1 when it never comes within it.
  double axis_leaves(const std::pair<Vec3, Vec3>& box) const requires(D == 3) {
    const double pad = radius + rounding;
    double out = never;
    for (int i = 0; i < 3; ++i) {
      const double lo = box.first[i] - pad, hi = box.second[i] + pad;
      if (drift[i] == 0) {
        if (center[i] < lo || center[i] > hi) return -1;
        continue;
      }
      out = std::min(out, ((drift[i] > 0 ? hi : lo) - center[i]) / drift[i]);
    }
    return out;
  }
  /// The first wall of the table the orbit leaves through before t_end, with the state there
  /// from the crossing's half angle where a closed form found it (no sine or cosine).  The
  /// closed forms' crossings are compared as half angles (magnetic_exit-inl.hpp: cross
  /// products, no arctangent), so that only a crossing earlier than the best so far gets a
  /// span test, and only the winner an arctangent.
  FlightHit<BasicMagneticFlight<Real>> first_hit(const BasicTable<Real>& table, const Real& t_end) const
    requires(D == 2);
  /// The hit from the earliest closed-form crossing through the table's segments and arcs
  /// (`earliest`, through `wall`), as first_hit finds it: its time, if before t_end; then the
  /// scans of the other walls, each up to the hit so far; the state at the hit.  (The lock-step
  /// search finds `earliest` for several flights at once.)
  FlightHit<BasicMagneticFlight<Real>> hit_from(const BasicTable<Real>& table,
                                                const EarliestCrossing<Real, bool>& earliest, const WallId& wall,
                                                const Real& t_end) const
    requires(D == 2);
  /// Makes the hit so far (before hit.t) the earliest crossing through the walls that have no
  /// closed form (elliptic arcs), each scanned up to the hit so far; true if one is crossed
  /// earlier.
  bool scan_walls_without_closed_form(const BasicTable<Real>& table, FlightHit<BasicMagneticFlight<Real>>& hit) const
    requires(D == 2);
  /// The circle as magnetic_exit-inl.hpp reads it, its numbers in place (2-D).
  GyrationLanes<const Real&> lanes() const requires(D == 2) {
    return {s.x.x(), s.x.y(), s.v.x(), s.v.y(), w0.x(), w0.y(),   k,
            inv_k,   speed,   center.x(), center.y(), radius, rounding};
  }
  /// Can the orbit meet the wall's bounding disk (before t_end)?  Not when the disk lies wholly
  /// outside the cyclotron circle or wholly inside it.
  template <class Wall>
  bool may_reach(const Wall& w, const Real& t_end) const requires(D == 2) {
    if (!gyration_reaches(ScalarLanes<Real>{}, lanes(), reach_lanes(w))) return false;
    if (t_end == never) return true;
    // The arc flown until t_end is no shorter than its chord.
    const Real margin = rounding + 16 * scan::eps<Real> * w.bound_radius;
    const Real travel = speed * (t_end - s.t) + w.bound_radius + margin;
    return (s.x - w.bound_center).squaredNorm() <= travel * travel;
  }

  double exit_time(const PlaneWall& w, double t_end) const requires(D == 3);
  double exit_time(const TriangleWall& w, double t_end) const requires(D == 3);
  double exit_time(const SphereWall& w, double t_end) const requires(D == 3);
  /// The guiding axis and r_c (and rounding) around it: the tube the BVH walks (table3.hpp).
  Tube3 tube() const requires(D == 3);

 private:
  /// Through the plane n·(x − a) = 0 within `in_span` (3-D): closed forms across and (without a
  /// span) along the field, else the scan.
  template <class InSpan>
  double plane_exit(const Vec3& n, const Vec3& a, double slack, double t_end, bool spanless, InSpan in_span) const
    requires(D == 3);
};

/// Flight in the uniform field: Ω = qB/m, the signed cyclotron frequency (≠ 0) in 2-D, the
/// vector (≠ 0) in 3-D.
template <class Real, int D>
struct BasicMagneticFlight {
  using Scalar = Real;
  using State = BasicState<Real, D>;
  static constexpr bool conserves_energy = true;

  Cyclotron<Real, D> omega_c;  // Ω = qB/m

  State start(const State& s) const { return s; }
  State advance(const State& s, const Real& t) const;
  Gyration<Real, D> scan_from(const State& s) const { return {*this, s}; }
  template <class Wall>
  Real exit_time(const State& s, const Wall& w, const Real& t_end) const {
    return scan_from(s).exit_time(w, t_end);
  }
  /// Does the orbit from s close (no drift along the field: always in 2-D)?  Such an orbit
  /// may circle inside the table forever; any other drifts to a wall.
  bool closes_orbit(const State& s) const {
    if constexpr (D == 2) return true;
    else return s.v.dot(omega_c) == 0;
  }
  Real period() const;
};
using MagneticFlight = BasicMagneticFlight<double>;
using MagneticFlight3 = BasicMagneticFlight<double, 3>;

/// The field B and a uniform force F cos(ωt + φ0) on the charge (ω = 0: the static force
/// F cos φ0, whose E×B drift carries the centre of gyration across the field).  Across the
/// field, with the plane's vectors as complex numbers (2-D: J = i; 3-D: a basis e1, e2 with
/// e1 × e2 = b, where Ω = |Ω|), v̇ = −iΩ v + a cos(ωt + φ0), a = F/m, and from s (phase θ):
///   v(τ) = e^{−iΩτ} [v0 + (a/2)(e^{iθ} E(Ω + ω, τ) + e^{−iθ} E(Ω − ω, τ))],
/// E(λ, τ) = ∫₀^τ e^{iλs} ds = e^{iλτ/2} 2 sin(λτ/2)/λ, which is τ at the resonance λ = 0: the
/// same formula holds at ω = |Ω| without a division by zero (the energy then grows secularly).
/// x(τ) integrates it once more (docs/collisions.md).  Along the field (3-D) the motion is the
/// free driven one, v∥(τ) = v∥0 + a∥ Re(e^{iθ} E(ω, τ)).  Exit times through every wall kind:
/// the certified scan, with |v| bounded by
/// |v0| + (|a⊥|/2)(min(τ, 2/|Ω + ω|) + min(τ, 2/|Ω − ω|)) + |a∥| min(τ, 2/ω).
/// The search needs a horizon (t_end finite): a bounded orbit may circle forever.
/// The state carries the drive's phase θ (as the periodic drive's, forced_flight.hpp: two
/// doubles, reduced, with its sine and cosine), so that each flight runs on its own clock: θ
/// as ω t + φ0 from an absolute t in one double would keep only ulp(ω t) (3e-9 rad at
/// ω = 40π, t = 10⁶).
/// Collision searches per cyclotron period of a magnetic flight with a force (lookahead).
inline constexpr int lookaheads_per_period = 8;

template <class Real, int D = 2>
struct BasicMagneticDriveFlight {
  using Scalar = Real;
  using State = BasicDrivenState<Real, D>;
  static constexpr bool conserves_energy = false;

  Cyclotron<Real, D> omega_c;  // Ω = qB/m
  VecN<Real, D> accel;         // F/m
  Real omega = 0;              // ω (0: a static force)
  Real phase0 = 0;             // φ0

  /// The state at s with the drive's phase ω s.t + φ0.
  State start(const BasicState<Real, D>& s) const {
    return BasicPeriodicDriveFlight<Real, D>{accel, omega, phase0}.start(s);
  }
  State advance(const State& s, const Real& t) const;
  Real exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const requires(D == 2);
  Real exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const requires(D == 2);
  /// Through any other wall kind (elliptic arcs): the scan with the wall's own gap_sample.
  /// (magnetic_flight.cpp instantiates it for every kind of WallKinds and WallKinds3.)
  template <class Wall>
  Real exit_time(const State& s, const Wall& w, const Real& t_end, Scanned = {}) const;
  double exit_time(const State& s, const PlaneWall& w, double t_end) const requires(D == 3);
  double exit_time(const State& s, const TriangleWall& w, double t_end) const requires(D == 3);
  double exit_time(const State& s, const SphereWall& w, double t_end) const requires(D == 3);
  /// A bound on the speed over the next τ of the flight from s.
  Real speed_bound(const State& s, const Real& tau) const;
  /// How far ahead one collision search looks: an eighth of a cyclotron period
  /// (lookaheads_per_period).  The search scans each wall up to its horizon, so its cost grows
  /// with the horizon (in the driven clover in a field: 18 µs per collision an eighth of a
  /// period ahead, 42 µs a period ahead, 237 µs 100 time units ahead); a caller that meets no
  /// wall advances the flight there and searches again.
  Real lookahead() const {
    using std::abs;
    if constexpr (D == 2) return boost::math::constants::two_pi<Real>() / (lookaheads_per_period * abs(omega_c));
    else return boost::math::constants::two_pi<Real>() / (lookaheads_per_period * omega_c.norm());
  }
};
using MagneticDriveFlight = BasicMagneticDriveFlight<double>;
using MagneticDriveFlight3 = BasicMagneticDriveFlight<double, 3>;

}  // namespace billiards::dynamics
