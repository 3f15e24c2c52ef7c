// 3-D tables: walls from a Region3, the triangle BVH, collision search, sampling.
#include "billiards/dynamics/table3.hpp"

#include "billiards/dynamics/certified_scan.hpp"
#include "billiards/dynamics/magnetic_flight.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace billiards::dynamics {

using namespace geometry3;

// ---------------------------------------------------------------- BVH

namespace {
constexpr int leaf_size = 4;
}

Bvh::Bvh(const std::vector<TriangleWall>& tris, double pad) {
  order_.resize(tris.size());
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(2 * tris.size() / leaf_size + 1);
  if (!tris.empty()) build(tris, 0, int(tris.size()), pad);
}

int Bvh::build(const std::vector<TriangleWall>& tris, int first, int count, double pad) {
  const int index = int(nodes_.size());
  nodes_.emplace_back();
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo, clo = lo, chi = hi;  // boxes of triangles, centroids
  for (int i = first; i < first + count; ++i) {
    const auto& p = tris[order_[i]].p;
    const Vec3 centroid = (p[0] + p[1] + p[2]) / 3;
    for (const Vec3& q : p) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    clo = clo.cwiseMin(centroid), chi = chi.cwiseMax(centroid);
  }
  nodes_[index].lo = lo - Vec3::Constant(pad);
  nodes_[index].hi = hi + Vec3::Constant(pad);
  if (count <= leaf_size) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  int axis;
  (chi - clo).maxCoeff(&axis);
  const auto key = [&](int t) { return tris[t].p[0][axis] + tris[t].p[1][axis] + tris[t].p[2][axis]; };
  const int half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](int a, int b) { return key(a) < key(b); });
  build(tris, first, half, pad);
  const int right = build(tris, first + half, count - half, pad);
  nodes_[index].right = right;
  return index;
}

namespace {

/// Parameter interval in which the ray x + τ v is inside the box (grown by `pad`), intersected
/// with [0, t_max].  A zero velocity component is replaced by a tiny one of the same role: the
/// slab then spans everything (particle between the planes) or nothing, with no 0·∞.
struct SlabRay {
  Vec3 x, inv;
  double pad;
  SlabRay(const Vec3& origin, const Vec3& v, double pad_) : x(origin), pad(pad_) {
    for (int k = 0; k < 3; ++k) inv[k] = 1 / (v[k] != 0 ? v[k] : 1e-300);
  }
  bool hits(const Bvh::Node& n, double t_max, double& t_in) const {
    double lo = 0, hi = t_max;
    for (int k = 0; k < 3; ++k) {
      double a = (n.lo[k] - pad - x[k]) * inv[k], b = (n.hi[k] + pad - x[k]) * inv[k];
      if (a > b) std::swap(a, b);
      lo = std::max(lo, a);
      hi = std::min(hi, b);
    }
    t_in = lo;
    return lo <= hi;
  }
};

}  // namespace

// ---------------------------------------------------------------- table

Table3::BasicTable(const Region3& region) : region_(region) {
  const auto m = measures_of(region);
  lo_ = m.bbox_lo;
  hi_ = m.bbox_hi;
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
  bvh_ = Bvh(triangles, 4 * slack);
  // Store the triangles in the BVH's leaf order: a leaf's triangles are then contiguous.
  std::vector<TriangleWall> sorted;
  sorted.reserve(triangles.size());
  for (int i : bvh_.order()) sorted.push_back(triangles[i]);
  triangles = std::move(sorted);
}

