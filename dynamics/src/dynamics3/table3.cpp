// 3-D tables: walls from a Region3, the triangle BVH, collision search, reflection, sampling.
#include "billiards/dynamics3/table3.hpp"

#include "billiards/dynamics/certified_scan.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace billiards::dynamics3 {

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

Table3::Table3(const Region3& region) : region_(region) {
  const auto m = measures_of(region);
  lo_ = m.bbox_lo;
  hi_ = m.bbox_hi;
  const double slack = slack_ulps * std::max(lo_.cwiseAbs().maxCoeff(), hi_.cwiseAbs().maxCoeff());
  slack_ = slack;
  const auto sphere = [&](const Ball& b, bool focusing) {
    spheres_.push_back({b.center, b.radius, b.radius * b.radius, focusing, slack});
  };
  if (const auto* p = std::get_if<ConvexPolyhedron>(&region.outer))
    for (const Plane& pl : p->planes) planes_.push_back({pl.normal, pl.offset, slack});
  if (const auto* m = std::get_if<TriangleMesh>(&region.outer))
    for (const auto& t : m->triangles)
      triangles_.emplace_back(m->vertices[t[0]], m->vertices[t[1]], m->vertices[t[2]], slack);
  if (const auto* b = std::get_if<Ball>(&region.outer)) sphere(*b, true);
  for (const Ball& b : region.holes) sphere(b, false);
  bvh_ = Bvh(triangles_, 4 * slack);
  // Store the triangles in the BVH's leaf order: a leaf's triangles are then contiguous.
  std::vector<TriangleWall> sorted;
  sorted.reserve(triangles_.size());
  for (int i : bvh_.order()) sorted.push_back(triangles_[i]);
  triangles_ = std::move(sorted);
}

/// Walks the BVH nearest box first along the ray `origin + τ dir` (τ after `t0`), boxes grown
/// by `pad`, and keeps in `best` the earliest exit time `exit(triangle)` found.
template <class Exit>
void Table3::search_triangles(const Vec3& origin, const Vec3& dir, double pad, double t0, Hit3& best,
                              Exit exit) const {
  if (triangles_.empty()) return;
  const SlabRay slab(origin, dir, pad);
  const auto& nodes = bvh_.nodes();
  const int base = int(planes_.size());
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
        const double t = exit(triangles_[i], best.t);
        if (t < best.t) best.t = t, best.wall = base + i;
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

Hit3 Table3::collision(const State3& s, double t_end) const {
  Hit3 best;
  best.t = t_end;
  for (int w = 0; w < int(planes_.size()); ++w) {
    const double t = exit_time(s, planes_[w], best.t);
    if (t < best.t) best.t = t, best.wall = w;
  }
  const Ray ray(s.x, s.v);
  search_triangles(s.x, s.v, 0, s.t, best,
                   [&](const TriangleWall& w, double t_end) { return exit_time(s, ray, w, t_end); });
  const int base = int(planes_.size() + triangles_.size());
  for (int w = 0; w < int(spheres_.size()); ++w) {
    const double t = exit_time(s, spheres_[w], best.t);
    if (t < best.t) best.t = t, best.wall = base + w;
  }
  if (!best.found()) return best;
  best.point = s.x + s.v * (best.t - s.t);
  best.normal = normal_at(best.wall, best.point);
  return best;
}

DrivenHit3 Table3::collision(const PeriodicDriveFlight3& flight, const DrivenState3& s, double t_end) const {
  using Quiver3 = dynamics::scan::Quiver<PeriodicDriveFlight3, DrivenState3>;
  Hit3 best;
  best.t = t_end;
  const Quiver3 q(flight, s);
  const int np = int(planes_.size()), nt = int(triangles_.size()), ns = int(spheres_.size());
  if (q.creeping || np + ns > dynamics::scan::windows_in_time_order_walls) {  // (as in 2-D: DrivenScan::first_hit)
    for (int w = 0; w < np; ++w) {
      const double t = flight.exit_time(s, planes_[w], best.t);
      if (t < best.t) best.t = t, best.wall = w;
    }
    for (int w = 0; w < ns; ++w) {
      const double t = flight.exit_time(s, spheres_[w], best.t);
      if (t < best.t) best.t = t, best.wall = np + nt + w;
    }
  } else {
    // Planes and spheres: their windows in time order, as in 2-D (no spans to cull by).
    auto never_passes = [](double, double) { return false; };
    auto everywhere = [](const Vec3&) { return true; };
    auto visit = [&](int w, auto&& fn) {
      if (w < np) {
        const PlaneWall& p = planes_[w];
        fn(dynamics::scan::PlaneGap<Quiver3, Vec3>(q, p.normal, Vec3(p.normal * p.offset), p.slack), never_passes,
           everywhere);
      } else {
        const SphereWall& b = spheres_[w - np];
        fn(dynamics::scan::SphereGap<Quiver3, Vec3>(q, b.center, b.radius, b.focusing, b.slack), never_passes,
           everywhere);
      }
    };
    double tau_best = t_end - s.t;
    int wall = -1;
    dynamics::scan::PhaseSample<double> phase;  // (unused: the 3-D advance takes no sample)
    dynamics::scan::first_hit_in_windows(np + ns, visit, tau_best, wall, phase);
    if (wall >= 0) best.t = s.t + tau_best, best.wall = wall < np ? wall : wall + nt;
  }
  if (nt > 0) {
    // The particle stays within δ = |F|/(mω²) of its guiding line: boxes grown by δ (and the
    // scan's rounding band) along that line hold every triangle it can cross.
    search_triangles(q.g0, q.u, q.delta + 2 * slack_, s.t, best,
                     [&](const TriangleWall& w, double t) { return flight.exit_time(s, w, t); });
  }
  if (!best.found()) return {best, {}};
  DrivenHit3 hit{best, flight.advance(s, best.t)};
  hit.point = hit.state.x;
  hit.normal = normal_at(hit.wall, hit.point);
  return hit;
}

Vec3 Table3::normal_at(int wall, const Vec3& x) const {
  const int np = int(planes_.size()), nt = int(triangles_.size());
  if (wall < np) return planes_[wall].normal;
  if (wall < np + nt) return triangles_[wall - np].normal;
  return spheres_[wall - np - nt].normal_at(x);
}

void bounce(State3& s, const Hit3& hit, double v2) {
  bounce(FreeFlight3{}, s, hit);
  s.v *= std::sqrt(v2 / s.v.squaredNorm());
}

void bounce(const PeriodicDriveFlight3&, DrivenState3& s, const DrivenHit3& hit) {
  s = hit.state;
  s.x = hit.point;
  s.v -= 2 * s.v.dot(hit.normal) * hit.normal;
}

State3 sample_microcanonical(const Table3& table, double speed, dynamics::ParticleRng& rng) {
  const Vec3 size = table.hi() - table.lo();
  State3 s;
  do {
    s.x = table.lo() + Vec3(rng.uniform(), rng.uniform(), rng.uniform()).cwiseProduct(size);
  } while (!contains(table.region(), s.x));
  const double z = 2 * rng.uniform() - 1, phi = 2 * geometry::pi * rng.uniform();
  const double rho = std::sqrt(std::max(0.0, 1 - z * z));
  s.v = speed * Vec3(rho * std::cos(phi), rho * std::sin(phi), z);
  return s;
}

}  // namespace billiards::dynamics3
