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

/// The oscillation segment g ± amp_x, g = s.x + amp_x cos θ_s + u τ the guide at τ after the
/// state s (guiding velocity u): it holds the position at τ, and the particle sweeps it once
/// per period.  (Quiver::sweep; and the flights' own, which need no more of a Quiver.)
template <class State, class V, class Real>
std::pair<V, V> oscillation_segment(const State& s, const V& u, const V& amp_x, const Real& tau) {
  const V g = s.x + amp_x * s.cos_phase + u * tau;
  return {g - amp_x, g + amp_x};
}

/// The guiding velocity of a driven flight from s in the lab picture, v − (F/mω) sin θ_s: the
/// free particle's velocity about which the drive oscillates.
template <class Flight, class State>
auto guiding_velocity(const Flight& f, const State& s) {
  using V = std::decay_t<decltype(s.v)>;
  return scan::guide_velocity(V(s.v), drive_amplitudes(f.accel, f.omega).second, s.sin_phase);
}


/// A periodically driven flight from state s as a guiding line plus an oscillation of
/// amplitude |F|/(mω²): x(τ) = g0 + u τ − (F/mω²) cos θ(τ), τ after the start.  `Flight` has
/// `accel` (F/m, a 2-D or 3-D vector), `omega` and `Scalar`; `State` has x, v, phase and its
/// sine and cosine.  The same object describes the quivering-wall picture: there g0 + u τ is
/// the free particle and (F/mω²) cos θ the walls' displacement, and x(τ) the particle's
/// position relative to the walls.
///
/// It is what the certified scan and the walls' gaps (walls.hpp) know of the flight: the
/// guiding line (g0, u, `guide`), the bounds on the deviation from it (`delta`, `wobble`), on
/// the speed and the acceleration (`speed_bound`, `accel_norm`, `turn_rate`), the motion
/// (`at`, `motion`) and its `Mark` at a sample (the drive's phase, from which `shifted_to` gives
/// a nearby time's position without a sine and cosine).
template <class Flight, class State>
struct Quiver {
  using Real = typename Flight::Scalar;
  using V = std::decay_t<decltype(std::declval<Flight>().accel)>;
  using Mark = PhaseSample<Real>;
  const Flight& flight;
  const State& s;
  V u, g0;
  V v0;              // velocity relative to the walls at τ = 0
  V amp_x, amp_v;    // F/(mω²) and F/(mω): the oscillation's amplitudes
  Real accel_norm;   // |F|/m
  Real inv_omega;    // 1/ω
  Real wobble;       // |F|/(mω) ≥ |v − u|
  Real speed_bound;  // bound on |v| at any time of this flight
  Real delta;        // |F|/(mω²) ≥ |oscillation|
  Real speed;          // |u|
  Real uu, inv_uu;     // |u|² and 1/|u|² (0 when u = 0)
  bool creeping;       // the guide moves less than δ per period (see `creep`)
  Real rounding_rate;  // how fast the rounding of x(τ) grows with τ (see `at`)

