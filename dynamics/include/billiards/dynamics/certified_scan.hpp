// The certified root scan behind the forced flights, in 2-D and 3-D (internal to dynamics).
//
// For one wall, f(τ) measures how far beyond the wall the particle is τ after the flight's
// start.  The scan steps from sample to sample by the earliest time at which f could vanish
// given a bound M on |f''| (the positive root of |f| − σ f' s − M s²/2, σ = sign f), so it
// never steps over a root; near a simple root it converges like Newton's iteration from the
// safe side.  Before each sample, the guiding line of the flight may show that no collision
// can occur sooner (`earliest`): then the scan moves on without evaluating f at all, which
// costs a sine and a cosine.
#pragma once

#include "billiards/dynamics/flight.hpp"
#include "billiards/dynamics/phase.hpp"

#include <boost/math/constants/constants.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <type_traits>
#include <utility>

namespace billiards::dynamics::scan {

template <class Real>
inline const Real eps = std::numeric_limits<Real>::epsilon();

/// f and f' at one time of the scan, with what bounds f'' until the next sample.
template <class Real, class V = Vec2T<Real>>
struct Sample {
  Real f, df;  // how far beyond the wall, and its rate
  Real M;      // bound on |f''| over the next `cap` time units
  Real cap;    // longest step for which M holds
  V x;         // position
};

/// The collision time returned for a sample p at τ within the rounding band (|f| ≤ tol, f' > 0):
/// one Newton step polishes the root from |f| ≤ tol (rounding of the walls, ~1e-13) to the
/// rounding of f itself, so the collision time does not depend on where the search happened to
/// enter the band; the step stays inside that band.
template <class Real, class S>
Real polished_root(const Real& tau, const S& p, const Real& tol) {
  using std::max;
  return max(Real(0), Real(tau - std::clamp(p.f, Real(-tol), tol) / p.df));
}

/// First τ in [0, tau_end] at which f crosses zero upward at a point in the wall's span.
/// `sample(τ)` evaluates f; `earliest(τ)` returns a time ≥ τ before which no collision can
/// occur (from the guiding line and the bounded oscillation; τ itself when it cannot tell), or
/// +∞; `tolerance(τ)` is the rounding level of f at τ.  When no crossing is found, `*resume`
/// (if given) receives the first τ beyond tau_end at which the scan would sample next: a caller
/// that extends f piece by piece (an integrated flight, step by step) continues from there.
/// Inlined into each caller so that its lambdas fold into one loop (measured with callgrind:
/// 12% fewer instructions than a call).
template <bool local_band = false, class Real, class SampleFn, class EarliestFn, class SpanFn, class TolFn>
[[gnu::always_inline]] inline Real first_outward_crossing(SampleFn sample, EarliestFn earliest, SpanFn in_span,
                                                          TolFn tolerance, const Real& tau_end,
                                                          Real* resume = nullptr) {
  using std::abs;
  using std::max;
  using std::min;
  using std::sqrt;
  constexpr int max_steps = 1000000;
  Real tau = 0;
  for (int step = 0; step < max_steps; ++step) {
    if (tau <= tau_end && tau != never) tau = earliest(tau);
    if (tau > tau_end || tau == never) {  // (τ = ∞: no window ahead, with no horizon)
      if (resume) *resume = tau;
      return never;
    }
    const auto p = sample(tau);
    // τ advances by at least `floor`, over which f changes by up to |f'| floor: the band must
    // be that wide, or a root could fall between two samples that both miss it (found in MPFR,
    // where a creeping flight's rounding band was narrower than that after 1.8e9 s).  Callers'
    // tolerances include it through a bound on |f'|, except where that bound is too wide
    // (`local_band`: creeping flights, where it made touches count periods early).
    const Real floor = 4 * eps<Real> * max(tau, Real(1e-300));
    Real tol = tolerance(tau);
    if constexpr (local_band) tol = max(tol, Real(floor * abs(p.df)));
    Real s;
    if (abs(p.f) <= tol) {
      // At the wall to rounding: an outward crossing in the span is the collision.
      if (p.df > 0 && in_span(p.x)) return polished_root(tau, p, tol);
      // Otherwise no collision here.  Leaving the wall (f' < 0, as from the wall just bounced
      // off), f decreases until f' ≥ 0 and stays below f + tol + f' s + M s²/2, whose larger
      // root is the earliest return to zero.  A touch or a crossing outside the span is passed
      // by the time f needs to change by tol (a skipped crossing would be no deeper than
      // rounding: a graze).
      const Real hi = p.f + tol, disc = p.df * p.df - 2 * p.M * hi;
      s = p.df < 0 && disc > 0 ? min(Real((sqrt(disc) - p.df) / p.M), p.cap)
                               : Real(2 * tol / (abs(p.df) + sqrt(2 * p.M * tol)));
    } else {
      // Earliest zero allowed by |f''| ≤ M: the positive root of |f| − σ f' s − M s²/2.
      // Each form is free of cancellation on its side: moving away from the wall (slope < 0)
      // the first would divide by a difference of nearly equal numbers and could step past
      // the root (a ball thrown off a floor and pulled back by the force).  (Found and fixed
      // by the hard-cases suite.)
      const Real a = abs(p.f), slope = p.f < 0 ? p.df : Real(-p.df);
      const Real root = sqrt(slope * slope + 2 * p.M * a);
      const Real quadratic = p.M > 0 ? (slope >= 0 ? Real(2 * a / (slope + root)) : Real((root - slope) / p.M))
                                     : (slope > 0 ? Real(a / slope) : Real(never));
      s = min(quadratic, p.cap);
    }
    // Keep a floor so that τ advances in floating point; it is far below any physical time.
    tau += max(s, floor);
  }
  throw std::runtime_error("certified root isolation did not converge in a million steps");
}

/// The `earliest` of a driven flight: f lies within the oscillation amplitude (and rounding)
/// of its guiding part, so no collision can occur before the guide comes that close to the
/// wall — `window_start(τ)`, τ itself when it is that close — nor in a window, up to the time
/// `window_end(start)` at which the guide is twice that far, that `passes(start, end)`
/// declares out of the wall's span.  Such windows are passed one after another without
/// evaluating f.  Returns τ, a later time, or +∞ (nothing before tau_end).  `sampled_until`
/// keeps the end of the last window that could not be passed: while the scan samples its way
/// through that window, it is not decided again (sampling is always safe).
template <class Real, class StartFn, class EndFn, class Passes>
[[gnu::always_inline]] inline Real first_window(Real tau, const Real& tau_end, StartFn window_start, EndFn window_end,
                                                Passes passes, Real& sampled_until) {
  for (;;) {
    const Real start = window_start(tau);
    if (start == never || start > tau_end) return never;
    if (start < sampled_until) return start;
    const Real end = window_end(start);
    // (A window without end, of a guide standing still, is not passed: guide(∞) = g0 + 0·∞.)
    if (!(end > start) || end == never || !passes(start, end)) {
      sampled_until = end;
      return start;
    }
    if (end >= tau_end) return never;
    tau = end;
  }
}

/// The `earliest` of a driven flight whose guide creeps (moves less than δ per period, as for a
/// particle nearly at rest at a drive phase near 0): from τ, the first time ≥ τ at which the
/// oscillation segment may come within rounding of the wall.  The particle stays on that
/// segment, which moves rigidly at |u|; so while `clearance(τ)`, a lower bound on its distance
/// from the wall within the span, exceeds the rounding band, no collision can occur before
/// τ + clearance/|u|, and the scan jumps there (to the next window) instead of sampling every
/// period — 10⁸ of them for the clover scaled by 1e-6 from a speed of 1e-15.  A guide that
/// stands still (u = 0) gives a periodic f: a period scanned without a collision, or a segment
/// clear of the wall, means no collision ever.  Jumps shorter than a period stop: sampling it
/// costs no more.
template <class Q, class Real, class Clearance, class TolFn>
[[gnu::noinline]] Real creep(const Q& q, const Real& tau, const Real& tau_end, Clearance clearance, TolFn tolerance) {
  if (tau == never || tau > tau_end) return never;
  if (q.speed == 0 && tau >= q.period()) return never;
  const Real gap = clearance(tau) - 2 * tolerance(tau);
  if (!(gap > 0)) return tau;
  if (q.speed == 0) return never;
  return gap < q.speed * q.period() ? tau : Real(tau + gap / q.speed);
}

/// Distance from the segment [p, q] to the sphere (circle) of centre c and radius r: the
/// segment's distances from c fill [nearest, farthest].
template <class V, class Real>
Real segment_sphere_distance(const V& p, const V& q, const V& c, const Real& r) {
  using std::max;
  const Real nearest = point_segment_distance(c, p, q), farthest = max((p - c).norm(), (q - c).norm());
  return max({Real(nearest - r), Real(r - farthest), Real(0)});
}

/// Scans of flights that do not creep take this instead of a clearance: their loop has no call
/// to `creep`, which, even never taken, kept the scan's state out of registers (+25%
/// instructions per collision at 320π).  `with_creep` picks one or the other.
struct NotCreeping {};

template <class Scan, class Clearance>
[[gnu::noinline]] auto creeping_scan(Scan scan, Clearance clearance) {
  return scan(clearance);
}

/// scan(clearance) for a creeping flight, in a call of its own; scan(NotCreeping{}) otherwise.
template <class Q, class Scan, class Clearance>
[[gnu::always_inline]] inline auto with_creep(const Q& q, Scan scan, Clearance clearance) {
  return q.creeping ? creeping_scan(scan, clearance) : scan(NotCreeping{});
}

/// Distance from the segment [p, q] to the plane through a with unit normal n (a lower bound
/// for any piece of it).
template <class V, class Real = typename V::Scalar>
Real segment_plane_distance(const V& p, const V& q, const V& n, const V& a) {
  using std::abs;
  using std::min;
  const Real fp = n.dot(p - a), fq = n.dot(q - a);
  return fp * fq <= 0 ? Real(0) : min(abs(fp), abs(fq));
}

/// Time, from τ0, at which the linear function ℓ(τ) = l0 + l1 (τ − τ0) first reaches level L
/// from below (ℓ(τ0) < L), or +∞.
template <class Real>
Real reach_linear(const Real& tau0, const Real& l0, const Real& l1, const Real& level) {
  if (l0 >= level) return tau0;
  return l1 > 0 ? Real(tau0 + (level - l0) / l1) : Real(never);
}

/// First τ ≥ τ0 at which |q0 + u (τ − τ0)|² crosses ρ², going outward (from inside) when
/// `outward`, inward otherwise; τ0 itself when already on that side, +∞ when never.
template <class Real, class V>
[[gnu::always_inline]] inline Real reach_radius(const Real& tau0, const V& q0, const V& u, const Real& rho, bool outward) {
  using std::sqrt;
  const Real a = u.squaredNorm(), b = q0.dot(u), c = q0.squaredNorm() - rho * rho;
  if (outward ? c >= 0 : c <= 0) return tau0;
  if (a == 0) return never;
  const Real D = b * b - a * c;
  if (D < 0) return never;  // the guiding line misses the circle of radius ρ
  if (!outward && b >= 0) return never;  // moving away
  const Real root = sqrt(D);
  if (outward) return tau0 + (b <= 0 ? Real((root - b) / a) : Real(-c / (b + root)));  // larger root
  return tau0 + c / (root - b);                                                        // smaller root
}

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
  return V(s.v - drive_amplitudes(f.accel, f.omega).second * s.sin_phase);
}