/// Walks the BVH nearest box first along the ray `origin + τ dir` (τ after `t0`), boxes grown
/// by `pad`, and keeps in `best` the earliest exit time `exit(triangle)` found.
template <class Exit>
void Table3::search_triangles(const Vec3& origin, const Vec3& dir, double pad, double t0, Hit3& best,
                              Exit exit) const {
  const auto& triangles = this->triangles();
  if (triangles.empty()) return;
  const SlabRay slab(origin, dir, pad);
  const auto& nodes = bvh_.nodes();
  struct Entry {
    int node;
    double t_in;  // where the ray enters its box
  };
  Entry stack[64];
  int top = 0;
  double t_in;
  if (slab.hits(nodes[0], best.t - t0, t_in)) stack[top++] = {0, t_in};
  while (top > 0) {
    const Entry e = stack[--top];
    if (t0 + e.t_in > best.t) continue;  // a nearer hit was found since it was pushed
    const Bvh::Node& n = nodes[e.node];
    if (n.count > 0) {
      for (int i = n.first; i < n.first + n.count; ++i) {
        const double t = exit(triangles[i], best.t);
        if (t < best.t) best.t = t, best.wall = {wall_kind3::triangle, i};
      }
      continue;
    }
    // Push the farther child first, so that the nearer one is searched first and `best`
    // shrinks early.
    const int left = e.node + 1;
    double t_left, t_right;
    const bool hit_left = slab.hits(nodes[left], best.t - t0, t_left);
    const bool hit_right = slab.hits(nodes[n.right], best.t - t0, t_right);
    if (hit_left && hit_right && t_left <= t_right) {
      stack[top++] = {n.right, t_right};
      stack[top++] = {left, t_left};
    } else if (hit_left && hit_right) {
      stack[top++] = {left, t_left};
      stack[top++] = {n.right, t_right};
    } else if (hit_left) {
      stack[top++] = {left, t_left};
    } else if (hit_right) {
      stack[top++] = {n.right, t_right};
    }
  }
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
  if constexpr (is_straight<Flight> || requires { flight.scan_from(s).tube(); }) {
    const auto scan = flight.scan_from(s);
    const Tube3 tube = [&] {
      if constexpr (is_straight<Flight>) return Tube3{s.x, s.v, 0};
      else return scan.tube();
    }();
    for_each_kind([&]<class W>(const std::vector<W>& walls, int kind) {
      if constexpr (std::is_same_v<W, TriangleWall>) {
        search_triangles(tube.origin, tube.dir, tube.pad, s.t, best,
                         [&](const TriangleWall& w, double t) { return scan.exit_time(w, t); });
      } else {
        for (int i = 0, n = int(walls.size()); i < n; ++i) {
          const double t = scan.exit_time(walls[i], best.t);
          if (t < best.t) best.t = t, best.wall = {kind, i};
        }
      }
    });
  } else if constexpr (!std::is_same_v<Flight, PeriodicDriveFlight3>) {
    for_each_kind([&](const auto& walls, int kind) {
      for (int i = 0, n = int(walls.size()); i < n; ++i) {
        const double t = flight.exit_time(s, walls[i], best.t);
        if (t < best.t) best.t = t, best.wall = {kind, i};
      }
    });
  } else {
    const DriveQuiver3 q(flight, s);
    const WindowedWalls3 windowed(*this);
    const bool by_windows = !q.creeping && windowed.count() <= scan::windows_in_time_order_walls;
    if (by_windows) first_hit_in_windows(windowed, q, t_end, best);
    // Wall by wall: every kind but the triangles (below), or those without windows.
    for_each_kind([&]<class W>(const std::vector<W>& walls, int kind) {
      if constexpr (!std::is_same_v<W, TriangleWall>) {
        if (by_windows && Windowed<DriveQuiver3>::template along<W>::value) return;
        for (int i = 0, n = int(walls.size()); i < n; ++i) {
          const double t = flight.exit_time(s, walls[i], best.t);
          if (t < best.t) best.t = t, best.wall = {kind, i};
        }
      }
    });
    // The particle stays within δ = |F|/(mω²) of its guiding line: boxes grown by δ (and the
    // scan's rounding band) along that line hold every triangle it can cross.
    search_triangles(q.g0, q.u, q.delta + 2 * slack_, s.t, best,
                     [&](const TriangleWall& w, double t) { return flight.exit_time(s, w, t); });
  }
  if (!best.found()) return best;
  best.state = flight.advance(s, best.t);
  std::tie(best.point, best.normal) = contact(best.wall, best.state.x);
  return best;
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
