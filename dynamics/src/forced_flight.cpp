#include "billiards/dynamics/forced_flight.hpp"

#include "billiards/dynamics/certified_scan.hpp"
#include "billiards/dynamics/precision.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <tuple>

namespace billiards::dynamics {

namespace {

using scan::eps;
using scan::first_outward_crossing;
using scan::Sample;
}  // namespace

// ---- Periodic drive ---------------------------------------------------------------------

template <class Real, int D>
auto BasicPeriodicDriveFlight<Real, D>::start(const BasicState<Real, D>& s) const -> State {
  using P = PhaseOf<Real>;
  State d;
  static_cast<BasicState<Real, D>&>(d) = s;
  d.set_phase(advance_phase(P(phase0), omega, s.t));
  return d;
}

namespace {

/// The state's phase at τ after s, from `near` when known.
template <class Real, int D>
void set_phase_at(BasicDrivenState<Real, D>& r, const BasicDrivenState<Real, D>& s, const Real& omega, const Real& tau,
                  const PhaseSample<Real>& near) {
  const auto theta = advance_phase(s.phase, omega, tau);
  if (near.known() && near.near(theta))
    r.set_phase(theta, near.at(theta));
  else
    r.set_phase(theta);
}

}  // namespace

template <class Real, int D>
auto BasicPeriodicDriveFlight<Real, D>::advance(const State& s, const Real& t, const PhaseSample<Real>& near) const
    -> State {
  const Real tau = t - s.t;
  State r = s;
  set_phase_at(r, s, omega, tau, near);
  const auto [amp_x, amp_v] = drive_amplitudes(accel, omega);
  r.v = scan::advanced_velocity(s.v, amp_v, r.sin_phase, s.sin_phase);
  r.x = scan::advanced_position(s.x, scan::guide_velocity(s.v, amp_v, s.sin_phase), tau, amp_x, r.cos_phase, s.cos_phase);
  r.t = t;
  return r;
}

namespace {

/// Can the flight described by the Quiver q come near the wall before τ_end at all?  The wall
/// lies in its bounding disk, the particle within δ of the guiding line, and a collision is
/// declared within the scan's rounding band (the slack and a few ulps) of the wall: when the
/// guiding line stays farther than twice all that from the disk until τ_end, the wall has no
/// collision, and none of its windows need be computed.  (The band grows with τ: with no
/// horizon, every wall is scanned.)
template <class Real, class Q, class Wall>
bool may_come_near(const Q& q, const Wall& w, const Real& tau_end) {
  if (tau_end == never) return true;
  const Vec2T<Real> g = q.g0 - w.bound_center;
  const Real rounding = 16 * eps<Real> * (g.template lpNorm<1>() + w.bound_radius + q.speed_bound * tau_end + q.delta);
  const Real reach = w.bound_radius + 2 * (q.delta + w.slack + rounding);
  return scan::reach_radius(Real(0), g, q.u, reach, false) <= tau_end;
}

/// The distance of q's oscillation segment from the wall at τ (scan::creep's clearance).
template <class Q, class Wall>
auto clearance_of(const Q& q, const Wall& w) {
  return [&q, &w](const auto& tau) {
    const auto [p, r] = q.sweep(tau);
    return w.distance(p, r);
  };
}

/// Exit time through one wall (a segment or an arc: its gap_along) of a flight described by the
/// Quiver q (lab or quivering walls).
template <class Real, class Q, class Wall>
Real driven_exit_time(const Q& q, const Wall& w, const Real& t0, const Real& t_end) {
  if (!may_come_near(q, w, Real(t_end - t0))) return Real(never);
  // A crossing counts only if the particle, within δ of the guiding point, can be in the
  // wall's span.
  auto passes = [&](const Real& tau, const Real& end) { return !w.may_meet_span(q.guide(tau), q.guide(end), q.delta); };
  auto in_span = [&](const Vec2T<Real>& x) { return w.within_span(x); };
  const Real tau = scan::with_creep(q, [&](auto clearance) {
    return scan::scan_windows(q, w.gap_along(q), passes, in_span, clearance, Real(t_end - t0));
  }, clearance_of(q, w));
  return tau == never ? Real(never) : Real(t0 + tau);
}

/// Does a wall of kind W have windows along the flight q (`gap_along`: segments and arcs)?
template <class W, class Q>
concept has_windows = requires(const W& w, const Q& q) { w.gap_along(q); };
template <class Q>
struct Windowed {
  template <class W>
  struct along : std::bool_constant<has_windows<W, Q>> {};
};

/// fn(gap, passes, in_span) for a wall with windows along the flight q: what
/// scan::first_hit_in_windows' `visit` gives it.
template <class Real, class Q, class Wall, class Fn>
void visit_windowed(const Q& q, const Wall& wall, Fn&& fn) {
  // A window in which the particle cannot reach the wall's span is passed unsampled.
  auto passes = [&](const Real& start, const Real& end) {
    return !wall.may_meet_span(q.guide(start), q.guide(end), q.delta);
  };
  auto in_span = [&wall](const Vec2T<Real>& x) { return wall.within_span(x); };
  fn(wall.gap_along(q), passes, in_span);
}

/// The first hit of the flight q among the table's walls that have windows before best.t,
/// into `best` (t and wall) and `phase`.
template <class Real, class Q>
void first_hit_in_windows(const BasicTable<Real>& table, const Q& q, BasicHit<Real>& best, PhaseSample<Real>& phase) {
  Real tau_best = best.t - q.s.t;
  const NumberedWalls<BasicTable<Real>, Windowed<Q>::template along> walls(table);
  auto visit = [&](int w, auto&& fn) { walls.visit(w, [&](const auto& wall) { visit_windowed<Real>(q, wall, fn); }); };
  int best_wall = -1;
  scan::first_hit_in_windows(walls.count(), visit, tau_best, best_wall, phase);
  if (best_wall >= 0) {
    best.t = q.s.t + tau_best;
    best.wall = walls.id(best_wall);
  }
}

/// The first hit of the flight q through one wall with windows before τ = tau_best, searched
/// as a table's are: true, and tau_best updated, if there is one.
template <class Real, class Q, class Wall>
bool first_hit_in_windows(const Q& q, const Wall& wall, Real& tau_best) {
  PhaseSample<Real> phase;
  int hit = -1;
  auto visit = [&](int, auto&& fn) { visit_windowed<Real>(q, wall, fn); };
  scan::first_hit_in_windows(1, visit, tau_best, hit, phase);
  return hit == 0;
}

}  // namespace

template <class Flight>
auto DrivenScan<Flight>::first_hit(const BasicTable<Real>& table, const Real& t_end) const -> FlightHit<Flight> {
  BasicHit<Real> best;
  best.t = t_end;
  PhaseSample<Real> phase;  // the drive's phase sampled at the best root, if it was
  // A table of many walls (it has a grid): those listed near the guiding line, cell by cell
  // along it, each by its own scan (the particle stays within δ of the guide).  Wall by wall
  // for creeping guides in the others (creep's jumps are interleaved with the windows of one
  // wall at a time).
  static_assert(scan::windows_in_time_order_walls == BasicTable<Real>::grid_threshold);
  if (table.grid()) {
    const Vec2 g0(double(quiver.g0.x()), double(quiver.g0.y())), u(double(quiver.u.x()), double(quiver.u.y()));
    detail::tube_collision(table, *this, g0, u, double(quiver.s.t), double(quiver.delta), best);
  } else if (quiver.creeping) {
    detail::try_every_wall(table, *this, best);
  } else {
    first_hit_in_windows(table, quiver, best, phase);
    if (first_hit_without_windows(table, best)) phase = {};
  }
  if (!best.found()) return {best, {}};
  // (The state made in place, as `collision` makes the hit: see there.)
  return {best, quiver.flight.advance(quiver.s, best.t, phase)};
}

template <class Flight>
bool DrivenScan<Flight>::first_hit_without_windows(const BasicTable<Real>& table, BasicHit<Real>& best) const {
  const Real before = best.t;
  table.for_each_kind([&]<class W>(const Walls<W>& walls, int kind) {
    if constexpr (!has_windows<W, decltype(quiver)>) detail::try_walls(walls, kind, *this, best);
  });
  return best.t < before;
}

template <class Flight>
auto DrivenScan<Flight>::exit_time(const BasicSegmentWall<Real>& w, const Real& t_end) const -> Real {
  return driven_exit_time(quiver, w, quiver.s.t, t_end);
}

template <class Flight>
auto DrivenScan<Flight>::exit_time(const BasicArcWall<Real>& w, const Real& t_end) const -> Real {
  return driven_exit_time(quiver, w, quiver.s.t, t_end);
}

template <class Flight>
auto DrivenScan<Flight>::exit_time(const BasicEllipticArcWall<Real>& w, const Real& t_end) const -> Real {
  // The mapped flight through the unit arc (elliptic_exit_time), searched in its windows as a
  // table's arcs are unless it creeps: so the lock-step search, which searches it so in lanes
  // (LockstepTable), finds the same hit.
  const Flight flight = mapped(quiver.flight, w);
  const typename Flight::State s = mapped_state(quiver.s, w);
  const DrivenScan unit = flight.scan_from(s);
  if (unit.quiver.creeping) return unit.exit_time(w.unit, t_end);
  Real tau = t_end - s.t;
  return first_hit_in_windows(unit.quiver, w.unit, tau) ? Real(s.t + tau) : Real(never);
}

// ---- Quivering walls ---------------------------------------------------------------------

template <class Real>
auto BasicQuiveringWallFlight<Real>::advance(const State& s, const Real& t, const PhaseSample<Real>& near) const
    -> State {
  const Real tau = t - s.t;
  State r = s;
  set_phase_at(r, s, omega, tau, near);
  r.x = scan::advanced_position(s.x, s.v, tau, drive_amplitudes(accel, omega).first, r.cos_phase, s.cos_phase);
  r.t = t;
  return r;
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
  // f is a parabola: once it falls (f' ≤ 0) under a force away from the wall, or is beyond the
  // wall and rising under a force towards it, it never crosses outward again.  Without this
  // the scan, with no horizon, stepped on until τ² overflowed and f became NaN.
  auto earliest = [&](const Real& tau) {
    const auto p = sample(tau);
    const bool never_again = (p.df <= 0 && n_a <= 0) || (p.f > tolerance(tau) && p.df >= 0 && n_a >= 0);
    return never_again ? Real(never) : tau;
  };
  auto in_span = [&](const Vec2T<Real>& x) { return w.within_span(x); };
  const Real tau = first_outward_crossing(sample, earliest, in_span, tolerance, Real(t_end - s.t));
  return tau == never ? Real(never) : Real(s.t + tau);
}

template <class Real>
Real BasicConstantForceFlight<Real>::exit_time(const State& s, const BasicArcWall<Real>& w, const Real& t_end) const {
  using std::abs;
  const Real sign = w.focusing ? 1 : -1;
  const Real A = accel.norm();
  const Real scale = (s.x - w.center).norm() + w.radius;
  auto tolerance = [&](const Real& tau) {
    return Real(w.slack + 8 * eps<Real> * (scale + s.v.norm() * tau + A * tau * tau));
  };
  auto sample = [&](const Real& tau) {
    const auto [x, v] = parabola(s, accel, tau);
    const Vec2T<Real> p = x - w.center;
    const Real rho = p.norm(), V = v.norm(), f = sign * (rho - w.radius);
    // Nearer the centre than the circle (where the bound below fails: a particle at the centre
    // never got away), f moves by at most V s + A s²/2 in time s.
    if (rho < abs(f)) return Sample<Real>{f, f < 0 ? V : Real(-V), A, Real(never), x};
    // Over a step of length h ≤ ρ/(2V'), |v| ≤ V' = V + A h and |p| ≥ ρ/2.
    const Real h = rho / (2 * (V + A));
    const Real Vmax = V + A * h;
    return Sample<Real>{f, sign * p.dot(v) / rho, 2 * Vmax * Vmax / rho + A, h, x};
  };
  // |p|² (p from the centre) is a quartic in τ whose Taylor coefficients at τ are |p|², 2p·v,
  // |v|² + p·a, v·a and |a|²/4 ≥ 0: when the middle three are ≥ 0 the distance from the centre
  // never decreases again, so f never rises again on a dispersing wall, and beyond a focusing
  // one never returns.  (Otherwise, as for segments, the scan overflowed.)
  auto earliest = [&](const Real& tau) {
    const auto [x, v] = parabola(s, accel, tau);
    const Vec2T<Real> p = x - w.center;
    const bool receding = p.dot(v) >= 0 && v.squaredNorm() + p.dot(accel) >= 0 && v.dot(accel) >= 0;
    const bool never_again = receding && (!w.focusing || p.norm() - w.radius > tolerance(tau));
    return never_again ? Real(never) : tau;
  };
  auto in_span = [&](const Vec2T<Real>& x) { return w.within_span(x); };
  const Real tau = first_outward_crossing(sample, earliest, in_span, tolerance, Real(t_end - s.t));
  return tau == never ? Real(never) : Real(s.t + tau);
}

// ---- Periodic drive in 3-D: planes, mesh triangles, spheres --------------------------------

namespace {

using Quiver3 = Quiver<PeriodicDriveFlight3, DrivenState3>;
const auto no_window_passed = [](double, double) { return false; };  // no spans to cull by
const auto everywhere = [](const Vec3&) { return true; };

/// The distance of q's oscillation segment from the plane through a with normal n (the
/// certified scan's clearance for a creeping flight).
auto plane_clearance(const Quiver3& q, const Vec3& n, const Vec3& a) {
  return [&q, n, a](double tau) {
    const auto [p, r] = q.sweep(tau);
    return segment_plane_distance(p, r, n, a);
  };
}

}  // namespace

template <class Real, int D>
double BasicPeriodicDriveFlight<Real, D>::exit_time(const State& s, const PlaneWall& w, double t_end) const
  requires(D == 3) {
  // A face of a convex polyhedron has no span: the first plane crossed outward is the exit.
  const Quiver3 q(*this, s);
  const double tau = scan::with_creep(q, [&](auto clearance) {
    return scan::scan_windows(q, w.gap_along(q), no_window_passed, everywhere, clearance, t_end - s.t);
  }, plane_clearance(q, w.normal, Vec3(w.normal * w.offset)));
  return tau == never ? never : s.t + tau;
}

template <class Real, int D>
double BasicPeriodicDriveFlight<Real, D>::exit_time(const State& s, const TriangleWall& w, double t_end) const
  requires(D == 3) {
  const Quiver3 q(*this, s);
  // The particle stays within δ of the guiding segment, along which each edge's signed
  // distance is linear: when both ends are beyond the same edge by more than δ and the slack,
  // no point of the window is within the widened span.
  auto passes = [&](double tau, double end) {
    const Vec3 a = q.guide(tau), b = q.guide(end);
    for (int k = 0; k < 3; ++k) {
      const Vec3 pa = a - w.p[k], pb = b - w.p[k];
      const double da = w.edge_normal[k].dot(pa), db = w.edge_normal[k].dot(pb);
      const double rounding = 8 * eps<double> * (pa.cwiseAbs().sum() + pb.cwiseAbs().sum());
      const double margin = w.slack + q.delta + rounding;
      if (da > margin && db > margin) return true;
    }
    return false;
  };
  auto in_span = [&](const Vec3& x) { return w.within_span(x); };
  // (The triangle's plane: a lower bound of the distance from the triangle.)
  const double tau = scan::with_creep(q, [&](auto clearance) {
    return scan::scan_windows(q, w.gap_along(q), passes, in_span, clearance, t_end - s.t);
  }, plane_clearance(q, w.normal, w.p[0]));
  return tau == never ? never : s.t + tau;
}

template <class Real, int D>
double BasicPeriodicDriveFlight<Real, D>::exit_time(const State& s, const SphereWall& w, double t_end) const
  requires(D == 3) {
  const Quiver3 q(*this, s);
  auto clearance = [&](double tau) {
    const auto [a, b] = q.sweep(tau);
    return segment_sphere_distance(a, b, w.center, w.radius);
  };
  const double tau = scan::with_creep(q, [&](auto clearance) {
    return scan::scan_windows(q, w.gap_along(q), no_window_passed, everywhere, clearance, t_end - s.t);
  }, clearance);
  return tau == never ? never : s.t + tau;
}

template struct DrivenScan<BasicPeriodicDriveFlight<double>>;
template struct DrivenScan<BasicPeriodicDriveFlight<long double>>;
template struct DrivenScan<BasicPeriodicDriveFlight<Reference>>;
template struct DrivenScan<BasicQuiveringWallFlight<double>>;
template struct DrivenScan<BasicQuiveringWallFlight<long double>>;
// (Member by member: a whole-class instantiation would also instantiate the members of the
// other dimension.)
template PeriodicDriveFlight::State PeriodicDriveFlight::start(const BasicState<double>&) const;
template PeriodicDriveFlight::State PeriodicDriveFlight::advance(const State&, const double&,
                                                                 const PhaseSample<double>&) const;
template BasicPeriodicDriveFlight<long double>::State BasicPeriodicDriveFlight<long double>::start(
    const BasicState<long double>&) const;
template BasicPeriodicDriveFlight<long double>::State BasicPeriodicDriveFlight<long double>::advance(
    const State&, const long double&, const PhaseSample<long double>&) const;
template BasicPeriodicDriveFlight<Reference>::State BasicPeriodicDriveFlight<Reference>::start(
    const BasicState<Reference>&) const;
template BasicPeriodicDriveFlight<Reference>::State BasicPeriodicDriveFlight<Reference>::advance(
    const State&, const Reference&, const PhaseSample<Reference>&) const;
template PeriodicDriveFlight3::State PeriodicDriveFlight3::start(const State3&) const;
template PeriodicDriveFlight3::State PeriodicDriveFlight3::advance(const State&, const double&,
                                                                   const PhaseSample<double>&) const;
template double PeriodicDriveFlight3::exit_time(const State&, const PlaneWall&, double) const;
template double PeriodicDriveFlight3::exit_time(const State&, const TriangleWall&, double) const;
template double PeriodicDriveFlight3::exit_time(const State&, const SphereWall&, double) const;
template struct BasicQuiveringWallFlight<double>;
template struct BasicQuiveringWallFlight<long double>;
template struct BasicConstantForceFlight<double>;
template struct BasicConstantForceFlight<long double>;
template struct BasicConstantForceFlight<Reference>;

}  // namespace billiards::dynamics