/// A periodically driven flight from state s as a guiding line plus an oscillation of
/// amplitude |F|/(mω²): x(τ) = g0 + u τ − (F/mω²) cos θ(τ), τ after the start.  `Flight` has
/// `accel` (F/m, a 2-D or 3-D vector), `omega` and `Scalar`; `State` has x, v, phase and its
/// sine and cosine.  The same object describes the quivering-wall picture: there g0 + u τ is
/// the free particle and (F/mω²) cos θ the walls' displacement, and x(τ) the particle's
/// position relative to the walls.
template <class Flight, class State>
struct Quiver {
  using Real = typename Flight::Scalar;
  using V = std::decay_t<decltype(std::declval<Flight>().accel)>;
  const Flight& flight;
  const State& s;
  V u, g0;
  V v0;              // velocity relative to the walls at τ = 0
  V amp_x, amp_v;    // F/(mω²) and F/(mω): the oscillation's amplitudes
  Real accel_norm;   // |F|/m
  Real inv_omega;    // 1/ω
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
    std::tie(amp_x, amp_v) = drive_amplitudes(f.accel, f.omega);
    inv_omega = 1 / f.omega;
    accel_norm = f.accel.norm();
    g0 = st.x + amp_x * st.cos_phase;
    uu = u.squaredNorm();
    inv_uu = uu > 0 ? Real(1 / uu) : Real(0);
    speed = sqrt(uu);
    speed_bound = speed + accel_norm * inv_omega;
    delta = accel_norm * inv_omega * inv_omega;
    creeping = speed * boost::math::constants::two_pi<Real>() < delta * f.omega;  // |u| T < δ
    rounding_rate = creeping ? speed : speed_bound;
  }
  V guide(const Real& tau) const { return g0 + u * tau; }
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
    return {position(tau, c), u + amp_v * sn, flight.accel * c, th, sn, c};
  }
  /// The drive's phase θ τ after the start, as `motion` computes it.
  Real phase_at(const Real& tau) const {
    return creeping ? Real(reduce_phase(advance_phase(s.phase, flight.omega, tau))) : Real(Real(s.phase) + flight.omega * tau);
  }
  /// The position τ after the start, where cos θ = cos_th.
  V position(const Real& tau, const Real& cos_th) const { return g0 + u * tau - amp_x * cos_th; }
};

