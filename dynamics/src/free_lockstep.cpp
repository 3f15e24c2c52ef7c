#include "billiards/dynamics/free_lockstep.hpp"

#include <tuple>

namespace billiards::dynamics {

free_lanes::Kernel free_lanes::chosen_kernel() {
  static const Kernel k = kernel_of(simd::chosen_target());
  return k;
}

bool free_lanes::fits(const Table& table) {
  return table.segments().size() <= std::size_t(max_walls) && table.arcs().size() <= std::size_t(max_walls) &&
         table.elliptic_arcs().size() <= std::size_t(max_walls);
}

namespace {

free_lanes::Arc arc_of(const ArcWall& w) {
  const auto a = arc_lanes(w);
  return {a.cx, a.cy, a.r, a.r2, a.near, a.span_tol, a.from_x, a.from_y, a.to_x, a.to_y, a.focusing, a.full, a.half};
}

}  // namespace

free_lanes::Walls free_lanes::walls_of(const Table& table) {
  const auto& segments = table.segments();
  const auto& arcs = table.arcs();
  Walls walls;
  walls.segment_count = int(segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const auto g = segment_lanes(segments[i]);
    walls.segments[i] = {g.ax, g.ay, g.nx, g.ny, g.dir_x, g.dir_y, g.slack, g.span_tol};
  }
  walls.arc_count = int(arcs.size());
  for (std::size_t i = 0; i < arcs.size(); ++i) walls.arcs[i] = arc_of(arcs[i]);
  const auto& ellipses = table.elliptic_arcs();
  walls.ellipse_count = int(ellipses.size());
  for (std::size_t i = 0; i < ellipses.size(); ++i) {
    const auto m = ellipse_map_lanes(ellipses[i]);
    walls.ellipses[i] = {m.cx, m.cy, m.l00, m.l01, m.l10, m.l11, arc_of(ellipses[i].unit)};
  }
  return walls;
}

FreeLockstepTable::FreeLockstepTable(const Table& table, const FreeFlight& flight, free_lanes::Kernel kernel)
    : table_(&table), flight_(&flight), kernel_(kernel), usable_(kernel && !table.grid() && free_lanes::fits(table)) {
  if (usable_) walls_ = free_lanes::walls_of(table);
}

void FreeLockstepTable::collisions(const State* const* states, const double* t_end, int n,
                                   FlightHit<FreeFlight>* hits) const {
  free_lanes::Rays in;
  for (int i = 0; i < free_lanes::lanes; ++i) {
    const State& s = *states[i < n ? i : 0];  // (lanes beyond n: a copy of the first)
    in.x[i] = s.x.x(), in.y[i] = s.x.y(), in.vx[i] = s.v.x(), in.vy[i] = s.v.y();
    in.t[i] = s.t, in.vv[i] = s.v.squaredNorm(), in.t_end[i] = t_end[i < n ? i : 0];
  }
  free_lanes::Hits out;
  kernel_(walls_, in, out);
  for (int i = 0; i < n; ++i) {
    const State& s = *states[i];
    auto& hit = hits[i];
    if (out.handed_back[i]) {
      hit = collision(*table_, *flight_, s, t_end[i]);
      continue;
    }
    // As `collision` makes the hit.
    hit.t = out.t[i];
    hit.wall = out.kind[i] < 0 ? WallId{} : WallId{int(out.kind[i]), int(out.index[i])};
    hit.midpoint_inside = false;
    if (!hit.found()) continue;
    hit.state = flight_->advance(s, hit.t);
    std::tie(hit.point, hit.normal) = table_->contact(hit.wall, hit.state.x, hit.state.v);
  }
}

}  // namespace billiards::dynamics
