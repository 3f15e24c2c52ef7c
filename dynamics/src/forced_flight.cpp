#include "billiards/dynamics/forced_flight.hpp"

#include <algorithm>
#include <tuple>
#include <limits>
#include <stdexcept>

namespace billiards::dynamics {

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

/// f and f' at one time of the scan, with what bounds f'' until the next sample.
struct Sample {
  double f, df;  // how far beyond the wall, and its rate
  double M;      // bound on |f''| over the next `cap` time units
  double cap;    // longest step for which M holds
  Vec2 x;        // position
};

/// First τ in [0, tau_end] at which f crosses zero upward at a point in the wall's span.
/// `sample(τ)` evaluates f; `earliest(τ, f)` returns a time before which f cannot vanish
/// (from the guiding line and the bounded oscillation), or +∞; `tolerance(τ)` is the rounding
/// level of f at τ.
template <class SampleFn, class EarliestFn, class SpanFn, class TolFn>
double first_outward_crossing(SampleFn sample, EarliestFn earliest, SpanFn in_span, TolFn tolerance,
                              double tau_end) {
  constexpr int max_steps = 1000000;
  double tau = 0;
  for (int step = 0; step < max_steps; ++step) {
    if (tau > tau_end) return never;
    const Sample p = sample(tau);
    const double tol = tolerance(tau);
    double s;
    if (std::abs(p.f) <= tol) {
      // At the wall to rounding: an outward crossing in the span is the collision.  A touch,
      // an inward crossing or a crossing outside the span is passed by the time f needs to
      // change by tol (a skipped crossing would be no deeper than rounding: a graze).
      // One Newton step polishes the root from |f| ≤ tol (rounding of the walls, ~1e-13) to
      // the rounding of f itself, so the collision time does not depend on where the scan
      // happened to enter the tolerance band; the step stays inside that band.
      if (p.df > 0 && in_span(p.x)) return std::max(0.0, tau - std::clamp(p.f / p.df, -tol / p.df, tol / p.df));
      s = 2 * tol / (std::abs(p.df) + std::sqrt(2 * p.M * tol));
    } else {
      // Earliest zero allowed by |f''| ≤ M: the positive root of |f| − σ f' s − M s²/2.
      const double a = std::abs(p.f), slope = p.f < 0 ? p.df : -p.df;
      const double quadratic =
          p.M > 0 ? 2 * a / (slope + std::sqrt(slope * slope + 2 * p.M * a)) : (slope > 0 ? a / slope : never);
      s = std::max(std::min(quadratic, p.cap), earliest(tau, p.f) - tau);
    }
    // Keep a floor so that τ advances in floating point; it is far below any physical time.
    tau += std::max(s, 4 * eps * std::max(tau, 1e-300));
  }
  throw std::runtime_error("certified root isolation did not converge in a million steps");
}

/// Time, from τ0, at which the linear function ℓ(τ) = l0 + l1 (τ − τ0) first reaches level L
/// from below (ℓ(τ0) < L), or +∞.
double reach_linear(double tau0, double l0, double l1, double level) {
  if (l0 >= level) return tau0;
  return l1 > 0 ? tau0 + (level - l0) / l1 : never;
}

/// First τ ≥ τ0 at which |q0 + u (τ − τ0)|² crosses ρ², going outward (from inside) when
/// `outward`, inward otherwise; τ0 itself when already on that side, +∞ when never.
double reach_radius(double tau0, const Vec2& q0, const Vec2& u, double rho, bool outward) {
  const double a = u.squaredNorm(), b = q0.dot(u), c = q0.squaredNorm() - rho * rho;
  if (outward ? c >= 0 : c <= 0) return tau0;
  if (a == 0) return never;
  const double D = b * b - a * c;
  if (D < 0) return never;  // the guiding line misses the circle of radius ρ
  const double root = std::sqrt(D);
  if (outward) return tau0 + (b <= 0 ? (root - b) / a : -c / (b + root));  // larger root
  if (b >= 0) return never;                                                // moving away
  return tau0 + c / (root - b);                                            // smaller root
}

/// Can a point within `pad` of the segment [p, q] lie in the wall's span?  The span is an
/// intersection (or, for arcs longer than a half circle, a union) of half-planes, whose linear
/// functions take their extremes over [p, q] at p or q; false only when certainly not.
bool may_meet_span(const SegmentWall& w, const Vec2& p, const Vec2& q, double pad) {
  const double sp = (p - w.a).dot(w.dir), sq = (q - w.a).dot(w.dir);
  const double margin = (w.slack + pad) * w.dir.norm() + 8 * eps * (1 + std::abs(sp) + std::abs(sq));
  return std::max(sp, sq) >= -margin && std::min(sp, sq) <= 1 + margin;
}

bool may_meet_span(const ArcWall& w, const Vec2& p, const Vec2& q, double pad) {
  if (w.full) return true;
  const Vec2 a = p - w.center, b = q - w.center;
  const double margin = w.radius * (w.slack + pad) + 16 * eps * w.radius * (a.norm() + b.norm());
  if (w.ccw_extent <= geometry::pi)
    return std::max(cross(w.from, a), cross(w.from, b)) >= -margin && std::max(cross(a, w.to), cross(b, w.to)) >= -margin;
  return !(std::min(cross(w.to, a), cross(w.to, b)) > margin && std::min(cross(a, w.from), cross(b, w.from)) > margin);
}

}  // namespace

