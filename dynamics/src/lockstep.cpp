#include "billiards/dynamics/lockstep.hpp"

#include <algorithm>
#include <tuple>

namespace billiards::dynamics {

namespace lockstep {

Kernel chosen_kernel() {
  static const Kernel k = kernel_of(simd::chosen_target());
  return k;
}

}  // namespace lockstep

LockstepTable::LockstepTable(const Table& table, const PeriodicDriveFlight& flight, lockstep::Kernel kernel)
    : table_(&table), flight_(&flight), kernel_(kernel) {
  const auto& segments = table.segments();
  const auto& arcs = table.arcs();
  const std::size_t count = segments.size() + arcs.size();
  // (Elliptic arcs are searched after the lanes, as DrivenScan::first_hit searches them after
  // the windows; a table of more walls than that searches in windows is searched wall by wall.)
  usable_ = kernel && count > 0 && count <= std::size_t(lockstep::max_walls) &&
            table.wall_count() <= std::size_t(scan::windows_in_time_order_walls);
  without_windows_ = table.wall_count() > count;
  if (!usable_) return;
  // The drive's numbers as every flight's Quiver computes them.
  DrivenState rest;
  rest.x = rest.v = Vec2::Zero();
  const Quiver<PeriodicDriveFlight, DrivenState> q(flight, rest);
  drive_ = {flight.omega, flight.accel.x(), flight.accel.y(), q.amp_x.x(), q.amp_x.y(), q.amp_v.x(), q.amp_v.y(),
            q.accel_norm, q.inv_omega, q.delta};
  const auto& classes = table.classes();
  cells_ = {classes.origin.x(), classes.origin.y(), classes.inverse_cell.x(), classes.inverse_cell.y(),
            classes.nx,         classes.ny,         classes.cell.data()};
  walls_.count = int(count), walls_.segments = int(segments.size());
  for (int i = 0; i < lockstep::max_walls; ++i) {
    const int k = std::min(i, walls_.count - 1);  // (padding: the last wall again)
    auto& w = walls_;
    w.arc[i] = k >= w.segments ? -1 : 0;
    if (k < w.segments) {
      const auto& g = segments[std::size_t(k)];
      w.slack[i] = g.slack, w.ax[i] = g.a.x(), w.ay[i] = g.a.y(), w.bx[i] = g.b.x(), w.by[i] = g.b.y();
      w.nx[i] = g.normal.x(), w.ny[i] = g.normal.y(), w.dir_x[i] = g.dir.x(), w.dir_y[i] = g.dir.y();
      w.dir_norm[i] = g.dir.norm(), w.span_tol[i] = g.span_tol;
    } else {
      const auto& a = arcs[std::size_t(k - w.segments)];
      w.slack[i] = a.slack, w.cx[i] = a.center.x(), w.cy[i] = a.center.y(), w.r[i] = a.radius;
      w.sign[i] = a.focusing ? 1 : -1, w.fx[i] = a.from.x(), w.fy[i] = a.from.y(), w.tx[i] = a.to.x(), w.ty[i] = a.to.y();
      w.full[i] = a.full ? -1 : 0, w.half[i] = a.ccw_extent <= geometry::pi ? -1 : 0;
    }
  }
}

void LockstepTable::collisions(const DrivenState* const* states, const double* t_end, int n,
                               FlightHit<PeriodicDriveFlight>* hits) const {
  lockstep::Flights in{};
  bool any = false;
  for (int i = 0; i < n; ++i) {
    const DrivenState& s = *states[i];
    if (!(t_end[i] < never)) continue;  // (without a horizon: the scalar search)
    any = true;
    in.active[i] = -1;
    in.sx[i] = s.x.x(), in.sy[i] = s.x.y(), in.vx[i] = s.v.x(), in.vy[i] = s.v.y();
    in.t[i] = s.t, in.phase_hi[i] = s.phase.hi, in.phase_lo[i] = s.phase.lo;
    in.sin_phase[i] = s.sin_phase, in.cos_phase[i] = s.cos_phase;
    in.tau_end[i] = t_end[i] - s.t;
  }
  lockstep::Hits out;
  if (any) kernel_(walls_, drive_, cells_, in, out);
  for (int i = 0; i < n; ++i) {
    const DrivenState& s = *states[i];
    if (!in.active[i] || out.handed_back[i]) {
      hits[i] = collision(*table_, *flight_, s, t_end[i]);
      continue;
    }
    // As DrivenScan::first_hit and `collision` make the hit: the kernel made its state, or
    // left it to be made here; a wall without windows may be hit before.
    auto& hit = hits[i] = {};
    hit.t = t_end[i];
    if (out.wall[i] >= 0) lane_hit(s, out, i, hit);
    if (without_windows_ && flight_->scan_from(s).first_hit_without_windows(*table_, hit)) {
      hit.midpoint_inside = false;
      hit.state = flight_->advance(s, hit.t);
      std::tie(hit.point, hit.normal) = table_->contact(hit.wall, hit.state.x, hit.state.v);
    }
  }
}

void LockstepTable::lane_hit(const DrivenState& s, const lockstep::Hits& out, int i,
                             FlightHit<PeriodicDriveFlight>& hit) const {
  hit.wall = out.wall[i] < walls_.segments ? WallId{wall_kind::segment, out.wall[i]}
                                           : WallId{wall_kind::arc, out.wall[i] - walls_.segments};
  hit.midpoint_inside = out.midpoint_inside[i];
  if (out.made[i]) {
    hit.t = out.t[i];
    auto& r = hit.state;
    r.x = Vec2(out.x[i], out.y[i]), r.v = Vec2(out.vx[i], out.vy[i]), r.t = out.t[i];
    r.phase = Phase(out.phase_hi[i], out.phase_lo[i]), r.sin_phase = out.sin_phase[i], r.cos_phase = out.cos_phase[i];
    hit.point = Vec2(out.point_x[i], out.point_y[i]), hit.normal = Vec2(out.normal_x[i], out.normal_y[i]);
    return;
  }
  hit.t = s.t + out.tau[i];
  hit.state = flight_->advance(s, hit.t, PhaseSample<double>{out.theta[i], out.sin[i], out.cos[i]});
  std::tie(hit.point, hit.normal) = table_->contact(hit.wall, hit.state.x, hit.state.v);
}

}  // namespace billiards::dynamics
