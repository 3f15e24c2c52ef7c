// 3-D tables: walls from a Region3, the triangle BVH, collision search, sampling.
#include "billiards/dynamics/table3.hpp"

#include "billiards/dynamics/certified_scan.hpp"
#include "billiards/dynamics/magnetic_flight.hpp"

#include <boost/container/static_vector.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <optional>

namespace billiards::dynamics {

using namespace geometry3;

// ---------------------------------------------------------------- table

Table3::BasicTable(const Region3& region, std::int64_t simd_target) : region_(region) {
  const auto m = measures_of(region);
  lo_ = m.bbox_lo;
  hi_ = m.bbox_hi;
  const Vec3 margin = straight_reach * (hi_ - lo_);
  straight_lo_ = lo_ - margin;
  straight_hi_ = hi_ + margin;
  const double slack = slack_ulps * std::max(lo_.cwiseAbs().maxCoeff(), hi_.cwiseAbs().maxCoeff());
  slack_ = slack;
  auto& planes = mutable_walls<PlaneWall>();
  auto& triangles = mutable_walls<TriangleWall>();
  auto& spheres = mutable_walls<SphereWall>();
  const auto sphere = [&](const Ball& b, bool focusing) {
    spheres.push_back({b.center, b.radius, b.radius * b.radius, focusing, slack});
  };
  if (const auto* p = std::get_if<ConvexPolyhedron>(&region.outer))
    for (const Plane& pl : p->planes) planes.push_back({pl.normal, pl.offset, slack});
  if (const auto* m = std::get_if<TriangleMesh>(&region.outer))
    for (const auto& t : m->triangles)
      triangles.emplace_back(m->vertices[t[0]], m->vertices[t[1]], m->vertices[t[2]], slack);
  if (const auto* b = std::get_if<Ball>(&region.outer)) sphere(*b, true);
  for (const Ball& b : region.holes) sphere(b, false);
  std::vector<Bvh::Box> boxes;
  std::vector<Bvh::Facing> facings;
  boxes.reserve(triangles.size());
  facings.reserve(triangles.size());
  // From a start within straight_reach of the table's box, every vertex is within reach.
  const double reach = (1 + 2 * straight_reach) * (hi_ - lo_).maxCoeff() + slack;
  for (const TriangleWall& w : triangles) {
    boxes.push_back({w.p[0].cwiseMin(w.p[1]).cwiseMin(w.p[2]), w.p[0].cwiseMax(w.p[1]).cwiseMax(w.p[2])});
    facings.push_back({w.normal, w.facing_away_margin(reach)});
  }
  bvh_ = Bvh(boxes, facings, 4 * slack, bvh_lanes::kernel_of(simd_target));
  // Store the triangles in the BVH's leaf order: a leaf's triangles are then contiguous.
  Walls<TriangleWall> sorted;
  sorted.reserve(triangles.size());
  for (int i : bvh_.order()) sorted.push_back(triangles[i]);
  triangles = std::move(sorted);
}

namespace {

/// The earliest exit time `exit(wall, best.t)` of the walls of a kind other than the triangles
/// (ask_triangles), kept in `best` where it is earlier.
template <class W, class Exit>
void ask_walls(const Walls<W>& walls, int kind, Hit3& best, Exit exit) {
  for (int i = 0; i < int(walls.size()); ++i) {
    const double t = exit(walls[i], best.t);
    if (t < best.t) best.t = t, best.wall = {kind, i};
  }
}

/// The earliest exit time `exit(triangle, best.t)` of the triangles [first, first + count) of a
/// BVH leaf, kept in `best` where it is earlier; of two at the same time, the one first in the
/// mesh's order (`order`, the BVH's leaf order to the mesh's), so that the hit depends neither
/// on the order in which a walk asks the leaves nor on the tree.
template <class Exit>
void ask_triangles(const Walls<TriangleWall>& triangles, const std::vector<int>& order, int first, int count,
                   Hit3& best, Exit exit) {
  for (int i = first; i < first + count; ++i) {
    const double t = exit(triangles[i], best.t);
    if (t < best.t || (t == best.t && best.wall.kind == wall_kind3::triangle && order[i] < order[best.wall.index]))
      best.t = t, best.wall = {wall_kind3::triangle, i};
  }
}

/// The bound of a walk's τ (from t0) that a leaf holding a triangle crossed at best.t, or
/// before, is never culled by: a crossing at τ is at fl(t0 + τ) ≤ best.t only if t0 + τ is
/// below the next double after best.t, which best.t + |best.t| 2⁻⁵² (rounded) is not below.
double tau_bound(double best_t, double t0) {
  return best_t + (std::abs(best_t) * 0x1p-52 + std::numeric_limits<double>::denorm_min()) - t0;
}

/// Asks the walls of every kind but the triangles one by one: those before the triangles in
/// WallKinds3 (the planes) or those after them (the spheres), as `collision` asks them
/// around the triangles' walk.
template <class Exit>
void ask_walls_beside_triangles(const Table3& table, bool before, Hit3& best, Exit exit) {
  table.for_each_kind([&]<class W>(const Walls<W>& walls, int kind) {
    if constexpr (!std::is_same_v<W, TriangleWall>)
      if ((kind < wall_kind3::triangle) == before) ask_walls(walls, kind, best, exit);
  });
}

/// Starts fetching what an exit test reads of a leaf's triangles [first, first + count): the
/// first two cache lines of each (TriangleWall).
void fetch_leaf(const Walls<TriangleWall>& triangles, int first, int count) {
  for (int i = first; i < first + count; ++i) {
    const char* t = reinterpret_cast<const char*>(&triangles[i]);
    __builtin_prefetch(t), __builtin_prefetch(t + 64);
  }
}

/// How long until a helix within tube.pad of its axis (origin + dir τ, dir ≠ 0) is certainly
/// outside the box [lo, hi]: its axis beyond a face by more than the pad (with a margin for
/// the quotient's rounding).
double time_to_leave(const Tube3& tube, const Vec3& lo, const Vec3& hi) {
  double tau = never;
  for (int k = 0; k < 3; ++k) {
    const double d = tube.dir[k], beyond = d > 0 ? hi[k] + tube.pad - tube.origin[k] : lo[k] - tube.pad - tube.origin[k];
    if (d != 0) tau = std::min(tau, std::max(0.0, beyond / d));
  }
  return tau * (1 + 1e-9);
}

}  // namespace

Bvh::Heading Table3::straight_from(const Vec3& x) const {
  const bool near = (x.array() >= straight_lo_.array()).all() && (x.array() <= straight_hi_.array()).all();
  return near ? Bvh::Heading::straight : Bvh::Heading::any;
}

/// A walk of the BVH, on `stack`, that keeps in `best` the earliest exit time `exit(triangle)`
/// found (after the time t0), not yet set out (Bvh::Walk::set_out).
template <class Exit>
auto Table3::triangle_walk(Hit3& best, const double& t0, Exit exit, Bvh::Pending* stack) const {
  const auto& walls = triangles();
  return Bvh::Walk(
      bvh_,
      [&walls, &order = bvh_.order(), &best, &t0, exit](int first, int count) {
        ask_triangles(walls, order, first, count, best, exit);
        return tau_bound(best.t, t0);
      },
      [&walls](int first, int count) { fetch_leaf(walls, first, count); }, stack);
}

/// The walk along the ray `origin + τ dir` (τ after `t0`), boxes grown by `pad`.
template <class Exit>
void Table3::search_triangles(const Vec3& origin, const Vec3& dir, double pad, double t0, Hit3& best, Exit exit) const {
  Bvh::Pending stack[Bvh::stack_size];
  auto walk = triangle_walk(best, t0, exit, stack);
  walk.set_out(origin, dir, pad, tau_bound(best.t, t0));
  walk.run();
}

/// The triangles a helix (Gyration) may cross, an arc at a time in time order: an arc of
/// angle Δ from τa to τb stays within r_c Δ²/8 of its chord traversed linearly in time (the
/// error of linear interpolation, |f''| = r_c Δ², across the field; the drift along it is
/// linear), so the chord's boxes grown by that (and rounding) hold every triangle the arc
/// meets, and the chord's parameter is the time: a hit found ends the walk of the arcs after
/// it.  An arc is an eighth of a turn, or an eighth of the table's diagonal long where that is
/// shorter (a wide helix): the walk visits the triangles near the path, not all those within
/// r_c of the guiding axis, and asks each leaf once, for a crossing before the arcs' end.  After
/// 64 arcs without a hit (a slow drift along the field) the rest goes by the axis' tube.  No
/// triangle is asked beyond the time the helix has certainly left the table's box (its first
/// crossing comes before; without drift, after a turn the orbit repeats itself): asked to
/// t_end = ∞ (`billiard trajectory` without `--time`), a triangle whose plane the helix meets
/// every turn outside its span would be scanned without end.
template <class Helix, class Exit>
void Table3::search_triangles_along_helix(const Helix& helix, double t0, Hit3& best, Exit exit) const {
  constexpr int max_arcs = 64;
  const Tube3 tube = helix.tube();
  const auto [a0, v0] = helix.at(0);
  const double h = std::min(helix.period() / 8, (hi_ - lo_).norm() / (8 * v0.norm())), angle = helix.k * h;
  const double bow = helix.radius * angle * angle / 8 * (1 + 1e-9), rounding = 2 * (tube.pad - helix.radius);
  const double t_out = t0 + (tube.dir == Vec3::Zero() ? 1.01 * helix.period() : time_to_leave(tube, lo_, hi_));
  const double arcs_end = std::min(t0 + max_arcs * h, t_out);
  const auto exit_before_arcs_end = [&](const TriangleWall& w, double t) { return exit(w, std::min(t, arcs_end)); };
  // The leaves already asked (by their first triangle): asked again, a triangle cannot cross
  // before its first crossing found then, the bound best.t having only fallen since.
  constexpr int max_seen = 64;
  int seen[max_seen], seen_count = 0;
  Vec3 a = a0;
  for (int j = 0; j < max_arcs; ++j) {
    const double ta = t0 + j * h;  // the arc [ta, ta + h], as the absolute time
    if (!(ta < best.t) || !(ta < arcs_end)) return;  // (arcs_end < t0 + j h: it is t_out)
    const Vec3 b = helix.at((j + 1) * h).first;
    const double pad = bow + rounding + 16 * scan::eps<double> * (a.cwiseAbs().maxCoeff() + b.cwiseAbs().maxCoeff());
    bvh_.walk(
        a, (b - a) / h, pad, std::min(h, tau_bound(best.t, ta)),
        [&](int first, int count) {
          if (std::find(seen, seen + seen_count, first) == seen + seen_count) {
            if (seen_count < max_seen) seen[seen_count++] = first;
            ask_triangles(triangles(), bvh_.order(), first, count, best, exit_before_arcs_end);
          }
          return std::min(h, tau_bound(best.t, ta));
        },
        [&](int first, int count) { fetch_leaf(triangles(), first, count); });
    a = b;
  }
  if (arcs_end < std::min(best.t, t_out))
    search_triangles(tube.origin, tube.dir, tube.pad, t0, best,
                     [&](const TriangleWall& w, double t) { return exit(w, std::min(t, t_out)); });
}

namespace {

/// Is a 3-D wall of kind W searched in the time order of its windows along the driven flight
/// `Q` (a gap along it, `gap_along`, and no BVH: planes and spheres)?
template <class Q>
struct Windowed {
  template <class W>
  struct along : std::bool_constant<requires(const W& w, const Q& q) { w.gap_along(q); } &&
                                    !std::is_same_v<W, TriangleWall>> {};
};

using DriveQuiver3 = Quiver<PeriodicDriveFlight3, DrivenState3>;
using WindowedWalls3 = NumberedWalls<Table3, Windowed<DriveQuiver3>::template along>;

/// The first hit by a driven flight among the walls searched by windows, in time order (as in
/// 2-D: DrivenScan::first_hit).
void first_hit_in_windows(const WindowedWalls3& walls, const DriveQuiver3& q, double t_end, Hit3& best) {
  auto never_passes = [](double, double) { return false; };  // no spans to cull by
  auto everywhere = [](const Vec3&) { return true; };
  auto visit = [&](int w, auto&& fn) {
    walls.visit(w, [&](const auto& wall) { fn(wall.gap_along(q), never_passes, everywhere); });
  };
  double tau_best = t_end - q.s.t;
  int wall = -1;
  PhaseSample<double> phase;  // (unused: the hit's state is advanced afresh)
  scan::first_hit_in_windows(walls.count(), visit, tau_best, wall, phase);
  if (wall < 0) return;
  best.t = q.s.t + tau_best;
  best.wall = walls.id(wall);
}

}  // namespace

template <class Flight>
FlightHit<Flight> Table3::collision(const Flight& flight, const typename Flight::State& s, double t_end) const {
  FlightHit<Flight> best;
  best.t = t_end;
  if constexpr (is_straight<Flight>) {
    const State3* const states[] = {&s};
    collisions(flight, states, &t_end, 1, &best);  // (a walk alone is a walk together with none)
    return best;
  } else if constexpr (requires { flight.scan_from(s).tube(); }) {
    const auto scan = flight.scan_from(s);
    const auto exit = [&](const auto& w, double t) { return scan.exit_time(w, t); };
    ask_walls_beside_triangles(*this, true, best, exit);
    search_triangles_along_helix(scan, s.t, best, exit);
    ask_walls_beside_triangles(*this, false, best, exit);
  } else if constexpr (!std::is_same_v<Flight, PeriodicDriveFlight3>) {
    const auto exit = [&](const auto& w, double t) { return flight.exit_time(s, w, t); };
    for_each_kind([&]<class W>(const Walls<W>& walls, int kind) {
      if constexpr (std::is_same_v<W, TriangleWall>)
        ask_triangles(walls, bvh_.order(), 0, int(walls.size()), best, exit);
      else ask_walls(walls, kind, best, exit);
    });
  } else {
    const DriveQuiver3 q(flight, s);
    const WindowedWalls3 windowed(*this);
    const bool by_windows = !q.creeping && windowed.count() <= scan::windows_in_time_order_walls;
    if (by_windows) first_hit_in_windows(windowed, q, t_end, best);
    const auto exit = [&](const auto& w, double t) { return flight.exit_time(s, w, t); };
    // Wall by wall: every kind but the triangles (below), or those without windows.
    for_each_kind([&]<class W>(const Walls<W>& walls, int kind) {
      if constexpr (!std::is_same_v<W, TriangleWall>)
        if (!by_windows || !Windowed<DriveQuiver3>::template along<W>::value) ask_walls(walls, kind, best, exit);
    });
    // The particle stays within δ = |F|/(mω²) of its guiding line: boxes grown by δ (and the
    // scan's rounding band) along that line hold every triangle it can cross.
    search_triangles(q.g0, q.u, q.delta + 2 * slack_, s.t, best, exit);
  }
  complete(flight, s, best);
  return best;
}

template <class Flight>
void Table3::complete(const Flight& flight, const typename Flight::State& s, FlightHit<Flight>& hit) const {
  if (!hit.found()) return;
  hit.state = flight.advance(s, hit.t);
  std::tie(hit.point, hit.normal) = contact(hit.wall, hit.state.x);
}

void Table3::collision_stream(const FreeFlight3& flight, int lanes, NextFlights3 next) const {
  assert(lanes <= max_together);
  // A lane's flight: from *s (null before its first), its exit times, the best hit so far.
  struct Lane {
    const State3* s = nullptr;
    double t0;  // s->t, where the lane's walk reads it for every flight (s changes between them)
    std::optional<StraightScan3> scan;
    FlightHit<FreeFlight3> hit;
  };
  Lane lane[max_together];
  const auto exit_of = [](const Lane& l) {
    return [&scan = l.scan](const auto& w, double t) { return scan->exit_time(w, t); };
  };
  Bvh::Pending stacks[max_together][Bvh::stack_size];
  boost::container::static_vector<decltype(triangle_walk(lane[0].hit, lane[0].t0, exit_of(lane[0]), stacks[0])),
                                   max_together>
      walks;
  for (int i = 0; i < lanes; ++i) walks.push_back(triangle_walk(lane[i].hit, lane[i].t0, exit_of(lane[i]), stacks[i]));
  // Lane i's walk has ended: its flight's hit completed and told, the next flight set out.
  Bvh::walk_stream(walks.data(), lanes, [&](int i) {
    Lane& l = lane[i];
    if (l.s) {
      ask_walls_beside_triangles(*this, false, l.hit, exit_of(l));
      complete(flight, *l.s, l.hit);
    }
    const NextFlight<State3> f = next(i, l.s ? &l.hit : nullptr);
    if (!(l.s = f.state)) return false;
    l.t0 = l.s->t;
    l.scan.emplace(*l.s);
    l.hit = {};
    l.hit.t = f.t_end;
    ask_walls_beside_triangles(*this, true, l.hit, exit_of(l));
    walks[i].set_out(l.s->x, l.s->v, 0, tau_bound(l.hit.t, l.t0), straight_from(l.s->x));
    return true;
  });
}

void Table3::collisions(const FreeFlight3& flight, const State3* const* states, const double* t_end, int n,
                        FlightHit<FreeFlight3>* hits) const {
  collision_stream(flight, n, [&](int i, const FlightHit<FreeFlight3>* hit) {
    if (hit) return hits[i] = *hit, NextFlight<State3>{};
    return NextFlight<State3>{states[i], t_end[i]};
  });
}

template FlightHit<FreeFlight3> Table3::collision(const FreeFlight3&, const State3&, double) const;
template FlightHit<PeriodicDriveFlight3> Table3::collision(const PeriodicDriveFlight3&, const DrivenState3&,
                                                           double) const;
template FlightHit<MagneticFlight3> Table3::collision(const MagneticFlight3&, const State3&, double) const;
template FlightHit<MagneticDriveFlight3> Table3::collision(const MagneticDriveFlight3&, const DrivenState3&, double) const;

State3 sample_microcanonical(const Table3& table, double speed, ParticleRng& rng) {
  const Vec3 size = table.hi() - table.lo();
  State3 s;
  do {
    const double uz = rng.uniform(), uy = rng.uniform(), ux = rng.uniform();  // (in this order: ensemble.cpp)
    s.x = table.lo() + Vec3(ux, uy, uz).cwiseProduct(size);
  } while (!contains(table.region(), s.x));
  const double z = 2 * rng.uniform() - 1, phi = 2 * geometry::pi * rng.uniform();
  const double rho = std::sqrt(std::max(0.0, 1 - z * z));
  s.v = speed * Vec3(rho * std::cos(phi), rho * std::sin(phi), z);
  return s;
}

}  // namespace billiards::dynamics
