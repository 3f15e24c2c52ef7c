// 3-D walls and their exit times for straight flights (the 3-D counterpart of
// dynamics/walls.hpp and free_flight.cpp, with the same rules):
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

#include "billiards/geometry3/region3.hpp"

#include <array>
#include <cmath>
#include <limits>

namespace billiards::dynamics3 {

using geometry3::Vec3;

inline constexpr double never = std::numeric_limits<double>::infinity();
/// Tolerance of "on the wall to rounding", relative to the coordinate scale (as in 2-D).
inline constexpr double slack_ulps = 256 * std::numeric_limits<double>::epsilon();

struct State3 {
  Vec3 x = Vec3::Zero();
  Vec3 v = Vec3::Zero();
  double t = 0;
};

/// A face of a convex polyhedron: n·x ≤ offset.  No span test: the region is the
/// intersection of the half-spaces, so the first plane the ray leaves through is the exit.
struct PlaneWall {
  Vec3 normal;
  double offset;
  double slack;
};

/// Ray data shared by all triangles of one query (the shear of Woop et al.).
struct Ray {
  Vec3 origin, dir;
  int kx, ky, kz;
  double sx, sy, sz;
  Ray(const Vec3& x, const Vec3& v);
};

struct TriangleWall {
  std::array<Vec3, 3> p;  // counter-clockwise seen from outside
  Vec3 normal;            // outward unit normal
  std::array<Vec3, 3> edge_normal;  // in-plane unit normals pointing out of the span
  double slack;
  double span_slack;  // `slack` in barycentric units

  TriangleWall(const Vec3& a, const Vec3& b, const Vec3& c, double slack);
  /// Is x (on the plane, to rounding) within `slack` of the closed triangle?
  bool within_span(const Vec3& x) const {
    for (int k = 0; k < 3; ++k)
      if (edge_normal[k].dot(x - p[k]) > slack) return false;
    return true;
  }
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
};

double exit_time(const State3& s, const PlaneWall& w, double t_end);
double exit_time(const State3& s, const Ray& ray, const TriangleWall& w, double t_end);
double exit_time(const State3& s, const SphereWall& w, double t_end);

/// Exact sign of r²|v|² − |(x − c) × v|² (the ray meets the sphere iff > 0), filtered.
int sphere_discriminant_sign_filtered(const Vec3& x, const Vec3& c, const Vec3& v, double r);

}  // namespace billiards::dynamics3
