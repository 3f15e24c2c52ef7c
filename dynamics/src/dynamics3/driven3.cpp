#include "billiards/dynamics3/driven3.hpp"

#include "billiards/dynamics/certified_scan.hpp"

namespace billiards::dynamics3 {

namespace {

using Quiver3 = dynamics::scan::Quiver<PeriodicDriveFlight3, DrivenState3>;
const auto no_window_passed = [](double, double) { return false; };  // no spans to cull by
const auto everywhere = [](const Vec3&) { return true; };

/// The distance of q's oscillation segment from the plane through a with normal n (the
/// certified scan's clearance for a creeping flight).
auto plane_clearance(const Quiver3& q, const Vec3& n, const Vec3& a) {
  return [&q, n, a](double tau) {
    const auto [p, r] = q.sweep(tau);
    return dynamics::scan::segment_plane_distance(p, r, n, a);
  };
}

}  // namespace

void DrivenState3::set_phase(const dynamics::Phase& theta) {
  phase = dynamics::reduce_phase(theta);
  std::tie(sin_phase, cos_phase) = dynamics::sin_cos(double(phase));
}

DrivenState3 PeriodicDriveFlight3::start(const State3& s) const {
  DrivenState3 d;
  static_cast<State3&>(d) = s;
  d.set_phase(dynamics::advance_phase(dynamics::Phase(phase0), omega, s.t));
  return d;
}

DrivenState3 PeriodicDriveFlight3::advance(const State& s, double t) const {
  const double tau = t - s.t;
  State r = s;
  r.set_phase(dynamics::advance_phase(s.phase, omega, tau));
  const auto [amp_x, amp_v] = dynamics::drive_amplitudes(accel, omega);
  r.v = s.v + amp_v * (r.sin_phase - s.sin_phase);
  r.x = s.x + (s.v - amp_v * s.sin_phase) * tau - amp_x * (r.cos_phase - s.cos_phase);
  r.t = t;
  return r;
}

double PeriodicDriveFlight3::exit_time(const State& s, const PlaneWall& w, double t_end) const {
  // A face of a convex polyhedron has no span: the first plane crossed outward is the exit.
  const Quiver3 q(*this, s);
  const Vec3 a = w.normal * w.offset;
  const double tau = dynamics::scan::with_creep(q, [&](auto clearance) {
    return dynamics::scan::driven_exit_through_plane(q, w.normal, a, w.slack, t_end - s.t, no_window_passed, everywhere,
                                                     clearance);
  }, plane_clearance(q, w.normal, a));
  return tau == never ? never : s.t + tau;
}

double PeriodicDriveFlight3::exit_time(const State& s, const TriangleWall& w, double t_end) const {
  const Quiver3 q(*this, s);
  // The particle stays within δ of the guiding segment, along which each edge's signed
  // distance is linear: when both ends are beyond the same edge by more than δ and the slack,
  // no point of the window is within the widened span.
  auto passes = [&](double tau, double end) {
    const Vec3 a = q.guide(tau), b = q.guide(end);
    for (int k = 0; k < 3; ++k) {
      const Vec3 pa = a - w.p[k], pb = b - w.p[k];
      const double da = w.edge_normal[k].dot(pa), db = w.edge_normal[k].dot(pb);
      const double rounding = 8 * dynamics::scan::eps<double> * (pa.cwiseAbs().sum() + pb.cwiseAbs().sum());
      const double margin = w.slack + q.delta + rounding;
      if (da > margin && db > margin) return true;
    }
    return false;
  };
  auto in_span = [&](const Vec3& x) { return w.within_span(x); };
  // (The triangle's plane: a lower bound of the distance from the triangle.)
  const double tau = dynamics::scan::with_creep(q, [&](auto clearance) {
    return dynamics::scan::driven_exit_through_plane(q, w.normal, w.p[0], w.slack, t_end - s.t, passes, in_span,
                                                     clearance);
  }, plane_clearance(q, w.normal, w.p[0]));
  return tau == never ? never : s.t + tau;
}

double PeriodicDriveFlight3::exit_time(const State& s, const SphereWall& w, double t_end) const {
  const Quiver3 q(*this, s);
  auto clearance = [&](double tau) {
    const auto [a, b] = q.sweep(tau);
    return dynamics::scan::segment_sphere_distance(a, b, w.center, w.radius);
  };
  const double tau = dynamics::scan::with_creep(q, [&](auto clearance) {
    return dynamics::scan::driven_exit_through_sphere(q, w.center, w.radius, w.focusing, w.slack, t_end - s.t,
                                                      no_window_passed, everywhere, clearance);
  }, clearance);
  return tau == never ? never : s.t + tau;
}

}  // namespace billiards::dynamics3
