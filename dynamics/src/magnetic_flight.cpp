// Exit times of a magnetic flight (magnetic_flight.hpp).  Segments and arcs: closed forms;
// the only delicate quantities are the discriminant at grazing incidence and the crossing
// at the start of a flight from a wall, each taken in the form that does not cancel there.
// Elliptic arcs: the certified scan.
#include "billiards/dynamics/magnetic_flight.hpp"

#include "billiards/dynamics/certified_scan.hpp"
#include "billiards/dynamics/precision.hpp"

#include <boost/math/constants/constants.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <tuple>
#include <stdexcept>
#include <utility>

namespace billiards::dynamics {

namespace {

/// Position and velocity after turning by φ = 2ψ on the circle of angular speed k, from
/// sin ψ and cos ψ: sin φ = 2 sin ψ cos ψ, 1 − cos φ = 2 sin²ψ (accurate at small φ).
template <class Real>
std::pair<Vec2T<Real>, Vec2T<Real>> turned(const BasicState<Real>& s, const Real& k, const Vec2T<Real>& w0,
                                           const Real& sn, const Real& cs) {
  const Real sin_phi = 2 * sn * cs, one_minus_cos = 2 * sn * sn, cos_phi = (cs - sn) * (cs + sn);
  return {s.x + (sin_phi / k) * s.v + (one_minus_cos / k) * w0, cos_phi * s.v + sin_phi * w0};
}

/// Position and velocity τ after s on the circle of angular speed k, w0 = v0 turned towards
/// the centre.
template <class Real>
std::pair<Vec2T<Real>, Vec2T<Real>> gyrate(const BasicState<Real>& s, const Real& k, const Vec2T<Real>& w0,
                                           const Real& tau) {
  using std::cos;
  using std::sin;
  const Real half = k * tau / 2;
  return turned(s, k, w0, sin(half), cos(half));
}

/// v turned by a quarter turn in the sense of the gyration (sign of Ω > 0: clockwise).
template <class Real>
Vec2T<Real> towards_center(const Vec2T<Real>& v, const Real& omega_c) {
  return omega_c > 0 ? Vec2T<Real>(v.y(), -v.x()) : Vec2T<Real>(-v.y(), v.x());
}

/// The exit time from the half angle of the outward crossing, or +∞: past t_end, or outside
/// the wall's span (the one crossing of each turn: the orbit never leaves through this wall).
template <class Real, class Wall>
Real exit_at(const Gyration<Real>& g, const Wall& w, const Vec2T<Real>& u, const Real& t_end) {
  using std::atan2;
  // (The span first: it rules out most crossings without an arctangent.)
  if ((u.x() == 0 && u.y() == 0) || !w.within_span(g.position_at_half_angle(u))) return never;
  const Real t = g.s.t + 2 * Real(atan2(u.y(), u.x())) / g.k;
  if (t > t_end) return never;
  g.found_t = t;
  g.found_u = u;
  return t;
}

/// The first outward zero of F0 + B1 sin φ + B2 (1 − cos φ) over one turn φ ∈ [0, 2π), as the
/// half angle ψ = φ/2 ∈ [0, π) in the form u ∝ (cos ψ, sin ψ) (u = 0: none).  `near` is the
/// rounding of F0: within it beyond the wall (0 ≤ F0 ≤ near) and moving out, the crossing is
/// now (u = (1, 0)), as for every flight (flight.hpp).  A touch (a double root) is no crossing.
/// `D` is B1² − F0 (F0 + 2 B2), the discriminant, computed by the caller in its accurate form.
template <class Real>
Vec2T<Real> outward_half_angle(const Real& F0, const Real& B1, const Real& B2, const Real& D, const Real& near) {
  using V = Vec2T<Real>;
  using std::sqrt;
  // Beyond the wall by rounding and moving out (or along it and curving out): now.
  if (F0 >= 0 && F0 <= near && (B1 > 0 || (B1 == 0 && B2 > 0))) return V(1, 0);
  if (!(D > 0)) return V::Zero();  // a miss or a touch
  // With c = cos ψ, s = sin ψ: F = F0 c² + 2 B1 s c + (F0 + 2 B2) s², zero where
  // tan ψ = (−B1 ± √D)/(F0 + 2 B2); F increases through the "+" root (its derivative in tan ψ
  // is 2√D there).  That root as a direction, in whichever of its two forms does not cancel:
  // from a wall just bounced off (F0 ≈ 0, B1 < 0) it is the far end of the chord, not the
  // start point.
  const Real root = sqrt(D);
  V u = B1 <= 0 ? V(F0 + 2 * B2, root - B1) : V(-B1 - root, F0);
  if (u.y() < 0 || (u.y() == 0 && u.x() < 0)) u = -u;  // ψ ∈ [0, π): one turn from now
  return u;
}

/// The certified scan's sample of a conic wall (an ellipse, or a circle: L = I/r): its gap
/// f = ±m(|u|² − 1)/2 (u = L(x − c), m the smaller semi-axis: to first order the distance beyond
/// the wall), f' = ±m u·Lv, and |f''| ≤ m|Lv|² + m|u| |La| ≤ (V² + P A)/m while |v| ≤ V, |a| ≤ A,
/// |x − c| ≤ P (|L| = 1/m), for `cap` time units.
template <class Real>
scan::Sample<Real> conic_sample(const Real& sign, const Real& m, const Vec2T<Real>& u, const Vec2T<Real>& Lv,
                                const Real& V, const Real& A, const Real& P, const Real& cap, const Vec2T<Real>& x) {
  return {sign * m * (u.squaredNorm() - 1) / 2, sign * m * u.dot(Lv), (V * V + P * A) / m, cap, x};
}

/// The rounding band of a scanned gap: the wall's slack, and the rounding of positions of size
/// `scale` reached at speed V after τ, in units of the gap (× scale/m for a conic).
template <class Real>
Real scan_tolerance(const Real& slack, const Real& scale, const Real& V, const Real& tau, const Real& stretch) {
  return slack + 16 * scan::eps<Real> * (scale + V * tau) * stretch;
}

}  // namespace

template <class Real>
Gyration<Real>::Gyration(const BasicMagneticFlight<Real>& flight, const BasicState<Real>& state)
    : s(state) {
  using std::abs;
  using std::sqrt;
  k = abs(flight.omega_c);
  inv_k = 1 / k;
  w0 = towards_center(state.v, flight.omega_c);
  speed = sqrt(state.v.squaredNorm());
  center = state.x + w0 * inv_k;
  radius = speed * inv_k;
}

template <class Real>
auto Gyration<Real>::position_at_half_angle(const V& u) const -> V {
  const Real scale = 2 * inv_k / u.squaredNorm();  // (2/k) / |u|², with sin ψ cos ψ = u_x u_y/|u|²
  return s.x + scale * (u.x() * u.y() * s.v + u.y() * u.y() * w0);
}

template <class Real>
auto Gyration<Real>::first_hit(const BasicTable<Real>& table, const Real& t_end) const
    -> FlightHit<BasicMagneticFlight<Real>> {
  using std::sqrt;
  FlightHit<BasicMagneticFlight<Real>> hit;
  hit.t = t_end;
  detail::try_every_wall(table, *this, hit);
  if (!hit.found()) return hit;
  hit.state = s;
  hit.state.t = hit.t;
  if (hit.t == found_t) {
    const Real norm = sqrt(found_u.squaredNorm());
    std::tie(hit.state.x, hit.state.v) = turned(s, k, w0, Real(found_u.y() / norm), Real(found_u.x() / norm));
  } else {  // (an elliptic arc's scan)
    std::tie(hit.state.x, hit.state.v) = gyrate(s, k, w0, Real(hit.t - s.t));
  }
  return hit;
}

template <class Real>
template <class Wall>
bool Gyration<Real>::may_reach(const Wall& w, const Real& t_end) const {
  const Real margin = 16 * scan::eps<Real> * (center.template lpNorm<Eigen::Infinity>() + radius + w.bound_radius);
  const Real reach = radius + w.bound_radius + margin;
  if ((center - w.bound_center).squaredNorm() > reach * reach) return false;
  if (t_end == never) return true;
  // The arc flown until t_end is no shorter than its chord.
  const Real travel = speed * (t_end - s.t) + w.bound_radius + margin;
  return (s.x - w.bound_center).squaredNorm() <= travel * travel;
}

template <class Real>
Real Gyration<Real>::exit_time(const BasicSegmentWall<Real>& w, const Real& t_end) const {
  if (!may_reach(w, t_end)) return never;
  // F = k × (distance beyond the line): F0 now, B1 = n·v0, B2 = n·w0; B1² + B2² = |v0|².
  const Real F0 = k * w.normal.dot(s.x - w.a), B1 = w.normal.dot(s.v), B2 = w.normal.dot(w0);
  const Real near = k * w.slack;
  using std::abs;
  // D = B1² − F0 (F0 + 2 B2): as it stands on the wall; elsewhere as |v0|² − (k × distance of the
  // centre beyond the line)², a product free of cancellation at a graze.
  const Real mean = F0 + B2;
  const Real D = abs(F0) <= near ? Real(B1 * B1 - F0 * (F0 + 2 * B2)) : Real((speed - mean) * (speed + mean));
  return exit_at(*this, w, outward_half_angle(F0, B1, B2, D, near), t_end);
}

template <class Real>
Real Gyration<Real>::exit_time(const BasicArcWall<Real>& w, const Real& t_end) const {
  if (!may_reach(w, t_end)) return never;
  // F = ±(k/2)(|x − c|² − r²), + for a focusing arc: beyond the wall is outside its circle.
  const Real sign = w.focusing ? 1 : -1;
  const V p = s.x - w.center;
  const Real F0 = sign * k / 2 * (p.squaredNorm() - w.radius2), B1 = sign * p.dot(s.v),
             B2 = sign * (p.dot(w0) + speed * radius);
  const Real near = k * w.radius * w.slack;
  using std::abs;
  Real D;
  if (abs(F0) <= near) {
    D = B1 * B1 - F0 * (F0 + 2 * B2);
  } else {
    // (k/2)² ((r + ρ)² − d²)(d² − (r − ρ)²), d the distance between the centres: each factor
    // a sum of three lengths, zero at a graze.
    const Real d = (center - w.center).norm(), r = w.radius, rho = radius;
    D = k * k / 4 * ((r - d + rho) * (r + d - rho)) * ((d + rho - r) * (d + rho + r));
  }
  return exit_at(*this, w, outward_half_angle(F0, B1, B2, D, near), t_end);
}

template <class Real>
Real Gyration<Real>::exit_time(const BasicEllipticArcWall<Real>& w, const Real& t_end) const {
  using std::max;
  using std::min;
  if (!may_reach(w, t_end)) return never;
  // Along the whole circle |v| = |v0|, |a| = k|v0| and |x − c| ≤ P.
  const Real sign = w.focusing ? 1 : -1, m = min(w.a, w.b);
  const Real P = (s.x - w.center).norm() + 2 * radius + max(w.a, w.b);
  auto sample = [&](const Real& tau) {
    const auto [x, v] = gyrate(s, k, w0, tau);
    return conic_sample(sign, m, w.to_unit(x), V(w.map * v), speed, Real(k * speed), P, Real(never), x);
  };
  auto tolerance = [&](const Real& tau) { return scan_tolerance(w.slack, P, speed, tau, Real(P / m)); };
  auto earliest = [](const Real& tau) { return tau; };
  auto in_span = [&](const V& x) { return w.within_span(x); };
  // One turn holds every crossing the orbit will ever make.
  const Real turn = boost::math::constants::two_pi<Real>() / k;
  const Real tau_end = t_end == never ? turn : min(Real(t_end - s.t), turn);
  const Real tau = scan::first_outward_crossing(sample, earliest, in_span, tolerance, tau_end);
  return tau == never ? Real(never) : Real(s.t + tau);
}

// ---- The field and a uniform force ---------------------------------------------------------

namespace {

template <class Real>
using Complex = std::complex<Real>;

/// E(λ, τ) = ∫₀^τ e^{iλs} ds = e^{iλτ/2} · 2 sin(λτ/2)/λ (τ at λ = 0).
template <class Real>
Complex<Real> ramp(const Real& lambda, const Real& tau) {
  using std::sin;
  const Real half = lambda * tau / 2;
  return std::polar(lambda == 0 ? tau : Real(2 * sin(half) / lambda), half);
}

/// G(λ, μ, τ) = ∫₀^τ e^{iμs} E(λ, s) ds = (E(λ + μ, τ) − E(μ, τ))/(iλ)
/// = (e^{iμτ} E(λ, τ) − E(λ + μ, τ))/(iμ): divided by the larger of |λ| and |μ|, so that the
/// resonance λ = 0 costs nothing.
template <class Real>
Complex<Real> double_ramp(const Real& lambda, const Real& mu, const Real& tau) {
  using std::abs;
  if (abs(lambda) >= abs(mu)) {
    if (lambda == 0) return tau * tau / 2;
    return (ramp(Real(lambda + mu), tau) - ramp(mu, tau)) / Complex<Real>(0, lambda);
  }
  return (std::polar(Real(1), Real(mu * tau)) * ramp(lambda, tau) - ramp(Real(lambda + mu), tau)) / Complex<Real>(0, mu);
}

/// Position and velocity τ after s (the header's formulas; the drive's phase from s.t).
template <class Real>
std::pair<Vec2T<Real>, Vec2T<Real>> drifted(const BasicMagneticDriveFlight<Real>& f, const BasicState<Real>& s,
                                            const Real& tau) {
  using C = Complex<Real>;
  const C v0(s.v.x(), s.v.y()), half_a = C(f.accel.x(), f.accel.y()) / Real(2);
  const Real W = f.omega_c, up = W + f.omega, down = W - f.omega;
  const C e = std::polar(Real(1), Real(f.omega * s.t + f.phase0));
  const C v = std::polar(Real(1), Real(-W * tau)) * (v0 + half_a * (e * ramp(up, tau) + std::conj(e) * ramp(down, tau)));
  const C dx = ramp(Real(-W), tau) * v0 +
               half_a * (e * double_ramp(up, Real(-W), tau) + std::conj(e) * double_ramp(down, Real(-W), tau));
  return {s.x + Vec2T<Real>(dx.real(), dx.imag()), Vec2T<Real>(v.real(), v.imag())};
}

/// The first outward crossing before t_end of the gap `gap(x, v, V, A, cap)` (a scan::Sample),
/// sampled along the flight from s, where `tolerance(τ, V)` is its rounding band.  The bounds
/// hold over a step of at most the faster of the two periods, with V the speed bound at its end.
template <class Real, class Gap, class Tolerance, class InSpan>
Real driven_exit(const BasicMagneticDriveFlight<Real>& f, const BasicState<Real>& s, const Real& t_end, Gap gap,
                 Tolerance tolerance, InSpan in_span) {
  using std::abs;
  using std::max;
  if (t_end == never) throw std::logic_error("a magnetic flight under a force needs a search horizon");
  const Real cap = boost::math::constants::two_pi<Real>() / max(Real(abs(f.omega_c)), f.omega);
  const Real a = f.accel.norm();
  auto sample = [&](const Real& tau) {
    const auto [x, v] = drifted(f, s, tau);
    const Real V = f.speed_bound(s, Real(tau + cap));
    return gap(x, v, V, Real(abs(f.omega_c) * V + a), cap);
  };
  auto earliest = [](const Real& tau) { return tau; };
  auto tol = [&](const Real& tau) { return tolerance(tau, f.speed_bound(s, tau)); };
  const Real tau = scan::first_outward_crossing(sample, earliest, in_span, tol, Real(t_end - s.t));
  return tau == never ? Real(never) : Real(s.t + tau);
}

}  // namespace

template <class Real>
auto BasicMagneticDriveFlight<Real>::advance(const State& s, const Real& t) const -> State {
  State r = s;
  std::tie(r.x, r.v) = drifted(*this, s, Real(t - s.t));
  r.t = t;
  return r;
}

template <class Real>
Real BasicMagneticDriveFlight<Real>::speed_bound(const State& s, const Real& tau) const {
  using std::abs;
  using std::min;
  // |E(λ, τ)| ≤ min(τ, 2/|λ|).
  auto ramp_bound = [&](const Real& lambda) { return lambda == 0 ? tau : min(tau, Real(2 / abs(lambda))); };
  return s.v.norm() + accel.norm() / 2 * (ramp_bound(omega_c + omega) + ramp_bound(omega_c - omega));
}

template <class Real>
Real BasicMagneticDriveFlight<Real>::exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const {
  using std::abs;
  const Real scale = abs(w.normal.dot(s.x - w.a)) + w.bound_radius;
  auto gap = [&](const Vec2T<Real>& x, const Vec2T<Real>& v, const Real&, const Real& A, const Real& cap) {
    return scan::Sample<Real>{w.normal.dot(x - w.a), w.normal.dot(v), A, cap, x};
  };
  auto tolerance = [&](const Real& tau, const Real& V) { return scan_tolerance(w.slack, scale, V, tau, Real(1)); };
  return driven_exit(*this, s, t_end, gap, tolerance, [&](const Vec2T<Real>& x) { return w.within_span(x); });
}

template <class Real>
Real BasicMagneticDriveFlight<Real>::exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const {
  const Real sign = w.focusing ? 1 : -1, r = w.radius, scale = (s.x - w.center).norm() + r;
  auto gap = [&](const Vec2T<Real>& x, const Vec2T<Real>& v, const Real& V, const Real& A, const Real& cap) {
    const Vec2T<Real> p = x - w.center;
    return conic_sample(sign, r, Vec2T<Real>(p / r), Vec2T<Real>(v / r), V, A, Real(p.norm() + V * cap), cap, x);
  };
  auto tolerance = [&](const Real& tau, const Real& V) { return scan_tolerance(w.slack, scale, V, tau, Real(scale / r)); };
  return driven_exit(*this, s, t_end, gap, tolerance, [&](const Vec2T<Real>& x) { return w.within_span(x); });
}

template <class Real>
Real BasicMagneticDriveFlight<Real>::exit_time(const State& s, const BasicEllipticArcWall<Real>& w,
                                               const Real& t_end) const {
  using std::max;
  using std::min;
  const Real sign = w.focusing ? 1 : -1, m = min(w.a, w.b), scale = (s.x - w.center).norm() + max(w.a, w.b);
  auto gap = [&](const Vec2T<Real>& x, const Vec2T<Real>& v, const Real& V, const Real& A, const Real& cap) {
    return conic_sample(sign, m, w.to_unit(x), Vec2T<Real>(w.map * v), V, A, Real((x - w.center).norm() + V * cap), cap, x);
  };
  auto tolerance = [&](const Real& tau, const Real& V) { return scan_tolerance(w.slack, scale, V, tau, Real(scale / m)); };
  return driven_exit(*this, s, t_end, gap, tolerance, [&](const Vec2T<Real>& x) { return w.within_span(x); });
}

template <class Real>
auto BasicMagneticFlight<Real>::advance(const State& s, const Real& t) const -> State {
  using std::abs;
  State r = s;
  std::tie(r.x, r.v) = gyrate(s, Real(abs(omega_c)), towards_center(s.v, omega_c), Real(t - s.t));
  r.t = t;
  return r;
}

template <class Real>
Real BasicMagneticFlight<Real>::period() const {
  using std::abs;
  return boost::math::constants::two_pi<Real>() / abs(omega_c);
}

template struct Gyration<double>;
template struct Gyration<long double>;
template struct Gyration<Reference>;
template struct BasicMagneticFlight<double>;
template struct BasicMagneticFlight<long double>;
template struct BasicMagneticFlight<Reference>;
template struct BasicMagneticDriveFlight<double>;
template struct BasicMagneticDriveFlight<long double>;

}  // namespace billiards::dynamics
