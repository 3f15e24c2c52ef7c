// 3-D wall primitives, beside the 2-D ones of walls.hpp and with the same queries: gap(x),
// the signed gap (> 0 beyond the wall, on the side away from the region: the signed distance
// to the plane, the triangle's plane or the sphere); normal_at, the region's outward unit
// normal; within_span; contact (the hit point, as computed, and the normal there); box, a
// bounding box (lo, hi) of the wall and its slack; curvature_at (signed, > 0 focusing: 1/r
// in every direction for a sphere seen from inside, −1/r from outside, 0 for flat walls); and
// `slack`, its rounding tolerance in distance units; `gap_sample(x, v, A)`, what the certified
// scan needs to search any flight against it (walls.hpp); and, for the scan of a driven
// flight, `gap_along(q)`, the gap of its plane or sphere seen along the flight q (walls.hpp).
//
// Straight flights' exit times through them (`straight_exit_time`, walls3.cpp) follow the
// rules of the 2-D ones:
//
// - exit_time gives the first time in [s.t, t_end] at which the flight crosses the wall
//   OUTWARD within its span, or `never`;
// - a particle beyond a wall by rounding only (≤ `slack`) and moving out collides at once;
//   farther beyond, it is elsewhere in a non-convex region and the wall is ignored; moving in,
//   it never collides with that wall (DynamO's "stable" rule);
// - a crossing AHEAD of the particle is found by a watertight ray–triangle test (Woop, Benthin
//   & Wald 2013): triangles sharing an edge evaluate its edge function from the same doubles,
//   so a ray through an edge or a vertex hits at least one of them even without slack; the
//   test is then widened by `slack`, because the neighbour of a triangle may be tested at
//   dt = 0 instead (below) and must not leave a gap at the edge;
// - a crossing AT the particle (dt = 0) is accepted when the particle is within `slack` of the
//   triangle's closed span, so a particle reflected at a concave edge or corner meets the
//   neighbouring face at once when it still moves out through it;
// - whether a ray meets a ball at grazing incidence is an exact predicate (filtered double,
//   then GMP).
#pragma once

#include "billiards/dynamics/state.hpp"
#include "billiards/dynamics/walls.hpp"
#include "billiards/geometry3/region3.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace billiards::dynamics {

using geometry3::Vec3;

/// Tolerance of "on the wall to rounding", relative to the coordinate scale (as in 2-D).
inline constexpr double slack_ulps = 256 * std::numeric_limits<double>::epsilon();

/// A face of a convex polyhedron: n·x ≤ offset.  No span test: the region is the
/// intersection of the half-spaces, so the first plane the ray leaves through is the exit.
struct PlaneWall {
  Vec3 normal;
  double offset;
  double slack;
  double gap(const Vec3& x) const { return normal.dot(x) - offset; }
  /// As for 2-D walls (walls.hpp): the gap, its rate, and |f''| ≤ A.
  scan::Sample<double, Vec3> gap_sample(const Vec3& x, const Vec3& v, double A) const {
    return {gap(x), normal.dot(v), A, never, x};
  }
  template <class Q>
  scan::PlaneGap<Q, Vec3> gap_along(const Q& q) const { return {q, normal, Vec3(normal * offset), slack}; }
  Vec3 normal_at(const Vec3&) const { return normal; }
  bool within_span(const Vec3&) const { return true; }
  std::pair<Vec3, Vec3> contact(const Vec3& x) const { return {x, normal}; }
  std::pair<Vec3, Vec3> box() const { return {Vec3::Constant(-never), Vec3::Constant(never)}; }  // all space
  double curvature_at(const Vec3&) const { return 0; }
};

/// Ray data shared by all triangles of one query (the shear of Woop et al.).
struct Ray {
  Vec3 origin, dir;
  int kx, ky, kz;
  double sx, sy, sz;
  Ray(const Vec3& x, const Vec3& v);
};

/// A straight flight's exit test reads p, normal, slack and span_slack: they come first, in
/// the first two cache lines of a wall aligned to them (a BVH leaf's triangles are fetched from
/// memory a line at a time).
struct alignas(64) TriangleWall {
  std::array<Vec3, 3> p;  // counter-clockwise seen from outside
  Vec3 normal;            // outward unit normal
  double slack;
  double span_slack;  // `slack` in barycentric units
  std::array<Vec3, 3> edge_normal;  // in-plane unit normals pointing out of the span