  /// The lab picture: s.v is the particle's velocity between fixed walls.
  Quiver(const Flight& f, const State& st) : Quiver(f, st, guiding_velocity(f, st), st.v) {}
  /// From the guiding velocity u (the free particle's, in the quivering-wall picture) and the
  /// velocity relative to the walls at the start; s.x is the position relative to the walls.
  Quiver(const Flight& f, const State& st, const V& guiding_velocity, const V& relative_velocity)
      : flight(f), s(st), u(guiding_velocity), v0(relative_velocity) {
    using L = ScalarLanes<Real>;
    std::tie(amp_x, amp_v) = drive_amplitudes(f.accel, f.omega);
    inv_omega = 1 / f.omega;
    accel_norm = f.accel.norm();
    g0 = scan::guide_start(st.x, amp_x, st.cos_phase);
    delta = accel_norm * inv_omega * inv_omega;
    const auto g = scan::guide_lanes<L>(u.squaredNorm(), accel_norm, f.omega, inv_omega, delta);
    uu = g.uu, inv_uu = g.inv_uu, speed = g.speed, wobble = g.wobble, speed_bound = g.speed_bound;
    creeping = scan::creeps<L>(g);
    rounding_rate = scan::rounding_rate<L>(g, creeping);
  }
  V guide(const Real& tau) const { return g0 + u * tau; }
  /// Its numbers as driven_exit-inl.hpp reads them (in place).
  scan::GuideLanes<const Real&> lanes() const {
    return {uu, inv_uu, speed, speed_bound, wobble, delta, accel_norm, flight.omega, inv_omega};
  }
  /// The acceleration turns at this rate: |da/dt| ≤ accel_norm · turn_rate (the drive's ω).
  Real turn_rate() const { return flight.omega; }
  Real period() const { return boost::math::constants::two_pi<Real>() / flight.omega; }
  /// The oscillation segment guide(τ) ± amp_x, which holds x(τ) and which the particle sweeps
  /// once per period.
  std::pair<V, V> sweep(const Real& tau) const { return oscillation_segment(s, u, amp_x, tau); }
  /// Position and velocity τ after the start (the closed form of advance()).  Within one
  /// flight ωτ stays moderate, so a phase in Real is accurate to ~1e-12 rad in double, which
  /// moves the particle by 1e-12 |F|/(mω²).  A creeping flight may last 10⁸ periods: its phase
  /// is computed as advance() does (advance_phase), since the rounding of ωτ, times the speed
  /// |F|/(mω), would widen the scan's tolerance band (`rounding_rate`) beyond the guide's
  /// approach to the wall per period, and a touch near a turning point would count periods
  /// early (measured: 1-4 periods of 1.8e9 before, with the phase in long double).
  std::pair<V, V> at(const Real& tau) const {
    const auto m = motion(tau);
    return {m.x, m.v};
  }
  /// Position, velocity and acceleration (F/m) cos θ τ after the start.
  struct Motion {
    V x, v, a;
    Real th, sin_th, cos_th;  // the drive's phase θ there (not reduced)
  };
  Motion motion(const Real& tau) const {
    if (tau == 0) return {s.x, v0, flight.accel * s.cos_phase, Real(s.phase), s.sin_phase, s.cos_phase};
    const Real th = phase_at(tau);
    const auto [sn, c] = sin_cos(th);
    return {position(tau, c), scan::quiver_velocity(u, amp_v, sn), flight.accel * c, th, sn, c};
  }
  /// The drive's phase θ τ after the start, as `motion` computes it.
  Real phase_at(const Real& tau) const {
    return creeping ? Real(reduce_phase(advance_phase(s.phase, flight.omega, tau))) : Real(Real(s.phase) + flight.omega * tau);
  }
  /// The position τ after the start, where cos θ = cos_th.
  V position(const Real& tau, const Real& cos_th) const { return scan::quiver_position(g0, u, tau, amp_x, cos_th); }
  /// The position x at τ and the mark there from the mark of a sample at a nearby time (the
  /// drive's phase shifted by ω Δτ: PhaseSample::shifted); false when τ is too far from it.
  bool shifted_to(const Mark& from, const Real& tau, V& x, Mark& at) const {
    using std::abs;
    const Real th = phase_at(tau), h = th - from.theta;
    if (!(abs(h) <= Real(Mark::h_max))) return false;
    const auto [sn, cs] = from.shifted(h);
    x = position(tau, cs);
    at = {th, sn, cs};
    return true;
  }
};


