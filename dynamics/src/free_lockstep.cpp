#include "billiards/dynamics/free_lockstep.hpp"

#include "billiards/dynamics/straight_exit3.hpp"

#include <tuple>

namespace billiards::dynamics {

template <>
free_lanes::Kernel free_lanes::chosen_kernel<2>() {
  static const Kernel k = kernel_of(simd::chosen_target());
  return k;
}
template <>
free_lanes::Kernel3 free_lanes::chosen_kernel<3>() {
  static const Kernel3 k = kernel3_of(simd::chosen_target());
  return k;
}
template <>
free_lanes::Propagator free_lanes::chosen_propagator<2>() {
  static const Propagator p = propagator_of(simd::chosen_target());
  return p;
}

bool free_lanes::fits(const Table& table) {
  return table.segments().size() <= std::size_t(max_walls) && table.arcs().size() <= std::size_t(max_walls);
}

namespace {

bool ellipses_fit(const Table& table) { return table.elliptic_arcs().size() <= std::size_t(free_lanes::max_walls); }

free_lanes::Arc arc_of(const ArcWall& w) {
  const auto a = arc_lanes(w);
  return {a.cx, a.cy, a.r, a.r2, a.near, a.span_tol, a.from_x, a.from_y, a.to_x, a.to_y, a.focusing, a.full, a.half};
}

/// The table's fine classes' cells inside (none when they are more than Cells holds).
free_lanes::Cells cells_of(const Table& table) {
  const Table::Classes& classes = table.fine_classes();
  free_lanes::Cells cells;
  if (classes.cell.size() > 64 * std::size_t(free_lanes::Cells::max_words)) return cells;
  cells.origin_x = classes.origin.x(), cells.origin_y = classes.origin.y();
  cells.inverse_x = classes.inverse_cell.x(), cells.inverse_y = classes.inverse_cell.y();
  cells.nx = classes.nx, cells.ny = classes.ny;
  for (std::size_t i = 0; i < classes.cell.size(); ++i)
    if (classes.cell[i] == Table::Classes::inside) cells.inside[i / 64] |= std::int64_t(std::uint64_t(1) << (i % 64));
  return cells;
}

}  // namespace

free_lanes::Walls free_lanes::walls_of(const Table& table) {
  const auto& segments = table.segments();
  const auto& arcs = table.arcs();
  Walls walls;
  walls.cells = cells_of(table);
  auto& c = walls.contacts;
  walls.segment_count = int(segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const auto g = segment_lanes(segments[i]);
    walls.segments[i] = {g.ax, g.ay, g.nx, g.ny, g.dir_x, g.dir_y, g.slack, g.span_tol};
    c.ax[i] = g.ax, c.ay[i] = g.ay, c.nx[i] = g.nx, c.ny[i] = g.ny, c.dir_x[i] = g.dir_x, c.dir_y[i] = g.dir_y;
    c.bx[i] = segments[i].b.x(), c.by[i] = segments[i].b.y();
  }
  walls.arc_count = int(arcs.size());
  for (std::size_t i = 0; i < arcs.size(); ++i) {
    const ArcWall& a = arcs[i];
    walls.arcs[i] = arc_of(a);
    c.cx[i] = a.center.x(), c.cy[i] = a.center.y(), c.r[i] = a.radius, c.r2[i] = a.radius2, c.slack[i] = a.slack;
    c.focusing |= std::uint64_t(a.focusing) << i;
  }
  if (!ellipses_fit(table)) return walls;
  const auto& ellipses = table.elliptic_arcs();
  walls.ellipse_count = int(ellipses.size());
  for (std::size_t i = 0; i < ellipses.size(); ++i) {
    const auto m = ellipse_map_lanes(ellipses[i]);
    walls.ellipses[i] = {m.cx, m.cy, m.l00, m.l01, m.l10, m.l11, arc_of(ellipses[i].unit)};
  }
  return walls;
}

free_lanes::Walls3 free_lanes::walls_of(const Table3& table) {
  Walls3 walls;
  walls.plane_count = int(table.planes().size());
  for (int i = 0; i < walls.plane_count; ++i) {
    const auto p = plane_lanes(table.planes()[std::size_t(i)]);
    walls.planes[i] = {p.nx, p.ny, p.nz, p.offset, p.slack};
  }
  walls.sphere_count = int(table.spheres().size());
  for (int i = 0; i < walls.sphere_count; ++i) {
    const auto b = sphere_lanes(table.spheres()[std::size_t(i)]);
    walls.spheres[i] = {b.cx, b.cy, b.cz, b.r, b.r2, b.near, b.focusing};
  }
  return walls;
}

namespace {

/// Can the kernel search the table: every wall of a kind it knows, few enough of each?
bool lanes_search(const Table& table) {
  const bool known = table.wall_count() == table.segments().size() + table.arcs().size() + table.elliptic_arcs().size();
  return known && !table.grid() && free_lanes::fits(table) && ellipses_fit(table);
}
bool lanes_search(const Table3& table) {
  constexpr std::size_t most = free_lanes::max_walls;
  const bool known = table.wall_count() == table.planes().size() + table.spheres().size();
  return known && table.planes().size() <= most && table.spheres().size() <= most;
}

/// Does the table search the flights by its BVH's walks run together (a mesh's triangles)?
bool walks_together(const Table&) { return false; }
bool walks_together(const Table3& table) { return !table.triangles().empty(); }
static_assert(free_lanes::lanes <= Table3::max_together);

}  // namespace

free_lanes::Rays free_lanes::rays_of(const State* const* states, const double* t_end, int n) {
  Rays in;
  for (int i = 0; i < lanes; ++i) {
    const State& s = *states[i < n ? i : 0];
    in.x[i] = s.x.x(), in.y[i] = s.x.y(), in.vx[i] = s.v.x(), in.vy[i] = s.v.y();
    in.t[i] = s.t, in.vv[i] = s.v.squaredNorm(), in.t_end[i] = t_end[i < n ? i : 0];
  }
  return in;
}
free_lanes::Rays3 free_lanes::rays_of(const State3* const* states, const double* t_end, int n) {
  Rays3 in;
  for (int i = 0; i < lanes; ++i) {
    const State3& s = *states[i < n ? i : 0];
    in.x[i] = s.x.x(), in.y[i] = s.x.y(), in.z[i] = s.x.z(), in.vx[i] = s.v.x(), in.vy[i] = s.v.y(), in.vz[i] = s.v.z();
    in.t[i] = s.t, in.vv[i] = s.v.squaredNorm(), in.t_end[i] = t_end[i < n ? i : 0];
  }
  return in;
}

void free_lanes::load(Particles& p, int i, const State& s, const Clock& clock, double v2, const Records& records,
                      std::int64_t record, double* energies) {
  Rays& r = p.rays;
  r.x[i] = s.x.x(), r.y[i] = s.x.y(), r.vx[i] = s.v.x(), r.vy[i] = s.v.y();
  r.t[i] = s.t, r.vv[i] = s.v.squaredNorm(), r.t_end[i] = never;
  p.clock_hi[i] = clock.hi, p.clock_lo[i] = clock.lo, p.v2[i] = v2;
  p.record[i] = record, p.record_at[i] = records.times[record], p.energies[i] = energies, p.bounces[i] = 0;
}
State free_lanes::state_in(const Particles& p, int i) {
  const Rays& r = p.rays;
  State s;
  s.x = Vec2(r.x[i], r.y[i]), s.v = Vec2(r.vx[i], r.vy[i]), s.t = r.t[i];
  return s;
}
Clock free_lanes::clock_in(const Particles& p, int i) {
  Clock clock;
  clock.hi = p.clock_hi[i], clock.lo = p.clock_lo[i];
  return clock;
}
void free_lanes::park(Particles& p, int i, int j, const Records& records) {
  load(p, i, state_in(p, j), clock_in(p, j), p.v2[j], records, records.count, nullptr);
}

namespace {

/// The hit's point and normal, as each table's `collision` makes them.
std::pair<Vec2, Vec2> contact_of(const Table& table, const FlightHit<FreeFlight>& hit) {
  return table.contact(hit.wall, hit.state.x, hit.state.v);
}
std::pair<Vec3, Vec3> contact_of(const Table3& table, const FlightHit<FreeFlight3>& hit) {
  return table.contact(hit.wall, hit.state.x);
}

}  // namespace

template <int Dim>
BasicFreeLockstepTable<Dim>::BasicFreeLockstepTable(const TableT& table, const Flight& flight, Kernel kernel,
                                                    Propagator propagator)
    : table_(&table), flight_(&flight), kernel_(kernel), propagator_(propagator), walks_together_(walks_together(table)),
      usable_(walks_together_ || (kernel && lanes_search(table))) {
  if (usable_ && !walks_together_) walls_ = free_lanes::walls_of(table);
}

template <int Dim>
void BasicFreeLockstepTable<Dim>::collisions(const typename Flight::State* const* states, const double* t_end, int n,
                                             FlightHit<Flight>* hits) const {
  if constexpr (Dim == 3)
    if (walks_together_) return table_->collisions(*flight_, states, t_end, n, hits);
  const auto in = free_lanes::rays_of(states, t_end, n);
  free_lanes::Hits out;
  kernel_(walls_, in, out);
  for (int i = 0; i < n; ++i) hit_of(out, i, *states[i], t_end[i], hits[i]);
}

template <int Dim>
void BasicFreeLockstepTable<Dim>::hit_of(const free_lanes::Hits& out, int i, const typename Flight::State& s,
                                         double t_end, FlightHit<Flight>& hit) const {
  if (out.handed_back[i]) {
    hit = collision(*table_, *flight_, s, t_end);
    return;
  }
  // As `collision` makes the hit (the kernel made it where `made`).
  hit.t = out.t[i];
  hit.wall = out.kind[i] < 0 ? WallId{} : WallId{int(out.kind[i]), int(out.index[i])};
  hit.midpoint_inside = false;
  if (!hit.found()) return;
  if constexpr (Dim == 2) {
    if (out.made[i]) {
      hit.state = s;
      hit.state.x = Vec2(out.x[i], out.y[i]), hit.state.t = hit.t;
      hit.point = Vec2(out.point_x[i], out.point_y[i]), hit.normal = Vec2(out.normal_x[i], out.normal_y[i]);
      return;
    }
  }
  hit.state = flight_->advance(s, hit.t);
  std::tie(hit.point, hit.normal) = contact_of(*table_, hit);
}

template class BasicFreeLockstepTable<2>;
template class BasicFreeLockstepTable<3>;

}  // namespace billiards::dynamics