  TriangleWall(const Vec3& a, const Vec3& b, const Vec3& c, double slack);
  /// A margin δ such that a straight flight from within `reach` of the vertices in each
  /// coordinate, whose unit heading h has normal·h < −δ, never leaves through the triangle
  /// (straight_exit_time is `never`): it moves away from it, and the exit test's rounding
  /// cannot turn that around (walls3.cpp).  At least 1 for a triangle too thin to tell.
  double facing_away_margin(double reach) const;
  /// Is x (on the plane, to rounding) within `slack` of the closed triangle?
  bool within_span(const Vec3& x) const {
    for (int k = 0; k < 3; ++k)
      if (edge_normal[k].dot(x - p[k]) > slack) return false;
    return true;
  }
  double gap(const Vec3& x) const { return normal.dot(x - p[0]); }
  scan::Sample<double, Vec3> gap_sample(const Vec3& x, const Vec3& v, double A) const {
    return {gap(x), normal.dot(v), A, never, x};
  }
  /// (The triangle's plane: a lower bound of the distance from the triangle.)
  template <class Q>
  scan::PlaneGap<Q, Vec3> gap_along(const Q& q) const { return {q, normal, p[0], slack}; }
  Vec3 normal_at(const Vec3&) const { return normal; }
  std::pair<Vec3, Vec3> contact(const Vec3& x) const { return {x, normal}; }
  std::pair<Vec3, Vec3> box() const {
    const Vec3 pad = Vec3::Constant(slack);
    return {p[0].cwiseMin(p[1]).cwiseMin(p[2]) - pad, p[0].cwiseMax(p[1]).cwiseMax(p[2]) + pad};
  }
  double curvature_at(const Vec3&) const { return 0; }
};

struct SphereWall {
  Vec3 center;
  double radius, radius2;
  bool focusing;  // the region is inside the sphere (the outer wall)
  double slack;
  Vec3 normal_at(const Vec3& x) const {
    const Vec3 u = (x - center) / radius;
    return focusing ? u : Vec3(-u);
  }
  double gap(const Vec3& x) const {
    const double d = (x - center).norm() - radius;
    return focusing ? d : -d;
  }
  scan::Sample<double, Vec3> gap_sample(const Vec3& x, const Vec3& v, double A) const {
    const Vec3 p = x - center;
    return radial_gap_sample(focusing, radius, p.norm(), p.dot(v), v.norm(), A, x);
  }
  template <class Q>
  scan::SphereGap<Q, Vec3> gap_along(const Q& q) const { return {q, center, radius, focusing, slack}; }
  bool within_span(const Vec3&) const { return true; }
  std::pair<Vec3, Vec3> contact(const Vec3& x) const { return {x, normal_at(x)}; }
  std::pair<Vec3, Vec3> box() const {
    const Vec3 r = Vec3::Constant(radius + slack);
    return {center - r, center + r};
  }
  double curvature_at(const Vec3&) const { return (focusing ? 1 : -1) / radius; }
};

/// The exit times of straight flights (see the rules above; FreeFlight3 calls them).
double straight_exit_time(const State3& s, const PlaneWall& w, double t_end);
double straight_exit_time(const State3& s, const SphereWall& w, double t_end);
/// Through a triangle, the watertight test (inline: a BVH leaf asks its triangles in a loop,
/// which then reads the ray's numbers once).
inline double straight_exit_time(const State3& s, const Ray& ray, const TriangleWall& w, double t_end) {
  const double beyond = w.normal.dot(s.x - w.p[0]);
  if (beyond > w.slack) return never;  // elsewhere in a non-convex region
  if (beyond >= 0) return w.normal.dot(s.v) > 0 && w.within_span(s.x) ? s.t : never;
  // Strictly on the region's side: the watertight test, for crossings ahead only.  An outward
  // crossing has all edge functions ≤ 0 and det < 0 (counter-clockwise seen from outside).
  // A vertex relative to the origin, its coordinates in the ray's order kx, ky, kz, sheared
  // (each coordinate read from the wall by its index, with nothing stored between).
  const auto sheared = [&](const Vec3& p, double& x, double& y, double& z) {
    z = p[ray.kz] - ray.origin[ray.kz];
    x = (p[ray.kx] - ray.origin[ray.kx]) - ray.sx * z;
    y = (p[ray.ky] - ray.origin[ray.ky]) - ray.sy * z;
  };
  double ax, ay, az, bx, by, bz, cx, cy, cz;
  sheared(w.p[0], ax, ay, az);
  sheared(w.p[1], bx, by, bz);
  sheared(w.p[2], cx, cy, cz);
  const double u = cx * by - cy * bx, v = ax * cy - ay * cx, e = bx * ay - by * ax;
  const double det = u + v + e;
  // Barycentric coordinates u/det, v/det, e/det ≥ −span_slack: the exact watertight test,
  // widened by the slack so that a crossing within rounding of an edge is also caught by the
  // triangle on whose side the particle starts (the neighbour may be tested at dt = 0).
  if (!(det < 0) || std::max({u, v, e}) > -w.span_slack * det) return never;
  const double T = ray.sz * (u * az + v * bz + e * cz);
  // beyond < 0 puts the crossing ahead; a negative T/det is rounding.
  const double t = s.t + std::max(0.0, T / det);
  return t <= t_end ? t : never;
}

/// Exact sign of r²|v|² − |(x − c) × v|² (the ray meets the sphere iff > 0), filtered.
int sphere_discriminant_sign_filtered(const Vec3& x, const Vec3& c, const Vec3& v, double r);

}  // namespace billiards::dynamics