/// The exit-time searches of one driven flight (lab or quivering walls) from one state: the
/// guiding line and the bounds that every wall's search starts from are computed once per
/// flight, not once per wall (`collision` asks the flight for it with `scan_from(s)`).  It
/// refers to the flight and the state, which must outlive it.
template <class Flight>
struct DrivenScan {
  using Real = typename Flight::Scalar;
  Quiver<Flight, BasicDrivenState<Real>> quiver;
  Real exit_time(const BasicSegmentWall<Real>& w, const Real& t_end) const;
  Real exit_time(const BasicArcWall<Real>& w, const Real& t_end) const;
  Real exit_time(const BasicEllipticArcWall<Real>& w, const Real& t_end) const;
  /// Through any other wall kind: the scan of its gap (scanned_exit_time), |a| ≤ |F|/m.
  template <class Wall>
  Real exit_time(const Wall& w, const Real& t_end) const {
    const Quiver<Flight, BasicDrivenState<Real>>& q = quiver;
    return scanned_exit_time(q.s, w, t_end, [&q](const Real& tau) { return q.at(tau); }, q.accel_norm,
                             [&q](const Real& tau) { return Real(q.speed_bound * tau); });
  }
  /// The first wall of the table the flight leaves through before t_end (the hit's t, wall and
  /// the flight's state there; wall −1 if none).  The walls' windows — the only stretches of the flight in which
  /// they can be hit — are searched in the order in which they open, so a wall whose window
  /// opens after the collision found is never sampled; in a window where the sign of f' is
  /// certain, the root is found by a bracketed Newton iteration instead of the certified scan.
  FlightHit<Flight> first_hit(const BasicTable<Real>& table, const Real& t_end) const;
  /// After the windows' first hit (`best`, t_end if none): the walls without windows here
  /// (elliptic arcs, searched as unit arcs by the mapped flight), wall by wall, each up to the
  /// best hit so far; true if one is hit earlier (`best` updated).
  bool first_hit_without_windows(const BasicTable<Real>& table, BasicHit<Real>& best) const;
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
  State advance(const State& s, const Real& t, const PhaseSample<Real>& near = {}) const;
  /// What an ensemble computes once per record time t for every particle's record there
  /// (ensemble.hpp's RecordMarks): sin θ(t), the phase ω t + φ0 reduced in two doubles.
  Real record_mark(const Real& t) const {
    BasicState<Real, D> at;
    at.t = t;
    return start(at).sin_phase;
  }
  /// ½ m v² at the time whose mark is sin θ: Appendix B's velocity v_s + (F/mω)(sin θ − sin θ_s)
  /// needs neither the position nor a sine of the particle's own.
  Real kinetic_energy_at_mark(const State& s, const Real& sin_theta, const Real& mass) const {
    const VecN<Real, D> v = s.v + drive_amplitudes(accel, omega).second * Real(sin_theta - s.sin_phase);
    return Real(0.5) * mass * v.squaredNorm();
  }
  DrivenScan<BasicPeriodicDriveFlight> scan_from(const State& s) const requires(D == 2) { return {{*this, s}}; }
  /// The oscillation segment guide ± F/(mω²) that holds the position at time t of the flight
  /// from s (no sine or cosine: the ensemble's every-flight check looks it up first).
  std::pair<VecN<Real, D>, VecN<Real, D>> sweep(const State& s, const Real& t) const {
    return oscillation_segment(s, guiding_velocity(*this, s), drive_amplitudes(accel, omega).first,
                                     Real(t - s.t));
  }
  Real exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const requires(D == 2) {
    return scan_from(s).exit_time(w, t_end);
  }
  Real exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const requires(D == 2) {
    return scan_from(s).exit_time(w, t_end);
  }
  /// Through any other wall kind: in 2-D the scan's (DrivenScan), in 3-D the scan of the
  /// wall's gap (scanned_exit_time), |a| ≤ |F|/m.
  template <class Wall>
  Real exit_time(const State& s, const Wall& w, const Real& t_end, Scanned = {}) const {
    if constexpr (D == 2) {
      return scan_from(s).exit_time(w, t_end);
    } else {
      const Quiver<BasicPeriodicDriveFlight, State> q(*this, s);
      return scanned_exit_time(s, w, t_end, [&q](const Real& tau) { return q.at(tau); }, q.accel_norm,
                               [&q](const Real& tau) { return Real(q.speed_bound * tau); });
    }
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
  State advance(const State& s, const Real& t, const PhaseSample<Real>& near = {}) const;
  /// ḋ, the walls' velocity at the state's time.
  Vec2T<Real> wall_velocity(const State& s) const { return -drive_amplitudes(accel, omega).second * s.sin_phase; }
  /// The lab flight's scan, seen from the walls: guiding velocity ẏ, velocity relative to the
  /// walls ẏ − ḋ.
  DrivenScan<BasicQuiveringWallFlight> scan_from(const State& s) const {
    return {{*this, s, s.v, s.v - wall_velocity(s)}};
  }
  /// As for the lab flight (the position relative to the walls lies on it).
  std::pair<Vec2T<Real>, Vec2T<Real>> sweep(const State& s, const Real& t) const {
    return oscillation_segment(s, s.v, drive_amplitudes(accel, omega).first, Real(t - s.t));
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
  /// Through any other wall kind: the scan of its gap along the parabola (scanned_exit_time).
  template <class Wall>
  Real exit_time(const State& s, const Wall& w, const Real& t_end) const {
    const Real V = s.v.norm(), A = accel.norm();
    auto at = [&](const Real& tau) {
      return std::pair{Vec2T<Real>(s.x + (s.v + accel * (tau / 2)) * tau), Vec2T<Real>(s.v + accel * tau)};
    };
    return scanned_exit_time(s, w, t_end, at, A, [V, A](const Real& tau) { return Real((V + A * tau / 2) * tau); });
  }
};
using ConstantForceFlight = BasicConstantForceFlight<double>;

}  // namespace billiards::dynamics