/// The drive's phase θ (as computed in Real, not reduced) and its sine and cosine at one
/// sample of a root search: the state at the root, a polishing step away, is had from them
/// without another sine and cosine.  (Not for creeping flights, whose samples reduce θ.)
template <class Real>
struct PhaseSample {
  Real theta = never, sin = 0, cos = 1;
  /// The farthest shift `shifted` serves.
  static constexpr double h_max = 0.05;
  bool known() const { return theta != never; }
  /// Is the phase `precise` (in the phase type) within h_max of θ, not reduced?  (A flight of
  /// 2²⁰ rad and more has its phase partly reduced by advance_phase.)
  bool near(const PhaseOf<Real>& precise) const {
    using std::abs;
    return abs(Real(precise - PhaseOf<Real>(theta))) <= Real(h_max);
  }
  /// sin and cos of `precise` (θ + h, near θ): which corrects the last step of a root search
  /// and the rounding of θ in Real.
  std::pair<Real, Real> at(const PhaseOf<Real>& precise) const { return shifted(Real(precise - PhaseOf<Real>(theta))); }
  /// sin and cos of θ + h, |h| ≤ h_max, by the angle-sum formulas, with sin h and cos h − 1 from
  /// their Taylor series (remainders below h⁹/9! = 5.4e-18): a fifth of a sine and cosine.
  /// The series' ratios are multiplied by their reciprocals, not divided: six divisions sat on
  /// the way from a root to the hit's state (the reciprocals' rounding, ~1e-16 of terms below
  /// z/6 ≈ 4e-4, is far below the remainder).
  std::pair<Real, Real> shifted(const Real& h) const {
    const Real z = h * h;
    const Real sin_h = h * (1 - z * Real(Real(1) / 6) * (1 - z * Real(Real(1) / 20) * (1 - z * Real(Real(1) / 42))));
    const Real cos_h_1 =
        -z * Real(0.5) * (1 - z * Real(Real(1) / 12) * (1 - z * Real(Real(1) / 30) * (1 - z * Real(Real(1) / 56))));
    return {sin + (sin * cos_h_1 + cos * sin_h), cos + (cos * cos_h_1 - sin * sin_h)};
  }
};

