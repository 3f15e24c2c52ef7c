// Exit times of a magnetic flight (magnetic_flight.hpp).  Segments and arcs: closed forms;
// the only delicate quantities are the discriminant at grazing incidence and the crossing
// at the start of a flight from a wall, each taken in the form that does not cancel there.
// Elliptic arcs, and in 3-D planes oblique to the field, triangles and spheres: the certified
// scan along the helix, its windows from the guiding axis.
#include "billiards/dynamics/magnetic_flight.hpp"

#include "billiards/dynamics/certified_scan.hpp"
#include "billiards/dynamics/precision.hpp"

#include <boost/math/constants/constants.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <tuple>
#include <type_traits>
#include <stdexcept>
#include <utility>

namespace billiards::dynamics {

namespace {

/// Position and velocity of a helix after turning by φ = 2ψ, τ after the start, from sin ψ
/// and cos ψ, with the drift (3-D; turned_by in 2-D).
std::pair<Vec3, Vec3> turned(const Gyration<double, 3>& g, double sn, double cs, double tau) {
  const double sin_phi = 2 * sn * cs, one_minus_cos = 2 * sn * sn, cos_phi = (cs - sn) * (cs + sn);
  const Vec3 x = g.s.x + (sin_phi * g.inv_k) * g.v_perp + (one_minus_cos * g.inv_k) * g.w0 + tau * g.drift;
  const Vec3 v = cos_phi * g.v_perp + sin_phi * g.w0 + g.drift;
  return {x, v};
}

/// Walls whose crossings are closed forms (magnetic_exit-inl.hpp); the others are scanned
/// (Gyration::exit_time's template).
template <class Real, class W>
inline constexpr bool has_closed_form = std::is_same_v<W, BasicSegmentWall<Real>> || std::is_same_v<W, BasicArcWall<Real>>;

/// The exit time through one wall with a closed form, or +∞: past t_end, or outside the wall's
/// span (the one crossing of each turn: the orbit never leaves through this wall).
template <class Real, class Wall>
Real closed_form_exit(const Gyration<Real>& g, const Wall& w, const Real& t_end) {
  if (!g.may_reach(w, t_end)) return never;
  EarliestCrossing<Real, bool> only{{Real(0), Real(0)}, false};
  ScalarLanes<Real> l;
  // (The span before the arctangent: it rules out most crossings.)
  const auto view = [&] {
    if constexpr (std::is_same_v<Wall, BasicSegmentWall<Real>>) return segment_lanes(w);
    else return arc_lanes(w);
  }();
  if (!keep_earlier_crossing(l, g.lanes(), view, reach_lanes(w), only)) return never;
  const Real t = crossing_time(l, g.lanes(), only.u, g.s.t);
  return t > t_end ? Real(never) : t;
}

/// The certified scan's sample of a conic wall (an ellipse, or a circle: L = I/r): its gap
/// f = ±m(|u|² − 1)/2 (u = L(x − c), m the smaller semi-axis: to first order the distance beyond
/// the wall), f' = ±m u·Lv, and |f''| ≤ m|Lv|² + m|u| |La| ≤ (V² + P A)/m while |v| ≤ V, |a| ≤ A,
/// |x − c| ≤ P (|L| = 1/m), for `cap` time units.
template <class Real, class Vec>
scan::Sample<Real, Vec> conic_sample(const Real& sign, const Real& m, const Vec& u, const Vec& Lv, const Real& V,
                                     const Real& A, const Real& P, const Real& cap, const Vec& x) {
  return {sign * m * (u.squaredNorm() - 1) / 2, sign * m * u.dot(Lv), (V * V + P * A) / m, cap, x};
}



/// The first time t ≥ τ at which |q0 + t u| ≤ R (`inward`) or ≥ R (outward), or +∞: where the
/// guiding axis of a helix comes near enough a sphere's centre (or far enough from it) for the
/// helix to reach the sphere.  Each root in the form that does not cancel.
double first_reach(const Vec3& q0, const Vec3& u, double R, bool inward, double tau) {
  const Vec3 q = q0 + tau * u;
  const double c = q.squaredNorm() - R * R;
  if (inward ? c <= 0 : c >= 0) return tau;
  const double a = u.squaredNorm(), b = q.dot(u), disc = b * b - a * c;
  if (a == 0 || (inward && (b >= 0 || disc < 0))) return never;
  const double root = std::sqrt(disc);
  if (inward) return tau + c / (root - b);                    // the nearer root, ahead
  return tau + (b >= 0 ? -c / (b + root) : (root - b) / a);  // the farther root (c < 0)
}

}  // namespace

template <class Real, int D>
Gyration<Real, D>::Gyration(const BasicMagneticFlight<Real, D>& flight, const BasicState<Real, D>& state)
    : s(state) {
  using std::abs;
  using std::sqrt;
  if constexpr (D == 2) {
    k = abs(flight.omega_c);
    inv_k = 1 / k;
    const auto g = gyration_of(ScalarLanes<Real>{}, state.x.x(), state.x.y(), state.v.x(), state.v.y(), k, inv_k,
                               flight.omega_c > 0, Real(16 * scan::eps<Real>));
    v_perp = state.v;
    w0 = V(g.w0x, g.w0y);
    drift = V::Zero();
    axis = V::Zero();
    speed = g.speed;
    center = V(g.cx, g.cy);
    radius = g.radius;
    rounding = g.rounding;
  } else {
    // (Projected with Ω itself, not the rounded unit vector b, and w0 scaled to |v⊥|: a fixed
    // rounding of |b| would otherwise bias |v(τ)|² by the same sign in every flight.)
    const Real k2 = flight.omega_c.squaredNorm();
    k = sqrt(k2);
    inv_k = 1 / k;
    axis = flight.omega_c * inv_k;
    drift = (state.v.dot(flight.omega_c) / k2) * flight.omega_c;
    v_perp = state.v - drift;
    w0 = v_perp.cross(flight.omega_c);
    speed = sqrt(v_perp.squaredNorm());
    if (speed > 0) w0 *= speed / w0.norm();
    center = state.x + w0 * inv_k;
    radius = speed * inv_k;
    rounding = 16 * scan::eps<Real> * (center.template lpNorm<Eigen::Infinity>() + radius);
  }
}

template <class Real, int D>
auto Gyration<Real, D>::at(const Real& tau) const -> std::pair<V, V> {
  using std::cos;
  using std::sin;
  const Real half = k * tau / 2;
  if constexpr (D == 2) {
    const auto p = turned_by<ScalarLanes<Real>>(lanes(), Real(sin(half)), Real(cos(half)));
    return {V(p.x, p.y), V(p.vx, p.vy)};
  } else {
    return turned(*this, Real(sin(half)), Real(cos(half)), tau);
  }
}

template <class Real, int D>
Real Gyration<Real, D>::period() const {
  return boost::math::constants::two_pi<Real>() * inv_k;
}

template <class Real, int D>
auto Gyration<Real, D>::first_hit(const BasicTable<Real>& table, const Real& t_end) const
    -> FlightHit<BasicMagneticFlight<Real>>
  requires(D == 2) {
  // The closed forms: the earliest crossing within its wall's span (ties: the first wall).
  ScalarLanes<Real> l;
  const auto g = lanes();
  EarliestCrossing<Real, bool> earliest{{Real(0), Real(0)}, false};
  WallId wall;
  const auto& segments = table.segments();
  for (int i = 0, n = int(segments.size()); i < n; ++i)
    if (keep_earlier_crossing(l, g, segment_lanes(segments[i]), reach_lanes(segments[i]), earliest))
      wall = {wall_kind::segment, i};
  const auto& arcs = table.arcs();
  for (int i = 0, n = int(arcs.size()); i < n; ++i)
    if (keep_earlier_crossing(l, g, arc_lanes(arcs[i]), reach_lanes(arcs[i]), earliest)) wall = {wall_kind::arc, i};
  return hit_from(table, earliest, wall, t_end);
}

template <class Real, int D>
auto Gyration<Real, D>::hit_from(const BasicTable<Real>& table, const EarliestCrossing<Real, bool>& earliest,
                                 const WallId& wall, const Real& t_end) const -> FlightHit<BasicMagneticFlight<Real>>
  requires(D == 2) {
  FlightHit<BasicMagneticFlight<Real>> hit;
  hit.t = t_end;
  if (earliest.found) {
    if (const Real t = crossing_time(ScalarLanes<Real>{}, lanes(), earliest.u, s.t); t < t_end) hit.t = t, hit.wall = wall;
  }
  const bool scanned = scan_walls_without_closed_form(table, hit);
  if (!hit.found()) return hit;
  hit.state = s;
  hit.state.t = hit.t;
  if (!scanned) {
    const auto p = turned_by<ScalarLanes<Real>>(lanes(), earliest.u);
    hit.state.x = V(p.x, p.y), hit.state.v = V(p.vx, p.vy);
  } else {
    std::tie(hit.state.x, hit.state.v) = at(hit.t - s.t);
  }
  return hit;
}

template <class Real, int D>
bool Gyration<Real, D>::scan_walls_without_closed_form(const BasicTable<Real>& table,
                                                       FlightHit<BasicMagneticFlight<Real>>& hit) const
  requires(D == 2) {
  bool scanned = false;
  table.for_each_kind([&]<class W>(const Walls<W>& walls, int kind) {
    if constexpr (!has_closed_form<Real, W>) {
      for (int i = 0, n = int(walls.size()); i < n; ++i)
        if (const Real t = exit_time(walls[i], hit.t); t < hit.t) hit.t = t, hit.wall = {kind, i}, scanned = true;
    }
  });
  return scanned;
}

template <class Real, int D>
Real Gyration<Real, D>::exit_time(const BasicSegmentWall<Real>& w, const Real& t_end) const
  requires(D == 2) {
  return closed_form_exit(*this, w, t_end);
}

template <class Real, int D>
Real Gyration<Real, D>::exit_time(const BasicArcWall<Real>& w, const Real& t_end) const
  requires(D == 2) {
  return closed_form_exit(*this, w, t_end);
}

// ---- Helices (3-D) ---------------------------------------------------------------------------

template <class Real, int D>
template <class InSpan>
double Gyration<Real, D>::plane_exit(const Vec3& n, const Vec3& a, double slack, double t_end, bool spanless,
                                     InSpan in_span) const
  requires(D == 3) {
  const double along = n.dot(drift);  // the guide's rate towards the plane
  const double F0 = n.dot(s.x - a);
  // Across the field (n ∥ b): the gap grows linearly, as for a straight flight.
  if (n.cross(axis).isZero(0)) {
    if (!(along > 0) || F0 > slack) return never;  // moving in, or beyond: elsewhere
    const double tau = F0 >= 0 ? 0 : -F0 / along;
    if (s.t + tau > t_end || !in_span(at(tau).first)) return never;
    return s.t + tau;
  }
  // Along the field (n ⟂ b) and without a span: the circle's closed form (the 2-D segment's),
  // one crossing per turn whatever the drift along the plane.
  if (spanless && n.dot(axis) == 0) {
    const auto u = line_half_angle(ScalarLanes<double>{}, k, F0, n.dot(v_perp), n.dot(w0), speed, slack);
    if (u.x == 0 && u.y == 0) return never;
    const double t = s.t + 2 * half_angle_of(ScalarLanes<double>{}, u) * inv_k;
    return t > t_end ? never : t;
  }
  // Otherwise the scan: |f''| = |n·(v⊥ × Ω)| ≤ k |v⊥| |n⊥|, and the gap stays within r_c |n⊥| of
  // the guide's, F0 + n·(w0/k) + along τ.
  const double across = (n - n.dot(axis) * axis).norm(), M = k * speed * across, reach = radius * across;
  const double guide0 = n.dot(center - a), V = s.v.norm();
  const double scale = s.x.cwiseAbs().maxCoeff() + a.cwiseAbs().maxCoeff() + 2 * radius;
  auto tolerance = [&](double tau) { return scan::rounding_band(slack, scale, V, tau, 1.0); };
  auto sample = [&](double tau) {
    const auto [x, v] = at(tau);
    return scan::Sample<double, Vec3>{n.dot(x - a), n.dot(v), M, never, x};
  };
  auto earliest = [&](double tau) {
    const double band = reach + 2 * tolerance(tau);
    if (guide0 + along * tau + band >= 0) return tau;
    return along > 0 ? std::max(tau, (-band - guide0) / along) : never;
  };
  // (Without a drift towards the plane the gap is periodic: one turn holds every crossing.)
  const double tau_end = along == 0 ? std::min(t_end - s.t, period()) : t_end - s.t;
  const double tau = scan::first_outward_crossing(sample, earliest, in_span, tolerance, tau_end);
  return tau == never ? never : s.t + tau;
}

template <class Real, int D>
double Gyration<Real, D>::exit_time(const PlaneWall& w, double t_end) const
  requires(D == 3) {
  return plane_exit(w.normal, Vec3(w.normal * w.offset), w.slack, t_end, true, [](const Vec3&) { return true; });
}

template <class Real, int D>
double Gyration<Real, D>::exit_time(const TriangleWall& w, double t_end) const
  requires(D == 3) {
  return plane_exit(w.normal, w.p[0], w.slack, t_end, false, [&](const Vec3& x) { return w.within_span(x); });
}

template <class Real, int D>
double Gyration<Real, D>::exit_time(const SphereWall& w, double t_end) const
  requires(D == 3) {
  // |v| = V and |a| = k|v⊥| all along; |x − c| ≤ ρ + V h over a step h = (ρ + r)/V.
  const double sign = w.focusing ? 1 : -1, r = w.radius, V = s.v.norm();
  const double scale = (s.x - w.center).norm() + r + 2 * radius;
  auto tolerance = [&](double tau) { return scan::rounding_band(w.slack, scale, V, tau, scale / r); };
  auto sample = [&](double tau) {
    const auto [x, v] = at(tau);
    const Vec3 p = x - w.center;
    const double rho = p.norm(), cap = (rho + r) / V;
    return conic_sample(sign, r, Vec3(p / r), Vec3(v / r), V, k * speed, 2 * rho + r, cap, x);
  };
  // The helix is within r_c of its guiding axis: it can enter a hole only where the axis is
  // within r + r_c of the centre, and leave a ball only where the axis is beyond r − r_c.
  auto earliest = [&](double tau) {
    const double margin = 2 * tolerance(tau);
    if (!w.focusing) return first_reach(Vec3(center - w.center), drift, r + radius + margin, true, tau);
    const double inner = r - radius - margin;
    return inner <= 0 ? tau : first_reach(Vec3(center - w.center), drift, inner, false, tau);
  };
  const double tau_end = drift.isZero(0) ? std::min(t_end - s.t, period()) : t_end - s.t;
  const double tau = scan::first_outward_crossing(sample, earliest, [](const Vec3&) { return true; }, tolerance, tau_end);
  return tau == never ? never : s.t + tau;
}

template <class Real, int D>
Tube3 Gyration<Real, D>::tube() const
  requires(D == 3) {
  return {center, drift, radius + 16 * scan::eps<double> * (center.cwiseAbs().maxCoeff() + radius)};
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

/// The plane across the field as complex numbers: z ↦ z.x e1 + z.y e2 (2-D: the plane itself),
/// with e1 × e2 = b, so that the motion across the field is the 2-D one with Ω = |Ω| > 0.
template <class Real, int D>
struct FieldFrame {
  Real W;       // Ω in the plane's orientation (2-D: signed)
  VecN<Real, D> b, e1, e2;
  explicit FieldFrame(const Cyclotron<Real, D>& omega_c) {
    if constexpr (D == 2) {
      W = omega_c;
    } else {
      W = omega_c.norm();
      b = omega_c / W;
      e1 = b.unitOrthogonal();
      e2 = b.cross(e1);
    }
  }
  Complex<Real> across(const VecN<Real, D>& v) const {
    if constexpr (D == 2) return {v.x(), v.y()};
    else return {v.dot(e1), v.dot(e2)};
  }
  Real along(const VecN<Real, D>& v) const {
    if constexpr (D == 2) return 0;
    else return v.dot(b);
  }
  VecN<Real, D> vector(const Complex<Real>& z, const Real& along) const {
    if constexpr (D == 2) return {z.real(), z.imag()};
    else return z.real() * e1 + z.imag() * e2 + along * b;
  }
};

/// Position and velocity τ after s (the header's formulas; e^{iθ} from the state's phase).
template <class Real, int D>
std::pair<VecN<Real, D>, VecN<Real, D>> drifted(const BasicMagneticDriveFlight<Real, D>& f, const FieldFrame<Real, D>& frame,
                                                const BasicDrivenState<Real, D>& s, const Real& tau) {
  using C = Complex<Real>;
  const C v0 = frame.across(s.v), half_a = frame.across(f.accel) / Real(2);
  const Real W = frame.W, up = W + f.omega, down = W - f.omega;
  const C e(s.cos_phase, s.sin_phase);
  const C v = std::polar(Real(1), Real(-W * tau)) * (v0 + half_a * (e * ramp(up, tau) + std::conj(e) * ramp(down, tau)));
  const C dx = ramp(Real(-W), tau) * v0 +
               half_a * (e * double_ramp(up, Real(-W), tau) + std::conj(e) * double_ramp(down, Real(-W), tau));
  // Along the field: v∥0 + a∥ Re(e^{iθ} E(ω, τ)), and its integral with G(ω, 0, τ).
  Real v_along = 0, x_along = 0;
  if constexpr (D == 3) {
    const Real u0 = frame.along(s.v), a = frame.along(f.accel);
    v_along = u0 + a * (e * ramp(f.omega, tau)).real();
    x_along = u0 * tau + a * (e * double_ramp(f.omega, Real(0), tau)).real();
  }
  return {s.x + frame.vector(dx, x_along), frame.vector(v, v_along)};
}

/// The first outward crossing before t_end of the gap `gap(x, v, V, A, cap)` (a scan::Sample),
/// sampled along the flight from s, where `tolerance(τ, V)` is its rounding band.  The bounds
/// hold over a step of at most one cyclotron period, with V the speed bound at its end (away
/// from the resonance the bound saturates: a long step costs no accuracy).
template <class Real, int D, class Gap, class Tolerance, class InSpan>
Real driven_exit(const BasicMagneticDriveFlight<Real, D>& f, const BasicDrivenState<Real, D>& s, const Real& t_end, Gap gap,
                 Tolerance tolerance, InSpan in_span) {
  using std::abs;
  if (t_end == never) throw std::logic_error("a magnetic flight under a force needs a search horizon");
  const FieldFrame<Real, D> frame(f.omega_c);
  const Real k = abs(frame.W);
  const Real cap = boost::math::constants::two_pi<Real>() / k;
  const Real a = f.accel.norm();
  auto sample = [&](const Real& tau) {
    const auto [x, v] = drifted(f, frame, s, tau);
    const Real V = f.speed_bound(s, Real(tau + cap));
    return gap(x, v, V, Real(k * V + a), cap);
  };
  auto earliest = [](const Real& tau) { return tau; };
  auto tol = [&](const Real& tau) { return tolerance(tau, f.speed_bound(s, tau)); };
  const Real tau = scan::first_outward_crossing(sample, earliest, in_span, tol, Real(t_end - s.t));
  return tau == never ? Real(never) : Real(s.t + tau);
}

/// The gap beyond the plane n·(x − a) = 0 (a segment's line, a plane, a triangle's plane) for
/// driven_exit, and its rounding band (`scale`: the size of the positions).
template <class Real, class Vec>
auto plane_gap(const Vec& n, const Vec& a) {
  return [n, a](const Vec& x, const Vec& v, const Real&, const Real& A, const Real& cap) {
    return scan::Sample<Real, Vec>{n.dot(x - a), n.dot(v), A, cap, x};
  };
}
template <class Real>
auto plane_tolerance(const Real& slack, const Real& scale) {
  return [slack, scale](const Real& tau, const Real& V) { return scan::rounding_band(slack, scale, V, tau, Real(1)); };
}

/// The gap beyond a circle or sphere (centre c, radius r; `sign` + for a focusing wall), and its
/// rounding band, for driven_exit.
template <class Real, class Vec>
auto round_gap(const Real& sign, const Vec& c, const Real& r) {
  return [sign, c, r](const Vec& x, const Vec& v, const Real& V, const Real& A, const Real& cap) {
    using std::min;
    const Vec p = x - c;
    const Real rho = p.norm(), h = min(cap, Real((rho + r) / V));  // (|x − c| ≤ 2ρ + r over h)
    return conic_sample(sign, r, Vec(p / r), Vec(v / r), V, A, Real(rho + V * h), h, x);
  };
}
template <class Real>
auto round_tolerance(const Real& slack, const Real& scale, const Real& r) {
  return [slack, scale, r](const Real& tau, const Real& V) { return scan::rounding_band(slack, scale, V, tau, Real(scale / r)); };
}

const auto everywhere = [](const auto&) { return true; };

}  // namespace

template <class Real, int D>
auto BasicMagneticDriveFlight<Real, D>::advance(const State& s, const Real& t) const -> State {
  const Real tau = t - s.t;
  State r = s;
  std::tie(r.x, r.v) = drifted(*this, FieldFrame<Real, D>(omega_c), s, tau);
  r.set_phase(advance_phase(s.phase, omega, tau));
  r.t = t;
  return r;
}

template <class Real, int D>
Real BasicMagneticDriveFlight<Real, D>::speed_bound(const State& s, const Real& tau) const {
  using std::abs;
  using std::min;
  const FieldFrame<Real, D> frame(omega_c);
  // |E(λ, τ)| ≤ min(τ, 2/|λ|).
  auto ramp_bound = [&](const Real& lambda) { return lambda == 0 ? tau : min(tau, Real(2 / abs(lambda))); };
  const Real along = abs(frame.along(accel)), across = abs(frame.across(accel));
  return s.v.norm() + across / 2 * (ramp_bound(frame.W + omega) + ramp_bound(frame.W - omega)) +
         along * ramp_bound(omega);
}

template <class Real, int D>
Real BasicMagneticDriveFlight<Real, D>::exit_time(const State& s, const BasicSegmentWall<Real>& w, const Real& t_end) const
  requires(D == 2) {
  using std::abs;
  const Real scale = abs(w.normal.dot(s.x - w.a)) + w.bound_radius;
  return driven_exit(*this, s, t_end, plane_gap<Real>(w.normal, w.a), plane_tolerance(w.slack, scale),
                     [&](const Vec2T<Real>& x) { return w.within_span(x); });
}

template <class Real, int D>
Real BasicMagneticDriveFlight<Real, D>::exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const
  requires(D == 2) {
  const Real sign = w.focusing ? 1 : -1, r = w.radius, scale = (s.x - w.center).norm() + r;
  return driven_exit(*this, s, t_end, round_gap(sign, w.center, r), round_tolerance(w.slack, scale, r),
                     [&](const Vec2T<Real>& x) { return w.within_span(x); });
}

template <class Real, int D>
template <class Wall>
Real BasicMagneticDriveFlight<Real, D>::exit_time(const State& s, const Wall& w, const Real& t_end, Scanned) const {
  using std::min;
  using V = VecN<Real, D>;
  auto gap = [&w](const V& x, const V& v, const Real&, const Real& A, const Real& cap) {
    auto sample = w.gap_sample(x, v, A);
    sample.cap = min(sample.cap, cap);
    return sample;
  };
  return driven_exit(*this, s, t_end, gap, plane_tolerance(w.slack, Real(s.x.template lpNorm<Eigen::Infinity>())),
                     [&](const V& x) { return w.within_span(x); });
}

template <class Real, int D>
double BasicMagneticDriveFlight<Real, D>::exit_time(const State& s, const PlaneWall& w, double t_end) const
  requires(D == 3) {
  const Vec3 a = w.normal * w.offset;
  const double scale = s.x.cwiseAbs().maxCoeff() + a.cwiseAbs().maxCoeff();
  return driven_exit(*this, s, t_end, plane_gap<double>(w.normal, a), plane_tolerance(w.slack, scale), everywhere);
}

template <class Real, int D>
double BasicMagneticDriveFlight<Real, D>::exit_time(const State& s, const TriangleWall& w, double t_end) const
  requires(D == 3) {
  const double scale = s.x.cwiseAbs().maxCoeff() + w.p[0].cwiseAbs().maxCoeff();
  return driven_exit(*this, s, t_end, plane_gap<double>(w.normal, w.p[0]), plane_tolerance(w.slack, scale),
                     [&](const Vec3& x) { return w.within_span(x); });
}

template <class Real, int D>
double BasicMagneticDriveFlight<Real, D>::exit_time(const State& s, const SphereWall& w, double t_end) const
  requires(D == 3) {
  const double sign = w.focusing ? 1 : -1, r = w.radius, scale = (s.x - w.center).norm() + r;
  return driven_exit(*this, s, t_end, round_gap(sign, w.center, r), round_tolerance(w.slack, scale, r), everywhere);
}

template <class Real, int D>
auto BasicMagneticFlight<Real, D>::advance(const State& s, const Real& t) const -> State {
  State r = s;
  std::tie(r.x, r.v) = scan_from(s).at(Real(t - s.t));
  r.t = t;
  return r;
}

template <class Real, int D>
Real BasicMagneticFlight<Real, D>::period() const {
  using std::abs;
  if constexpr (D == 2) return boost::math::constants::two_pi<Real>() / abs(omega_c);
  else return boost::math::constants::two_pi<Real>() / omega_c.norm();
}

// (Member by member: clang instantiates a whole class's members of the other dimension too.)
template Gyration<double, 2>::Gyration(const BasicMagneticFlight<double>&, const BasicState<double>&);
template std::pair<Vec2T<double>, Vec2T<double>> Gyration<double, 2>::at(const double&) const;
template double Gyration<double, 2>::period() const;
template double Gyration<double, 2>::exit_time(const BasicSegmentWall<double>&, const double&) const;
template double Gyration<double, 2>::exit_time(const BasicArcWall<double>&, const double&) const;
template FlightHit<BasicMagneticFlight<double>> Gyration<double, 2>::first_hit(const BasicTable<double>&, const double&) const;
template bool Gyration<double, 2>::scan_walls_without_closed_form(const BasicTable<double>&,
                                                                  FlightHit<BasicMagneticFlight<double>>&) const;
template BasicState<double> BasicMagneticFlight<double>::advance(const State&, const double&) const;
template double BasicMagneticFlight<double>::period() const;
template Gyration<long double, 2>::Gyration(const BasicMagneticFlight<long double>&, const BasicState<long double>&);
template std::pair<Vec2T<long double>, Vec2T<long double>> Gyration<long double, 2>::at(const long double&) const;
template long double Gyration<long double, 2>::period() const;
template long double Gyration<long double, 2>::exit_time(const BasicSegmentWall<long double>&, const long double&) const;
template long double Gyration<long double, 2>::exit_time(const BasicArcWall<long double>&, const long double&) const;
template FlightHit<BasicMagneticFlight<long double>> Gyration<long double, 2>::first_hit(const BasicTable<long double>&, const long double&) const;
template BasicState<long double> BasicMagneticFlight<long double>::advance(const State&, const long double&) const;
template long double BasicMagneticFlight<long double>::period() const;
template Gyration<Reference, 2>::Gyration(const BasicMagneticFlight<Reference>&, const BasicState<Reference>&);
template std::pair<Vec2T<Reference>, Vec2T<Reference>> Gyration<Reference, 2>::at(const Reference&) const;
template Reference Gyration<Reference, 2>::period() const;
template Reference Gyration<Reference, 2>::exit_time(const BasicSegmentWall<Reference>&, const Reference&) const;
template Reference Gyration<Reference, 2>::exit_time(const BasicArcWall<Reference>&, const Reference&) const;
template FlightHit<BasicMagneticFlight<Reference>> Gyration<Reference, 2>::first_hit(const BasicTable<Reference>&, const Reference&) const;
template BasicState<Reference> BasicMagneticFlight<Reference>::advance(const State&, const Reference&) const;
template Reference BasicMagneticFlight<Reference>::period() const;
template BasicDrivenState<double> BasicMagneticDriveFlight<double>::advance(const State&, const double&) const;
template double BasicMagneticDriveFlight<double>::speed_bound(const State&, const double&) const;
template double BasicMagneticDriveFlight<double>::exit_time(const State&, const BasicSegmentWall<double>&, const double&) const;
template double BasicMagneticDriveFlight<double>::exit_time(const State&, const BasicArcWall<double>&, const double&) const;
template BasicDrivenState<long double> BasicMagneticDriveFlight<long double>::advance(const State&, const long double&) const;
template long double BasicMagneticDriveFlight<long double>::speed_bound(const State&, const long double&) const;
template long double BasicMagneticDriveFlight<long double>::exit_time(const State&, const BasicSegmentWall<long double>&, const long double&) const;
template long double BasicMagneticDriveFlight<long double>::exit_time(const State&, const BasicArcWall<long double>&, const long double&) const;
template Gyration<double, 3>::Gyration(const MagneticFlight3&, const State3&);
template std::pair<Vec3, Vec3> Gyration<double, 3>::at(const double&) const;
template double Gyration<double, 3>::period() const;
template double Gyration<double, 3>::exit_time(const PlaneWall&, double) const;
template double Gyration<double, 3>::exit_time(const TriangleWall&, double) const;
template double Gyration<double, 3>::exit_time(const SphereWall&, double) const;
template Tube3 Gyration<double, 3>::tube() const;
template State3 MagneticFlight3::advance(const State&, const double&) const;
template double MagneticFlight3::period() const;
template DrivenState3 MagneticDriveFlight3::advance(const State&, const double&) const;
template double MagneticDriveFlight3::speed_bound(const State&, const double&) const;
template double MagneticDriveFlight3::exit_time(const State&, const PlaneWall&, double) const;
template double MagneticDriveFlight3::exit_time(const State&, const TriangleWall&, double) const;
template double MagneticDriveFlight3::exit_time(const State&, const SphereWall&, double) const;

namespace {
/// Instantiates the magnetic drive's scanned exit time for every wall kind (a kind added to
/// WallKinds or WallKinds3 needs no line here).
template <class Flight, class... W>
auto scanned_exit_times(std::tuple<W...>*) {
  return std::tuple{&Flight::template exit_time<W>...};
}
[[gnu::used]] const auto scanned_double =
    scanned_exit_times<MagneticDriveFlight>(static_cast<WallKinds<double>*>(nullptr));
[[gnu::used]] const auto scanned_long_double =
    scanned_exit_times<BasicMagneticDriveFlight<long double>>(static_cast<WallKinds<long double>*>(nullptr));
[[gnu::used]] const auto scanned_3 = scanned_exit_times<MagneticDriveFlight3>(static_cast<WallKinds3*>(nullptr));
}  // namespace

}  // namespace billiards::dynamics