// ---- Periodic drive ---------------------------------------------------------------------

void DrivenState::set_phase(long double theta) {
  phase = reduce_phase(theta);
  sin_phase = std::sin(double(phase));
  cos_phase = std::cos(double(phase));
}

DrivenState PeriodicDriveFlight::start(const dynamics::State& s) const {
  DrivenState d;
  static_cast<dynamics::State&>(d) = s;
  d.set_phase(static_cast<long double>(omega) * s.t + phase0);
  return d;
}

DrivenState PeriodicDriveFlight::advance(const State& s, double t) const {
  const double tau = t - s.t;
  State r = s;
  r.set_phase(s.phase + static_cast<long double>(omega) * tau);
  const Vec2 amp_v = accel / omega, amp_x = accel / (omega * omega);
  r.v = s.v + amp_v * (r.sin_phase - s.sin_phase);
  r.x = s.x + (s.v - amp_v * s.sin_phase) * tau - amp_x * (r.cos_phase - s.cos_phase);
  r.t = t;
  return r;
}

namespace {

/// The periodic flight from s as a guiding line plus an oscillation of amplitude |F|/(mω²):
/// x(τ) = g0 + u τ − (F/mω²) cos θ(τ).
struct Quiver {
  const PeriodicDriveFlight& flight;
  const DrivenState& s;
  Vec2 u, g0;
  double speed_bound;  // bound on |v| at any time of this flight

  Quiver(const PeriodicDriveFlight& f, const DrivenState& st) : flight(f), s(st) {
    const Vec2 amp_x = f.accel / (f.omega * f.omega);
    u = st.v - f.accel / f.omega * st.sin_phase;
    g0 = st.x + amp_x * st.cos_phase;
    speed_bound = u.norm() + f.accel.norm() / f.omega;
  }
  Vec2 guide(double tau) const { return g0 + u * tau; }
  /// Position and velocity τ after the start (the closed form of advance()).  Within one
  /// flight ωτ stays moderate, so a double phase is accurate to ~1e-12 rad, which moves the
  /// particle by 1e-12 |F|/(mω²): no extended-precision reduction is needed here.
  std::pair<Vec2, Vec2> at(double tau) const {
    if (tau == 0) return {s.x, s.v};
    const double omega = flight.omega, th = double(s.phase) + omega * tau;
    return {g0 + u * tau - flight.accel / (omega * omega) * std::cos(th), u + flight.accel / omega * std::sin(th)};
  }
};

}  // namespace

double PeriodicDriveFlight::exit_time(const State& s, const SegmentWall& w, double t_end) const {
  const Quiver q(*this, s);
  const double n_a = std::abs(w.normal.dot(accel));
  const double B = n_a / (omega * omega);  // |n·oscillation| ≤ B
  const double nu = w.normal.dot(q.u), g_off = w.normal.dot(q.g0 - w.a);
  auto tolerance = [&](double tau) { return w.slack + 8 * eps * (std::abs(g_off) + std::abs(nu) * tau + B); };
  auto sample = [&](double tau) {
    const auto [x, v] = q.at(tau);
    return Sample{w.normal.dot(x - w.a), w.normal.dot(v), n_a, never, x};
  };
  // f lies within B of its guiding part g_off + nu τ, which must first come within B (and
  // rounding) of zero.  While it is that close (the window, widened to twice the margin so
  // that the scan leaves it for good), a crossing counts only if the particle, within δ of the
  // guiding point, can be in the segment's span; if it cannot, the whole window is passed.
  const double delta = accel.norm() / (omega * omega);
  auto earliest = [&](double tau, double f) {
    const double margin = B + tolerance(tau), guide = g_off + nu * tau;
    const double start = f < 0 ? reach_linear(tau, guide, nu, -margin) : reach_linear(tau, -guide, -nu, -margin);
    if (start > tau || nu == 0) return start;
    const double end = std::min(tau + ((nu > 0 ? 2 : -2) * margin - guide) / nu, t_end - s.t);
    return end > tau && !may_meet_span(w, q.guide(tau), q.guide(end), delta) ? end : tau;
  };
  auto in_span = [&](const Vec2& x) { return w.within_span(x); };
  const double tau = first_outward_crossing(sample, earliest, in_span, tolerance, t_end - s.t);
  return tau == never ? never : s.t + tau;
}