/// A function with the same sign and roots as f (and the same sign of slope), its first two
/// derivatives at one time, the position there, and `tol`, the level below which |f| ≤ the
/// rounding tolerance of f is certain.
template <class Real, class V>
struct Taylor {
  Real f, df, d2f;
  V x;
  Real tol;
  Real th, sin_th, cos_th;  // the drive's phase there
};

/// A stretch [start, end] of a driven flight in which its guide is within two margins (the
/// oscillation's amplitude and rounding) of a wall's supporting line or sphere: the only times
/// at which the wall can be hit.  `below`: the guide entered it from f's negative side, so
/// f(start) < 0.  (No default values: arrays of windows are filled as they are found.)
template <class Real>
struct Window {
  Real start, end, margin;
  int wall;
  bool below;
};

/// The rounding tolerance of a gap is c0 + c1 τ: the time by which a window that ends at
/// most (d + 2 tol(τ))/speed after t0 has ended, solved for τ (the margin at that time covers
/// the whole window), or +∞ when the guide is too slow to outrun the growth of the tolerance.
template <class Real>
Real window_horizon(const Real& t0, const Real& d, const Real& c0, const Real& c1, const Real& speed) {
  const Real slack = speed - 2 * c1;
  return slack > 0 ? Real(t0 + (d + 2 * (c0 + c1 * t0)) / slack) : Real(never);
}

/// The time up to which a window's margin must cover the rounding of f: the horizon, or when
/// there is none, `bound()` (a window_horizon).  (The horizon itself widens a window by the
/// rounding's growth until then, ~1e-12 of the oscillation's amplitude for a horizon of 10³
/// flights, and saves a division per wall.)
template <class Real, class Bound>
Real margin_time(const Real& horizon, Bound bound) {
  return horizon < never ? horizon : bound();
}

/// Clips the window [start, end] to [0, horizon] into out[n]; returns the new count.
template <class Real>
int clip_window(int n, Window<Real>* out, const Real& start, const Real& end, const Real& margin, bool below,
                const Real& horizon) {
  using std::max;
  using std::min;
  if (end < 0 || start > horizon) return n;
  out[n] = {max(start, Real(0)), min(end, horizon), margin, -1, below && start > 0};
  return n + 1;
}

/// How far beyond the line (2-D) or plane (3-D) through `a` with outward unit normal `n` the
/// driven flight `q` is: f = n·(x − a), which lies within B = |n·F|/(mω²) of its guiding part
/// g_off + nu τ.  A gap gives a scan of one wall everything it needs: f and its rounding, the
/// windows (the only times at which f can vanish) and a bound on the sign of f' in a window.
template <class Q, class V>
struct PlaneGap {
  using Real = typename Q::Real;
  const Q& q;
  V n, a;
  Real slack, n_a, B, nu, g_off;
  Real tol0, tol1;  // the rounding level of f at τ is tol0 + tol1 τ

