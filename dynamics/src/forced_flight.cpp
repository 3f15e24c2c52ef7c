#include "billiards/dynamics/forced_flight.hpp"

#include "billiards/dynamics/precision.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <tuple>

namespace billiards::dynamics {

namespace {

template <class Real>
const Real eps = std::numeric_limits<Real>::epsilon();

/// f and f' at one time of the scan, with what bounds f'' until the next sample.
template <class Real>
struct Sample {
  Real f, df;      // how far beyond the wall, and its rate
  Real M;          // bound on |f''| over the next `cap` time units
  Real cap;        // longest step for which M holds
  Vec2T<Real> x;   // position
};

/// First τ in [0, tau_end] at which f crosses zero upward at a point in the wall's span.
/// `sample(τ)` evaluates f; `earliest(τ, f)` returns a time before which f cannot vanish
/// (from the guiding line and the bounded oscillation), or +∞; `tolerance(τ)` is the rounding
/// level of f at τ.
template <class Real, class SampleFn, class EarliestFn, class SpanFn, class TolFn>
Real first_outward_crossing(SampleFn sample, EarliestFn earliest, SpanFn in_span, TolFn tolerance,
                            const Real& tau_end) {
  using std::abs;
  using std::max;
  using std::min;
  using std::sqrt;
  constexpr int max_steps = 1000000;
  Real tau = 0;
  for (int step = 0; step < max_steps; ++step) {
    if (tau > tau_end || tau == never) return never;  // (τ = ∞: no window ahead, with no horizon)
    const Sample<Real> p = sample(tau);
    const Real tol = tolerance(tau);
    Real s;
    if (abs(p.f) <= tol) {
      // At the wall to rounding: an outward crossing in the span is the collision.  A touch,
      // an inward crossing or a crossing outside the span is passed by the time f needs to
      // change by tol (a skipped crossing would be no deeper than rounding: a graze).
      // One Newton step polishes the root from |f| ≤ tol (rounding of the walls, ~1e-13) to
      // the rounding of f itself, so the collision time does not depend on where the scan
      // happened to enter the tolerance band; the step stays inside that band.
      if (p.df > 0 && in_span(p.x))
        return max(Real(0), Real(tau - std::clamp(Real(p.f / p.df), Real(-tol / p.df), Real(tol / p.df))));
      s = 2 * tol / (abs(p.df) + sqrt(2 * p.M * tol));
    } else {
      // Earliest zero allowed by |f''| ≤ M: the positive root of |f| − σ f' s − M s²/2.
      const Real a = abs(p.f), slope = p.f < 0 ? p.df : Real(-p.df);
      const Real quadratic = p.M > 0 ? Real(2 * a / (slope + sqrt(slope * slope + 2 * p.M * a)))
                                     : (slope > 0 ? Real(a / slope) : Real(never));
      s = max(min(quadratic, p.cap), Real(earliest(tau, p.f) - tau));
    }
    // Keep a floor so that τ advances in floating point; it is far below any physical time.
    tau += max(s, Real(4 * eps<Real> * max(tau, Real(1e-300))));
  }
  throw std::runtime_error("certified root isolation did not converge in a million steps");
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
template <class Real>
Real reach_radius(const Real& tau0, const Vec2T<Real>& q0, const Vec2T<Real>& u, const Real& rho, bool outward) {
  using std::sqrt;
  const Real a = u.squaredNorm(), b = q0.dot(u), c = q0.squaredNorm() - rho * rho;
  if (outward ? c >= 0 : c <= 0) return tau0;
  if (a == 0) return never;
  const Real D = b * b - a * c;
  if (D < 0) return never;  // the guiding line misses the circle of radius ρ
  const Real root = sqrt(D);
  if (outward) return tau0 + (b <= 0 ? Real((root - b) / a) : Real(-c / (b + root)));  // larger root
  if (b >= 0) return never;                                                            // moving away
  return tau0 + c / (root - b);                                                        // smaller root
}

/// Can a point within `pad` of the segment [p, q] lie in the wall's span?  The span is an
/// intersection (or, for arcs longer than a half circle, a union) of half-planes, whose linear
/// functions take their extremes over [p, q] at p or q; false only when certainly not.
template <class Real>
bool may_meet_span(const BasicSegmentWall<Real>& w, const Vec2T<Real>& p, const Vec2T<Real>& q, const Real& pad) {
  using std::abs;
  using std::max;
  using std::min;
  const Real sp = (p - w.a).dot(w.dir), sq = (q - w.a).dot(w.dir);
  const Real margin = (w.slack + pad) * w.dir.norm() + 8 * eps<Real> * (1 + abs(sp) + abs(sq));
  return max(sp, sq) >= -margin && min(sp, sq) <= 1 + margin;
}

template <class Real>
bool may_meet_span(const BasicArcWall<Real>& w, const Vec2T<Real>& p, const Vec2T<Real>& q, const Real& pad) {
  using std::max;
  using std::min;
  if (w.full) return true;
  const Vec2T<Real> a = p - w.center, b = q - w.center;
  const Real margin = w.radius * (w.slack + pad) + 16 * eps<Real> * w.radius * (a.norm() + b.norm());
  if (w.ccw_extent <= geometry::pi)
    return max(cross(w.from, a), cross(w.from, b)) >= -margin && max(cross(a, w.to), cross(b, w.to)) >= -margin;
  return !(min(cross(w.to, a), cross(w.to, b)) > margin && min(cross(a, w.from), cross(b, w.from)) > margin);
}

/// The periodic flight from s as a guiding line plus an oscillation of amplitude |F|/(mω²):
/// x(τ) = g0 + u τ − (F/mω²) cos θ(τ).
template <class Real>
struct Quiver {
  using V = Vec2T<Real>;
  const BasicPeriodicDriveFlight<Real>& flight;
  const BasicDrivenState<Real>& s;
  V u, g0;
  Real speed_bound;  // bound on |v| at any time of this flight

  Quiver(const BasicPeriodicDriveFlight<Real>& f, const BasicDrivenState<Real>& st) : flight(f), s(st) {
    const V amp_x = f.accel / (f.omega * f.omega);
    u = st.v - f.accel / f.omega * st.sin_phase;
    g0 = st.x + amp_x * st.cos_phase;
    speed_bound = u.norm() + f.accel.norm() / f.omega;
  }
  V guide(const Real& tau) const { return g0 + u * tau; }
  /// Position and velocity τ after the start (the closed form of advance()).  Within one
  /// flight ωτ stays moderate, so a phase in Real is accurate to ~1e-12 rad in double, which
  /// moves the particle by 1e-12 |F|/(mω²): no extended-precision reduction is needed here.
  std::pair<V, V> at(const Real& tau) const {
    using std::cos;
    using std::sin;
    if (tau == 0) return {s.x, s.v};
    const Real omega = flight.omega, th = Real(s.phase) + omega * tau;
    return {g0 + u * tau - flight.accel / (omega * omega) * Real(cos(th)), u + flight.accel / omega * Real(sin(th))};
  }
};

}  // namespace

// ---- Periodic drive ---------------------------------------------------------------------

template <class Real>
auto BasicPeriodicDriveFlight<Real>::start(const BasicState<Real>& s) const -> State {
  using P = PhaseOf<Real>;
  State d;
  static_cast<BasicState<Real>&>(d) = s;
  d.set_phase(P(omega) * P(s.t) + P(phase0));
  return d;
}

template <class Real>
auto BasicPeriodicDriveFlight<Real>::advance(const State& s, const Real& t) const -> State {
  using P = PhaseOf<Real>;
  const Real tau = t - s.t;
  State r = s;
  r.set_phase(s.phase + P(omega) * P(tau));
  const Vec2T<Real> amp_v = accel / omega, amp_x = accel / (omega * omega);
  r.v = s.v + amp_v * Real(r.sin_phase - s.sin_phase);
  r.x = s.x + (s.v - amp_v * s.sin_phase) * tau - amp_x * Real(r.cos_phase - s.cos_phase);
  r.t = t;
  return r;
}

template <class Real>
Real BasicPeriodicDriveFlight<Real>::exit_time(const State& s, const BasicSegmentWall<Real>& w,
                                               const Real& t_end) const {
  using std::abs;
  using V = Vec2T<Real>;
  const Quiver<Real> q(*this, s);
  const Real n_a = abs(w.normal.dot(accel));
  const Real B = n_a / (omega * omega);  // |n·oscillation| ≤ B
  const Real nu = w.normal.dot(q.u), g_off = w.normal.dot(q.g0 - w.a);
  auto tolerance = [&](const Real& tau) { return Real(w.slack + 8 * eps<Real> * (abs(g_off) + abs(nu) * tau + B)); };
  auto sample = [&](const Real& tau) {
    const auto [x, v] = q.at(tau);
    return Sample<Real>{w.normal.dot(x - w.a), w.normal.dot(v), n_a, never, x};
  };
  // f lies within B of its guiding part g_off + nu τ, which must first come within B (and
  // rounding) of zero.  While it is that close (the window, widened to twice the margin so
  // that the scan leaves it for good), a crossing counts only if the particle, within δ of the
  // guiding point, can be in the segment's span; if it cannot, the whole window is passed.
  const Real delta = accel.norm() / (omega * omega);
  auto earliest = [&](const Real& tau, const Real& f) {
    using std::min;
    const Real margin = B + tolerance(tau), guide = g_off + nu * tau;
    const Real start = f < 0 ? reach_linear(tau, guide, nu, Real(-margin))
                             : reach_linear(tau, Real(-guide), Real(-nu), Real(-margin));
    if (start > tau || nu == 0) return start;
    const Real end = min(Real(tau + ((nu > 0 ? 2 : -2) * margin - guide) / nu), Real(t_end - s.t));
    return end > tau && !may_meet_span(w, q.guide(tau), q.guide(end), delta) ? end : tau;
  };
  auto in_span = [&](const V& x) { return w.within_span(x); };
  const Real tau = first_outward_crossing(sample, earliest, in_span, tolerance, Real(t_end - s.t));
  return tau == never ? Real(never) : Real(s.t + tau);
}

template <class Real>
Real BasicPeriodicDriveFlight<Real>::exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const {
  using std::max;
  using V = Vec2T<Real>;
  const Quiver<Real> q(*this, s);
  const Real delta = accel.norm() / (omega * omega);  // |oscillation| ≤ δ
  const Real sign = w.focusing ? 1 : -1;               // f = ±(|x − c| − r): beyond the wall
  const Real Vb = q.speed_bound, A = accel.norm();
  const Real scale = (s.x - w.center).norm() + w.radius;
  auto tolerance = [&](const Real& tau) { return Real(w.slack + 8 * eps<Real> * (scale + Vb * tau + delta)); };
  auto sample = [&](const Real& tau) {
    const auto [x, v] = q.at(tau);
    const V p = x - w.center;
    const Real rho = p.norm();
    // d²|p|/dt² = (|v|² − (p̂·v)²)/|p| + p̂·a ≤ V²/|p| + A; valid while |p| ≥ ρ/2.
    const Real M = 2 * Vb * Vb / max(rho, Real(1e-300)) + A;
    return Sample<Real>{sign * (rho - w.radius), sign * p.dot(v) / rho, M, rho / (2 * Vb), x};
  };
  // |x − c| lies within δ of the guiding line's distance to the centre, which must first come
  // within δ (and rounding) of the radius.
  auto earliest = [&](const Real& tau, const Real& f) {
    using std::min;
    const V g = q.g0 + q.u * tau - w.center;
    const Real margin = delta + tolerance(tau);
    const bool inside = (f < 0) == w.focusing;  // inside the circle, to rounding
    const Real start = inside ? reach_radius(tau, g, q.u, max(Real(0), Real(w.radius - margin)), true)
                              : reach_radius(tau, g, q.u, Real(w.radius + margin), false);
    if (start > tau) return start;
    // In the window (see the segment's case), until the guiding point is twice the margin off.
    const Real end = min({reach_radius(tau, g, q.u, Real(w.radius + 2 * margin), true),
                          reach_radius(tau, g, q.u, max(Real(0), Real(w.radius - 2 * margin)), false),
                          Real(t_end - s.t)});
    return end > tau && !may_meet_span(w, q.guide(tau), q.guide(end), delta) ? end : tau;
  };
  auto in_span = [&](const V& x) { return w.within_span(x); };
  const Real tau = first_outward_crossing(sample, earliest, in_span, tolerance, Real(t_end - s.t));
  return tau == never ? Real(never) : Real(s.t + tau);
}

// ---- Static force ----------------------------------------------------------------------

namespace {

/// Position and velocity τ after s, evaluated in τ (not in absolute time, whose rounding at
/// large t would swallow the last steps of the scan).
template <class Real>
std::pair<Vec2T<Real>, Vec2T<Real>> parabola(const BasicState<Real>& s, const Vec2T<Real>& accel, const Real& tau) {
  return {s.x + s.v * tau + Real(0.5) * accel * tau * tau, s.v + accel * tau};
}

}  // namespace

template <class Real>
auto BasicConstantForceFlight<Real>::advance(const State& s, const Real& t) const -> State {
  State r = s;
  std::tie(r.x, r.v) = parabola(s, accel, Real(t - s.t));
  r.t = t;
  return r;
}

template <class Real>
Real BasicConstantForceFlight<Real>::exit_time(const State& s, const BasicSegmentWall<Real>& w,
                                               const Real& t_end) const {
  using std::abs;
  const Real n_a = w.normal.dot(accel);
  const Real f0 = abs(w.normal.dot(s.x - w.a));
  auto tolerance = [&](const Real& tau) {
    return Real(w.slack + 8 * eps<Real> * (f0 + s.v.norm() * tau + abs(n_a) * tau * tau));
  };
  auto sample = [&](const Real& tau) {
    const auto [x, v] = parabola(s, accel, tau);
    return Sample<Real>{w.normal.dot(x - w.a), w.normal.dot(v), abs(n_a), never, x};
  };
  auto earliest = [](const Real& tau, const Real&) { return tau; };
  auto in_span = [&](const Vec2T<Real>& x) { return w.within_span(x); };
  const Real tau = first_outward_crossing(sample, earliest, in_span, tolerance, Real(t_end - s.t));
  return tau == never ? Real(never) : Real(s.t + tau);
}

template <class Real>
Real BasicConstantForceFlight<Real>::exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const {
  using std::max;
  const Real sign = w.focusing ? 1 : -1;
  const Real A = accel.norm();
  const Real scale = (s.x - w.center).norm() + w.radius;
  auto tolerance = [&](const Real& tau) {
    return Real(w.slack + 8 * eps<Real> * (scale + s.v.norm() * tau + A * tau * tau));
  };
  auto sample = [&](const Real& tau) {
    const auto [x, v] = parabola(s, accel, tau);
    const Vec2T<Real> p = x - w.center;
    const Real rho = p.norm(), V = v.norm();
    // Over a step of length h ≤ ρ/(2V'), |v| ≤ V' = V + A h and |p| ≥ ρ/2.
    const Real h = rho / (2 * (V + A) + Real(1e-300));
    const Real Vmax = V + A * h;
    return Sample<Real>{sign * (rho - w.radius), sign * p.dot(v) / rho, 2 * Vmax * Vmax / max(rho, Real(1e-300)) + A,
                        h, x};
  };
  auto earliest = [](const Real& tau, const Real&) { return tau; };
  auto in_span = [&](const Vec2T<Real>& x) { return w.within_span(x); };
  const Real tau = first_outward_crossing(sample, earliest, in_span, tolerance, Real(t_end - s.t));
  return tau == never ? Real(never) : Real(s.t + tau);
}

template struct BasicPeriodicDriveFlight<double>;
template struct BasicPeriodicDriveFlight<long double>;
template struct BasicPeriodicDriveFlight<Reference>;
template struct BasicConstantForceFlight<double>;
template struct BasicConstantForceFlight<long double>;
template struct BasicConstantForceFlight<Reference>;

}  // namespace billiards::dynamics
