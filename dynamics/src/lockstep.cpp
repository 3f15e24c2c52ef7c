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
  const auto& arcs = table.arcs();
  usable_ = kernel && !arcs.empty() && table.wall_count() == arcs.size() && arcs.size() <= std::size_t(lockstep::max_arcs);
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
  arcs_.count = int(arcs.size());
  for (int i = 0; i < lockstep::max_arcs; ++i) {
    const auto& w = arcs[std::size_t(std::min(i, arcs_.count - 1))];
    arcs_.cx[i] = w.center.x(), arcs_.cy[i] = w.center.y(), arcs_.r[i] = w.radius, arcs_.sign[i] = w.focusing ? 1 : -1;
    arcs_.slack[i] = w.slack, arcs_.fx[i] = w.from.x(), arcs_.fy[i] = w.from.y(), arcs_.tx[i] = w.to.x(),
    arcs_.ty[i] = w.to.y();
    arcs_.full[i] = w.full ? -1 : 0, arcs_.half[i] = w.ccw_extent <= geometry::pi ? -1 : 0;
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
  if (any) kernel_(arcs_, drive_, cells_, in, out);
  for (int i = 0; i < n; ++i) {
    const DrivenState& s = *states[i];
    if (!in.active[i] || out.handed_back[i]) {
      hits[i] = collision(*table_, *flight_, s, t_end[i]);
      continue;
    }
    // As DrivenScan::first_hit and `collision` make the hit: the kernel made its state, or
    // left it to be made here.
    auto& hit = hits[i] = {};
    hit.t = t_end[i];
    if (out.wall[i] < 0) continue;
    hit.wall = {wall_kind::arc, out.wall[i]};
    hit.midpoint_inside = out.midpoint_inside[i];
    if (out.made[i]) {
      hit.t = out.t[i];
      auto& r = hit.state;
      r.x = Vec2(out.x[i], out.y[i]), r.v = Vec2(out.vx[i], out.vy[i]), r.t = out.t[i];
      r.phase = Phase(out.phase_hi[i], out.phase_lo[i]), r.sin_phase = out.sin_phase[i], r.cos_phase = out.cos_phase[i];
      hit.point = Vec2(out.point_x[i], out.point_y[i]), hit.normal = Vec2(out.normal_x[i], out.normal_y[i]);
      continue;
    }
    hit.t = s.t + out.tau[i];
    hit.state = flight_->advance(s, hit.t, PhaseSample<double>{out.theta[i], out.sin[i], out.cos[i]});
    std::tie(hit.point, hit.normal) = table_->contact(hit.wall, hit.state.x, hit.state.v);
  }
}

}  // namespace billiards::dynamics