  PlaneGap(const Q& q_, const V& n_, const V& a_, const Real& slack_) : q(q_), n(n_), a(a_), slack(slack_) {
    using std::abs;
    n_a = abs(n.dot(q.flight.accel));
    B = n_a * q.inv_omega * q.inv_omega;
    nu = n.dot(q.u);
    g_off = n.dot(q.g0 - a);
    tol0 = slack + 8 * eps<Real> * (abs(g_off) + B);
    // |f'| ≤ |nu| + |n·F|/(mω): the band covers f's change over the scan's step floor.
    tol1 = 8 * eps<Real> * (abs(nu) + n_a * q.inv_omega);
  }
  /// The rounding level of f at τ.
  Real tolerance(const Real& tau) const { return tol0 + tol1 * tau; }
  Sample<Real, V> sample(const Real& tau) const {
    const auto [x, v] = q.at(tau);
    return {n.dot(x - a), n.dot(v), n_a, never, x};
  }
  Taylor<Real, V> taylor(const Real& tau) const {
    const auto m = q.motion(tau);
    return {n.dot(m.x - a), n.dot(m.v), n.dot(m.a), m.x, band(tau), m.th, m.sin_th, m.cos_th};
  }
  /// The level below which |f| (as `taylor` gives it) is within the rounding band at τ.
  Real band(const Real& tau) const { return tolerance(tau); }
  /// The rounding of f itself at τ (the band without the walls' slack): a root known to that
  /// level is as good as a polished one.
  Real rounding(const Real& tau) const { return tolerance(tau) - slack; }
  /// A bound on |f'''| = |n·F ω sin θ|/m.
  Real jerk_bound(const Window<Real>&) const { return n_a * q.flight.omega; }
  /// First time ≥ τ at which the guide comes within the margin (B and rounding) of the wall, or
  /// +∞: before it f cannot vanish.
  Real window_start(const Real& tau) const {
    const Real margin = B + tolerance(tau), guide = g_off + nu * tau;
    return guide < 0 ? reach_linear(tau, guide, nu, Real(-margin)) : reach_linear(tau, Real(-guide), Real(-nu), Real(-margin));
  }
  /// When the guide, from the window's start, is twice the margin away (so that the scan leaves
  /// the window for good), or tau_end.
  Real window_end(const Real& start, const Real& tau_end) const {
    using std::min;
    if (nu == 0) return start;
    const Real margin = B + tolerance(start), guide = g_off + nu * start;
    return min(Real(start + ((nu > 0 ? 2 : -2) * margin - guide) / nu), tau_end);
  }
  /// The window until `horizon` (the guide is linear: one at most) into out; returns their
  /// number.
  int windows(const Real& horizon, Window<Real>* out) const {
    using std::abs;
    using std::min;
    if (nu == 0) return clip_window(0, out, Real(0), horizon, Real(B + tolerance(horizon)), false, horizon);
    const Real m = B + tolerance(margin_time(horizon, [&] {
                     return window_horizon(Real(0), Real(abs(g_off) + 2 * B), tol0, tol1, abs(nu));
                   }));
    const Real inv_nu = 1 / nu, from = (-2 * m - g_off) * inv_nu, to = (2 * m - g_off) * inv_nu;  // the guide at ∓2m
    return nu > 0 ? clip_window(0, out, from, to, m, true, horizon) : clip_window(0, out, to, from, m, false, horizon);
  }
  /// +1 when f' > 0 throughout the window (f then crosses zero there at most once, upward), −1
  /// when f' < 0 (no collision), 0 when the bounds cannot tell: f' = nu + n·(F/mω) sin θ.
  int slope_sign(const Window<Real>&) const {
    const Real wobble = n_a * q.inv_omega * (1 + 16 * eps<Real>) + 8 * eps<Real> * q.speed;
    return nu > wobble ? 1 : nu < -wobble ? -1 : 0;
  }
};

/// The same for the circle (2-D) or sphere (3-D) of centre c and radius r, the region inside it
/// when `focusing`: f = ±(|x − c| − r), where |x − c| lies within δ of the guide's distance
/// from c.
template <class Q, class V>
struct SphereGap {
  using Real = typename Q::Real;
  const Q& q;
  V c;
  Real r, sign, slack;
  Real tol0, tol1;  // the rounding level of f at τ is tol0 + tol1 τ