double PeriodicDriveFlight::exit_time(const State& s, const ArcWall& w, double t_end) const {
  const Quiver q(*this, s);
  const double delta = accel.norm() / (omega * omega);  // |oscillation| ≤ δ
  const double sign = w.focusing ? 1.0 : -1.0;           // f = ±(|x − c| − r): beyond the wall
  const double V = q.speed_bound, A = accel.norm();
  const double scale = (s.x - w.center).norm() + w.radius;
  auto tolerance = [&](double tau) { return w.slack + 8 * eps * (scale + V * tau + delta); };
  auto sample = [&](double tau) {
    const auto [x, v] = q.at(tau);
    const Vec2 p = x - w.center;
    const double rho = p.norm();
    // d²|p|/dt² = (|v|² − (p̂·v)²)/|p| + p̂·a ≤ V²/|p| + A; valid while |p| ≥ ρ/2.
    const double M = 2 * V * V / std::max(rho, 1e-300) + A;
    return Sample{sign * (rho - w.radius), sign * p.dot(v) / rho, M, rho / (2 * V), x};
  };
  // |x − c| lies within δ of the guiding line's distance to the centre, which must first come
  // within δ (and rounding) of the radius.
  auto earliest = [&](double tau, double f) {
    const Vec2 g = q.g0 + q.u * tau - w.center;
    const double margin = delta + tolerance(tau);
    const bool inside = (f < 0) == w.focusing;  // inside the circle, to rounding
    const double start = inside ? reach_radius(tau, g, q.u, std::max(0.0, w.radius - margin), true)
                                : reach_radius(tau, g, q.u, w.radius + margin, false);
    if (start > tau) return start;
    // In the window (see the segment's case), until the guiding point is twice the margin off.
    const double end = std::min({reach_radius(tau, g, q.u, w.radius + 2 * margin, true),
                                 reach_radius(tau, g, q.u, std::max(0.0, w.radius - 2 * margin), false), t_end - s.t});
    return end > tau && !may_meet_span(w, q.guide(tau), q.guide(end), delta) ? end : tau;
  };
  auto in_span = [&](const Vec2& x) { return w.within_span(x); };
  const double tau = first_outward_crossing(sample, earliest, in_span, tolerance, t_end - s.t);
  return tau == never ? never : s.t + tau;
}

// ---- Static force ----------------------------------------------------------------------

namespace {

/// Position and velocity τ after s, evaluated in τ (not in absolute time, whose rounding at
/// large t would swallow the last steps of the scan).
std::pair<Vec2, Vec2> parabola(const State& s, const Vec2& accel, double tau) {
  return {s.x + s.v * tau + 0.5 * accel * tau * tau, s.v + accel * tau};
}

}  // namespace

State ConstantForceFlight::advance(const State& s, double t) const {
  State r = s;
  std::tie(r.x, r.v) = parabola(s, accel, t - s.t);
  r.t = t;
  return r;
}

double ConstantForceFlight::exit_time(const State& s, const SegmentWall& w, double t_end) const {
  const double n_a = w.normal.dot(accel);
  const double f0 = std::abs(w.normal.dot(s.x - w.a));
  auto tolerance = [&](double tau) {
    return w.slack + 8 * eps * (f0 + s.v.norm() * tau + std::abs(n_a) * tau * tau);
  };
  auto sample = [&](double tau) {
    const auto [x, v] = parabola(s, accel, tau);
    return Sample{w.normal.dot(x - w.a), w.normal.dot(v), std::abs(n_a), never, x};
  };
  auto earliest = [](double tau, double) { return tau; };
  auto in_span = [&](const Vec2& x) { return w.within_span(x); };
  const double tau = first_outward_crossing(sample, earliest, in_span, tolerance, t_end - s.t);
  return tau == never ? never : s.t + tau;
}

double ConstantForceFlight::exit_time(const State& s, const ArcWall& w, double t_end) const {
  const double sign = w.focusing ? 1.0 : -1.0;
  const double A = accel.norm();
  const double scale = (s.x - w.center).norm() + w.radius;
  auto tolerance = [&](double tau) { return w.slack + 8 * eps * (scale + s.v.norm() * tau + A * tau * tau); };
  auto sample = [&](double tau) {
    const auto [x, v] = parabola(s, accel, tau);
    const Vec2 p = x - w.center;
    const double rho = p.norm(), V = v.norm();
    // Over a step of length h ≤ ρ/(2V'), |v| ≤ V' = V + A h and |p| ≥ ρ/2.
    const double h = rho / (2 * (V + A) + 1e-300);
    const double Vmax = V + A * h;
    return Sample{sign * (rho - w.radius), sign * p.dot(v) / rho, 2 * Vmax * Vmax / std::max(rho, 1e-300) + A, h, x};
  };
  auto earliest = [](double tau, double) { return tau; };
  auto in_span = [&](const Vec2& x) { return w.within_span(x); };
  const double tau = first_outward_crossing(sample, earliest, in_span, tolerance, t_end - s.t);
  return tau == never ? never : s.t + tau;
}

}  // namespace billiards::dynamics
