#include "billiards/dynamics/lockstep.hpp"

#include <algorithm>
#include <tuple>

namespace billiards::dynamics {

namespace lockstep {

static_assert(max_walls == scan::windows_group_walls, "the lanes search a table's walls in the scalar search's groups");

Kernel chosen_kernel() {
  static const Kernel k = kernel_of(simd::chosen_target());
  return k;
}

}  // namespace lockstep

namespace {

/// The drive's numbers as every flight's Quiver computes them.
lockstep::Drive drive_of(const PeriodicDriveFlight& flight) {
  DrivenState rest;
  rest.x = rest.v = Vec2::Zero();
  const Quiver<PeriodicDriveFlight, DrivenState> q(flight, rest);
  return {flight.omega, flight.accel.x(), flight.accel.y(), q.amp_x.x(), q.amp_x.y(), q.amp_v.x(), q.amp_v.y(),
          q.accel_norm, q.inv_omega, q.delta};
}

/// Walls first … first + count − 1 of the segments, then the arcs, field by field, padded
/// with the last to max_walls.
lockstep::Walls walls_of(const Walls<SegmentWall>& segments, const Walls<ArcWall>& arcs, int first,
                         int count) {
  lockstep::Walls w{};
  const int n_segments = int(segments.size());
  w.count = count, w.segments = std::clamp(n_segments - first, 0, count);
  for (int i = 0; i < lockstep::max_walls && count > 0; ++i) {
    const int k = first + std::min(i, count - 1);
    w.arc[i] = k >= n_segments ? -1 : 0;
    if (k < n_segments) {
      const auto& g = segments[std::size_t(k)];
      w.slack[i] = g.slack, w.ax[i] = g.a.x(), w.ay[i] = g.a.y(), w.bx[i] = g.b.x(), w.by[i] = g.b.y();
      w.nx[i] = g.normal.x(), w.ny[i] = g.normal.y(), w.dir_x[i] = g.dir.x(), w.dir_y[i] = g.dir.y();
      w.dir_norm[i] = g.dir.norm(), w.span_tol[i] = g.span_tol;
    } else {
      const auto& a = arcs[std::size_t(k - n_segments)];
      w.slack[i] = a.slack, w.cx[i] = a.center.x(), w.cy[i] = a.center.y(), w.r[i] = a.radius;
      w.sign[i] = a.focusing ? 1 : -1, w.fx[i] = a.from.x(), w.fy[i] = a.from.y(), w.tx[i] = a.to.x(), w.ty[i] = a.to.y();
      w.full[i] = a.full ? -1 : 0, w.half[i] = a.ccw_extent <= geometry::pi ? -1 : 0;
    }
  }
  return w;
}

}  // namespace

LockstepTable::LockstepTable(const Table& table, const PeriodicDriveFlight& flight, lockstep::Kernel kernel)
    : table_(&table), flight_(&flight), kernel_(kernel) {
  const auto& segments = table.segments();
  const auto& arcs = table.arcs();
  // (DrivenScan::first_hit searches a table of more walls than it takes in windows wall by
  // wall: not in lanes.)
  usable_ = kernel && table.wall_count() <= std::size_t(scan::windows_in_time_order_walls);
  if (!usable_) return;
  drive_ = drive_of(flight);
  const auto& classes = table.classes();
  cells_ = {classes.origin.x(), classes.origin.y(), classes.inverse_cell.x(), classes.inverse_cell.y(),
            classes.nx,         classes.ny,         classes.cell.data()};
  // The segments and arcs in scan::first_hit_in_windows' groups.
  const int count = int(segments.size() + arcs.size());
  for (int first = 0; first < count; first += lockstep::max_walls)
    groups_.push_back({walls_of(segments, arcs, first, std::min(count - first, lockstep::max_walls)), first});
  for (const auto& w : table.elliptic_arcs()) {
    elliptic_.push_back({walls_of({}, {w.unit}, 0, 1), drive_of(mapped(flight, w))});
    elliptic_.back().walls.make_states = false;
  }
}

void LockstepTable::collisions(const DrivenState* const* states, const double* t_end, int n,
                               FlightHit<PeriodicDriveFlight>* hits) const {
  lockstep::Flights in{};
  bool scalar[lockstep::lanes];  // lanes left to the scalar search
  for (int i = 0; i < n; ++i) {
    const DrivenState& s = *states[i];
    // (Without a horizon: the scalar search.)
    scalar[i] = !(t_end[i] < never);
    if (scalar[i]) continue;
    in.active[i] = -1;
    in.sx[i] = s.x.x(), in.sy[i] = s.x.y(), in.vx[i] = s.v.x(), in.vy[i] = s.v.y();
    in.t[i] = s.t, in.phase_hi[i] = s.phase.hi, in.phase_lo[i] = s.phase.lo;
    in.sin_phase[i] = s.sin_phase, in.cos_phase[i] = s.cos_phase;
    in.tau_end[i] = t_end[i] - s.t;
    hits[i] = {};
    hits[i].t = t_end[i];
  }
  // As DrivenScan::first_hit and `collision` make the hit: the segments' and arcs' windows,
  // group after group up to the best hit so far (the kernel made the hit's state, or left it
  // to be made here)...
  lockstep::Hits out;
  auto lanes_left = [&] { return std::find(scalar, scalar + n, false) != scalar + n; };
  for (const auto& group : groups_) {
    if (!lanes_left()) break;
    for (int i = 0; i < n; ++i) in.active[i] = scalar[i] ? 0 : -1;
    kernel_(group.walls, drive_, cells_, in, out);
    for (int i = 0; i < n; ++i) {
      scalar[i] |= out.handed_back[i];
      if (scalar[i] || out.wall[i] < 0) continue;
      lane_hit(*states[i], out, i, group.first, hits[i]);
      in.tau_end[i] = out.tau[i];
    }
  }
  // ...then each elliptic arc up to the best hit so far, as DrivenScan::exit_time searches it:
  // the mapped flight through the unit arc, in its windows (a lane handed back there: that
  // arc's scalar search).
  bool elliptic[lockstep::lanes] = {};
  for (std::size_t k = 0; k < elliptic_.size(); ++k) {
    const auto& w = table_->elliptic_arcs()[k];
    if (!lanes_left()) break;
    lockstep::Flights m = in;
    for (int i = 0; i < n; ++i) {
      m.active[i] = scalar[i] ? 0 : -1;
      if (scalar[i]) continue;
      const DrivenState s = mapped_state(*states[i], w);
      m.sx[i] = s.x.x(), m.sy[i] = s.x.y(), m.vx[i] = s.v.x(), m.vy[i] = s.v.y();
      m.tau_end[i] = hits[i].t - s.t;
    }
    kernel_(elliptic_[k].walls, elliptic_[k].drive, cells_, m, out);
    for (int i = 0; i < n; ++i) {
      if (scalar[i]) continue;
      const DrivenState& s = *states[i];
      const double t = out.handed_back[i] ? flight_->scan_from(s).exit_time(w, hits[i].t)
                       : out.wall[i] >= 0 ? s.t + out.tau[i] : never;
      if (t < hits[i].t) hits[i].t = t, hits[i].wall = {wall_kind::elliptic_arc, int(k)}, elliptic[i] = true;
    }
  }
  for (int i = 0; i < n; ++i) {
    const DrivenState& s = *states[i];
    if (scalar[i]) {
      hits[i] = collision(*table_, *flight_, s, t_end[i]);
    } else if (elliptic[i]) {
      auto& hit = hits[i];
      hit.midpoint_inside = false;
      hit.state = flight_->advance(s, hit.t);
      std::tie(hit.point, hit.normal) = table_->contact(hit.wall, hit.state.x, hit.state.v);
    }
  }
}

void LockstepTable::lane_hit(const DrivenState& s, const lockstep::Hits& out, int i, int first,
                             FlightHit<PeriodicDriveFlight>& hit) const {
  const int wall = first + out.wall[i], segments = int(table_->segments().size());
  hit.wall = wall < segments ? WallId{wall_kind::segment, wall} : WallId{wall_kind::arc, wall - segments};
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