  SphereGap(const Q& q_, const V& c_, const Real& r_, bool focusing, const Real& slack_)
      : q(q_), c(c_), r(r_), sign(focusing ? 1 : -1), slack(slack_),
        // (|x − c|₁ + r bounds |x − c| + r without a square root.)
        tol0(slack + 8 * eps<Real> * ((q.s.x - c).template lpNorm<1>() + r + q.delta)),
        tol1(8 * eps<Real> * q.rounding_rate) {}
  Real tolerance(const Real& tau) const { return tol0 + tol1 * tau; }
  Sample<Real, V> sample(const Real& tau) const {
    const auto [x, v] = q.at(tau);
    const V p = x - c;
    const Real rho = p.norm(), f = sign * (rho - r);
    if (rho < r / 2) {
      // Nearer the centre than the wall, f'' is unbounded (at the centre p̂·v is 0/0), but
      // |f'| ≤ |v|: the Lipschitz bound |f(τ + s) − f(τ)| ≤ |v| s + A s²/2, as a sample moving
      // towards zero at |v| with M = A, steps through safely, ~|f|/|v| at a time.
      const Real speed = v.norm();
      return {f, f < 0 ? speed : Real(-speed), q.accel_norm, never, x};
    }
    // d²|p|/dt² = (|v|² − (p̂·v)²)/|p| + p̂·a ≤ V²/|p| + A; valid while |p| ≥ ρ/2.
    const Real Vb = q.speed_bound;
    return {f, sign * p.dot(v) / rho, 2 * Vb * Vb / rho + q.accel_norm, rho / (2 * Vb), x};
  }
  /// ±(|p|² − r²), free of square roots and divisions (which lengthened each iteration of the
  /// root search by a third): |p|² − r² = (|p| − r)(|p| + r), and |p| − r ≤ tol is certain when
  /// ||p|² − r²| ≤ 2 tol (r − tol).
  Taylor<Real, V> taylor(const Real& tau) const {
    const auto m = q.motion(tau);
    const V p = m.x - c;
    return {sign * (p.squaredNorm() - r * r), 2 * sign * p.dot(m.v), 2 * sign * (m.v.squaredNorm() + p.dot(m.a)), m.x,
            band(tau), m.th, m.sin_th, m.cos_th};
  }
  Real band(const Real& tau) const {
    const Real tol = tolerance(tau);
    return 2 * tol * (r - tol);
  }
  Real rounding(const Real& tau) const { return 2 * r * (tolerance(tau) - slack); }
  /// A bound on the third derivative of ±(|p|² − r²), 2(3 v·a + p·ȧ), in the window w, where
  /// |p| ≤ r + 2m + δ, |v| ≤ V, |a| ≤ A and |ȧ| ≤ Aω.
  Real jerk_bound(const Window<Real>& w) const {
    return 2 * q.accel_norm * (3 * q.speed_bound + (r + 2 * w.margin + q.delta) * q.flight.omega);
  }
  Real window_start(const Real& tau) const {
    using std::max;
    const V g = q.guide(tau) - c;
    const Real margin = q.delta + tolerance(tau);
    return g.squaredNorm() < r * r ? reach_radius(tau, g, q.u, max(Real(0), Real(r - margin)), true)
                                   : reach_radius(tau, g, q.u, Real(r + margin), false);
  }
  Real window_end(const Real& start, const Real& tau_end) const {
    using std::max;
    using std::min;
    const V g = q.guide(start) - c;
    const Real margin = q.delta + tolerance(start);
    return min({reach_radius(start, g, q.u, Real(r + 2 * margin), true),
                reach_radius(start, g, q.u, max(Real(0), Real(r - 2 * margin)), false), tau_end});
  }
  /// The windows until `horizon` into out; returns their number.  The guide's distance from c
  /// is convex in τ: the guide is within r ± 2m of c in one interval, or in two when it
  /// passes inside r − 2m.
  int windows(const Real& horizon, Window<Real>* out) const {
    using std::max;
    using std::min;
    using std::sqrt;
    const V q0 = q.g0 - c;
    const Real b = q0.dot(q.u), cc = q0.squaredNorm(), uu = q.uu;
    if (!(uu > 0)) return clip_window(0, out, Real(0), horizon, Real(q.delta + tolerance(horizon)), false, horizon);
    // Most walls are out of reach: the guide misses the sphere, or moves away from it, even
    // with the margin at the horizon (no smaller than any margin below).
    const Real reach = r + 2 * (q.delta + tolerance(horizon)), k_reach = cc - reach * reach;
    if (k_reach > 0 && (b >= 0 || b * b < uu * k_reach)) return 0;
    const Real m = q.delta + tolerance(margin_time(horizon, [&] {
                     return window_horizon(Real(-b * q.inv_uu), Real(r + 2 * q.delta), tol0, tol1, q.speed);
                   }));
    // Times at which the guide is at distance ρ from c: the roots of uu τ² + 2bτ + cc − ρ²,
    // each from its stable form; false when it never is.
    auto at_distance = [&](const Real& rho, Real& t1, Real& t2) {
      const Real k = cc - rho * rho, D = b * b - uu * k;
      if (!(D >= 0)) return false;
      const Real root = sqrt(D);
      if (b <= 0) {
        t2 = (root - b) * q.inv_uu;
        t1 = root - b > 0 ? Real(k / (root - b)) : Real(0);  // (0/0 for a tangent at τ = 0)
      } else {
        t1 = -(b + root) * q.inv_uu;
        t2 = -k / (b + root);
      }
      return true;
    };
    Real t1, t2, t3, t4;
    if (!at_distance(Real(r + 2 * m), t1, t2)) return 0;
    const bool outside_is_below = sign < 0;  // beyond a dispersing circle's wall is its inside
    const Real inner = r - 2 * m;
    if (!(inner > 0) || !at_distance(inner, t3, t4))
      return clip_window(0, out, t1, t2, m, outside_is_below, horizon);
    const int n = clip_window(0, out, t1, t3, m, outside_is_below, horizon);
    return clip_window(n, out, t4, t2, m, !outside_is_below, horizon);
  }
  /// f' = ±p̂·v.  In the window the guide q stays within 2 margins m of the sphere, p = q + o
  /// with |o| ≤ δ, and v = u + w with |w| ≤ |F|/(mω); so |p̂·v − q̂·u| ≤ |F|/(mω) + 2δ V/|p|,
  /// and q̂·u = (q·u)/|q|, whose numerator grows linearly in τ, is bounded by its values at the
  /// window's ends.
  int slope_sign(const Window<Real>& w) const {
    using std::isfinite;
    const Real m2 = 2 * w.margin, inner = r - m2, outer = r + m2;
    if (!isfinite(w.end) || !(inner - q.delta > 0)) return 0;
    const V q0 = q.g0 - c;
    const Real qu0 = q0.dot(q.u);
    const Real qs = qu0 + q.uu * w.start, qe = qu0 + q.uu * w.end;
    const Real wobble = q.accel_norm * q.inv_omega + 2 * q.delta * q.speed_bound / (inner - q.delta);
    // q̂·u > wobble throughout (outward) when qs/|q| > wobble, as |q| ≤ outer; < −wobble
    // (inward) likewise at the end; compared without dividing, with the rounding of q·u.
    const Real threshold = wobble * outer + 16 * eps<Real> * (q0.template lpNorm<1>() * q.u.template lpNorm<1>() +
                                                               q.uu * w.end + q.speed_bound * outer);
    const bool outward = qs > threshold, inward = qe < -threshold;
    return sign > 0 ? (outward ? 1 : inward ? -1 : 0) : (inward ? 1 : outward ? -1 : 0);
  }
};

/// A root search that could not decide (see `monotone_crossing`).
inline constexpr double undecided = -1;

/// Is |f(τ + h)| certainly below `level`, h a step of the root search from the sample p at τ?
/// Then the sample at τ + h, which would cost a sine and a cosine, is not needed: f(τ + h) lies
/// within J|h|³/6 of the quadratic model f + f'h + f''h²/2 (J bounds |f'''|), and after a
/// Halley step close to the root both are at the rounding of f.
template <class S, class Real>
bool certainly_below(const S& p, const Real& h, const Real& jerk, const Real& level) {
  using std::abs;
  const Real model = p.f + h * (p.df + h / 2 * p.d2f);
  const Real rounding = 8 * eps<Real> * (abs(p.f) + abs(h * p.df) + abs(h * h * p.d2f));
  return abs(model) + jerk * abs(h * h * h) / 6 + rounding <= level;
}

/// The collision in a window w where f' > 0 throughout (slope_sign = +1): f crosses zero there
/// at most once, so Halley's iteration kept inside a bracket finds it without any risk of
/// passing an earlier root (cubic convergence: ~2 samples where the certified scan, whose steps
/// converge like Newton's, takes ~4).  A step that lands where f is certainly at its own
/// rounding (`certainly_below`: as close to the root as a polished sample) is the root without
/// a sample there; the drive's phase there comes from the last sample's (PhaseSample::shifted).
/// `w.below`: f(start) < 0 is known (the guide entered the window from f's negative side) and
/// start need not be sampled.  Returns the root, +∞ when f does not cross zero in the window or
/// crosses outside the wall's span, or `undecided` when the iteration stalls; `*phase` keeps
/// the drive's phase at the root.
template <class Gap, class InSpan, class Real>
Real monotone_crossing(const Gap& g, InSpan in_span, const Window<Real>& w, PhaseSample<Real>& phase) {
  using std::abs;
  const Real start = w.start, end = w.end;
  Real lo = start, hi = end;  // f(lo) < 0; f(hi) > 0 once `bracketed`
  bool bracketed = false;
  const Real jerk = g.jerk_bound(w);
  // The window runs from the guide at −2m to the guide at +2m: it crosses about half way.
  Real tau = w.below ? Real(start + (end - start) / 2) : start;
  for (int k = 0; k < 100; ++k) {
    const auto p = g.taylor(tau);
    const Real tol = p.tol;
    if (abs(p.f) <= tol) {
      if (!(p.df > 0)) return undecided;  // (f' > 0 was certified: only rounding could do this)
      if (!in_span(p.x)) return never;
      phase = {p.th, p.sin_th, p.cos_th};
      return polished_root(tau, p, tol);
    }
    if (p.f < 0) {
      if (tau >= end) return never;  // still below at the end of the window
      lo = tau;
    } else {
      if (tau == start) return never;  // above from the start, and rising
      hi = tau;
      bracketed = true;
    }
    const Real halley = 2 * p.df * p.df - p.f * p.d2f;
    Real next = p.df > 0 && halley > 0 ? Real(tau - 2 * p.f * p.df / halley) : lo;
    if (!(next > lo && next < hi)) next = bracketed ? Real(lo + (hi - lo) / 2) : hi;  // hi = end until bracketed
    if (next == tau) return undecided;
    if (certainly_below(p, Real(next - tau), jerk, g.rounding(next))) {
      const Real th = g.q.phase_at(next), h = th - p.th;
      if (abs(h) <= Real(PhaseSample<Real>::h_max)) {
        const auto [sn, cs] = PhaseSample<Real>{p.th, p.sin_th, p.cos_th}.shifted(h);
        if (!in_span(g.q.position(next, cs))) return never;
        phase = {th, sn, cs};
        return next;
      }
    }
    tau = next;
  }
  return undecided;
}

/// The first collision with one wall in its window [start, end], given the sign of f' there
/// (`slope_sign`): +∞ when f' < 0 throughout, the monotone search when f' > 0 throughout (which
/// keeps the drive's phase there in `*phase`), else the certified scan of the window.
template <class Gap, class InSpan, class Real>
Real crossing_in_window(const Gap& g, InSpan in_span, const Window<Real>& w, int slope, PhaseSample<Real>& phase) {
  if (slope < 0) return never;
  if (slope > 0) {
    const Real tau = monotone_crossing(g, in_span, w, phase);
    if (tau != undecided) return tau;
  }
  auto sample = [&](const Real& tau) { return g.sample(tau); };
  auto tolerance = [&](const Real& tau) { return g.tolerance(tau); };
  auto earliest = [&](const Real& tau) { return tau < w.start ? w.start : tau; };
  return first_outward_crossing(sample, earliest, in_span, tolerance, w.end);
}

/// Tables of more walls than this are searched wall by wall (see DrivenScan::first_hit).
inline constexpr int windows_in_time_order_walls = 24;

/// The first collision of a driven flight with any of `walls` walls before τ = tau_best:
/// tau_best, best_wall and `phase` (the drive's phase at the root, when the monotone search
/// found it) are updated.  Every wall's windows until then are computed in closed form and
/// searched in the order in which they open, so the search stops at the first window that
/// opens after the best collision found and the walls beyond it are never sampled.
/// `visit(w, fn)` calls fn(gap, passes, in_span) for wall w: its gap (PlaneGap or SphereGap),
/// passes(start, end), true when the particle cannot reach the wall's span in the window, and
/// the span test in_span(x).  Not for creeping flights (see `creep`), whose gaps these are.
template <class Real, class Visit>
void first_hit_in_windows(int walls, Visit visit, Real& tau_best, int& best_wall, PhaseSample<Real>& phase) {
  using std::min;
  // The windows as they are found (uninitialized storage), and their order of opening sorted
  // by insertion, stable: cheaper than swapping the windows themselves.
  if (walls > windows_in_time_order_walls) throw std::logic_error("first_hit_in_windows: too many walls");
  Window<Real> windows[2 * windows_in_time_order_walls];
  unsigned char order[2 * windows_in_time_order_walls];
  int count = 0;
  for (int w = 0; w < walls; ++w)
    visit(w, [&](const auto& gap, const auto&, const auto&) {
      for (int n = count + gap.windows(tau_best, windows + count); count < n; ++count) {
        windows[count].wall = w;
        int i = count;
        for (; i > 0 && windows[order[i - 1]].start > windows[count].start; --i) order[i] = order[i - 1];
        order[i] = static_cast<unsigned char>(count);
      }
    });
  for (int k = 0; k < count && windows[order[k]].start <= tau_best; ++k)
    visit(windows[order[k]].wall, [&](const auto& gap, const auto& passes, const auto& in_span) {
      auto window = windows[order[k]];
      window.end = min(window.end, tau_best);
      // The sign of f' first: it rules out the window the flight leaves its last wall through
      // (one a flight) at half the cost of the span test.
      const int slope = gap.slope_sign(window);
      if (slope < 0 || passes(window.start, window.end)) return;
      PhaseSample<Real> sampled;
      const Real tau = crossing_in_window(gap, in_span, window, slope, sampled);
      if (tau < tau_best) {
        tau_best = tau;
        best_wall = window.wall;
        phase = sampled;
      }
    });
}

/// The scan of a driven flight through one wall (`first_outward_crossing` of the gap g) whose
/// `earliest` passes the windows it can (`first_window`) and, for a creeping flight, lets
/// `creep`'s jumps and the windows take turns until neither moves on.  `passes(τ, end)` may
/// declare a window [τ, end] free of collisions (the wall's span is out of reach) and
/// `clearance(τ)` bounds the distance of the oscillation segment from the wall within its span
/// from below (see `creep`), or is NotCreeping (see `with_creep`).  +∞ if no collision.
template <class Q, class Gap, class Passes, class InSpan, class Clearance, class Real>
[[gnu::always_inline]] inline Real scan_windows(const Q& q, const Gap& g, Passes passes, InSpan in_span,
                                                Clearance clearance, const Real& tau_end) {
  auto sample = [&](const Real& tau) { return g.sample(tau); };
  auto tolerance = [&](const Real& tau) { return g.tolerance(tau); };
  auto window_start = [&](const Real& tau) { return g.window_start(tau); };
  auto window_end = [&](const Real& start) { return g.window_end(start, tau_end); };
  Real sampled_until = -1;
  auto earliest = [&](const Real& tau) {
    Real t = first_window(tau, tau_end, window_start, window_end, passes, sampled_until);
    if constexpr (!std::is_same_v<Clearance, NotCreeping>) {
      for (;;) {  // jumps and windows in turn, until neither moves on
        const Real next = creep(q, t, tau_end, clearance, tolerance);
        if (next == t || next == never) return next;
        t = first_window(next, tau_end, window_start, window_end, passes, sampled_until);
      }
    }
    return t;
  };
  return first_outward_crossing<!std::is_same_v<Clearance, NotCreeping>>(sample, earliest, in_span, tolerance, tau_end);
}

/// First τ ≤ tau_end at which the driven flight `q` crosses the line (2-D) or plane (3-D)
/// through `a` with outward unit normal `n` outward, at a point where `in_span`; +∞ if none.
template <class Q, class V, class Real, class Passes, class InSpan, class Clearance>
Real driven_exit_through_plane(const Q& q, const V& n, const V& a, const Real& slack, const Real& tau_end,
                               Passes passes, InSpan in_span, Clearance clearance) {
  return scan_windows(q, PlaneGap<Q, V>(q, n, a, slack), passes, in_span, clearance, tau_end);
}

/// The same through the circle (2-D) or sphere (3-D) of centre c and radius r, the region
/// inside it when `focusing`.
template <class Q, class V, class Real, class Passes, class InSpan, class Clearance>
Real driven_exit_through_sphere(const Q& q, const V& c, const Real& r, bool focusing, const Real& slack,
                                const Real& tau_end, Passes passes, InSpan in_span, Clearance clearance) {
  return scan_windows(q, SphereGap<Q, V>(q, c, r, focusing, slack), passes, in_span, clearance, tau_end);
}

}  // namespace billiards::dynamics::scan
