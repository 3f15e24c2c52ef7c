// The 3-D billiard table: a Region3's walls by kind (WallKinds3: planes, mesh triangles,
// spheres; WallSet's `for_each_kind` and `visit`), a bounding-volume hierarchy over the
// triangles of a mesh (the acceleration structure that the uniform grid is in 2-D), and the
// independent point-in-region test of geometry3.
#pragma once

#include "billiards/dynamics/bvh3.hpp"
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/function_ref.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/dynamics/simd.hpp"
#include "billiards/dynamics/table.hpp"
#include "billiards/dynamics/wall_set.hpp"
#include "billiards/dynamics/walls3.hpp"
#include "billiards/geometry3/region3.hpp"

#include <tuple>
#include <utility>
#include <vector>

namespace billiards::dynamics {

/// The wall kinds of a 3-D table, in the order of WallId::kind.
using WallKinds3 = std::tuple<PlaneWall, TriangleWall, SphereWall>;

/// WallId::kind of each 3-D wall type: its position in WallKinds3.
namespace wall_kind3 {
inline constexpr int plane = 0, triangle = 1, sphere = 2;
}

/// A line x = origin + τ dir that a flight's path stays within `pad` of (τ from the flight's
/// start): a helix's guiding axis (pad r_c).  The BVH walks it when a helix has not met a wall
/// within the 64 arcs whose chords it walks first (table3.cpp).
struct Tube3 {
  Vec3 origin, dir;
  double pad;
};

template <>
class BasicTable<double, 3> : public WallSet<WallKinds3> {
 public:
  using V = Vec3;
  static_assert(std::is_same_v<Kind<wall_kind3::plane>, PlaneWall> &&
                std::is_same_v<Kind<wall_kind3::triangle>, TriangleWall> &&
                std::is_same_v<Kind<wall_kind3::sphere>, SphereWall>);

  /// Keeps a reference to `region` (for point location), which must outlive the table: a
  /// temporary region does not compile.  The BVH's slab test runs in the lanes of
  /// `simd_target` (bvh_lanes.hpp; simd::scalar: four children at a time, without a target),
  /// the same children entered on any.
  explicit BasicTable(const geometry3::Region3& region, std::int64_t simd_target = simd::chosen_target());
  BasicTable(geometry3::Region3&&, std::int64_t = simd::scalar) = delete;

  /// The first wall the flight (FreeFlight3, PeriodicDriveFlight3, MagneticFlight3 or
  /// MagneticDriveFlight3) from `s` leaves the region through, before `t_end`, with the
  /// flight's state there.  The walls other than triangles are asked one by one (a driven
  /// flight's in the time order of their windows); the triangles through the BVH, walked along
  /// the flight's guiding line with boxes grown by its oscillation's amplitude |F|/(mω²), or
  /// along a helix's chords an eighth of a turn at a time, except under a magnetic field with a
  /// force, whose path no tube holds: every triangle is asked.  For a particle inside the region and
  /// t_end = never, found() == false means an escape.
  template <class Flight>
  FlightHit<Flight> collision(const Flight& flight, const typename Flight::State& s, double t_end = never) const;
  /// The most flights `collision_stream` searches at once.
  static constexpr int max_together = 16;
  /// What a lane of `collision_stream` is told of its flight's hit (null at its start) and
  /// asked for its next flight.
  using NextFlights3 = FunctionRef<NextFlight<State3>(int lane, const FlightHit<FreeFlight3>* hit)>;
  /// The collisions of a stream of straight flights in `lanes` ≤ max_together lanes, whose BVH
  /// walks run together (Bvh::walk_stream, each flight its own walk), so that the triangles'
  /// fetches from memory overlap: lane i starts with the flight next(i, nullptr); as soon as a
  /// flight's hit is found, next(i, &hit) gives the lane its next flight, and a lane given
  /// none closes.  Each hit is collision(flight, *state, t_end)'s, bit for bit.
  void collision_stream(const FreeFlight3& flight, int lanes, NextFlights3 next) const;
  /// hits[i] = collision(flight, *states[i], t_end[i]) for i < n ≤ max_together: a stream of
  /// one flight a lane (a straight flight's `collision` is this with n = 1).
  void collisions(const FreeFlight3& flight, const State3* const* states, const double* t_end, int n,
                  FlightHit<FreeFlight3>* hits) const;
  /// Is x in the closed region (the independent point-in-region test of geometry3)?
  bool contains(const Vec3& x) const { return geometry3::contains(region_, x); }
  const Walls<PlaneWall>& planes() const { return walls<PlaneWall>(); }
  /// (In the BVH's leaf order; the mesh's order is piece_of's.)
  const Walls<TriangleWall>& triangles() const { return walls<TriangleWall>(); }
  const Walls<SphereWall>& spheres() const { return walls<SphereWall>(); }
  std::pair<Vec3, Vec3> contact(const WallId& wall, const Vec3& p) const {
    return visit(wall, [&](const auto& w) { return w.contact(p); });
  }
  Vec3 normal_at(const WallId& wall, const Vec3& p) const {
    return visit(wall, [&](const auto& w) { return w.normal_at(p); });
  }
  /// Signed curvature of the wall at p, seen from the region (> 0 focusing).
  double curvature_at(const WallId& wall, const Vec3& p) const {
    return visit(wall, [&](const auto& w) { return w.curvature_at(p); });
  }
  /// The wall's position among all walls, kind by kind: planes, triangles (in the mesh's
  /// order), spheres.
  int piece_of(const WallId& wall) const {
    int before = 0;
    for_each_kind([&](const auto& walls, int kind) { before += kind < wall.kind ? int(walls.size()) : 0; });
    return before + (wall.kind == wall_kind3::triangle ? bvh_.order()[wall.index] : wall.index);
  }
  const geometry3::Region3& region() const { return region_; }
  const Vec3& lo() const { return lo_; }  // bounding box
  const Vec3& hi() const { return hi_; }

 private:
  /// How far beyond the table's box, in units of its size, a straight flight's walk passes
  /// over the triangles it moves away from (Bvh::Heading; their margins hold there).
  static constexpr double straight_reach = 0.01;
  /// Bvh::Heading::straight for a straight flight from x, where x is that near the box.
  Bvh::Heading straight_from(const Vec3& x) const;
  template <class Exit>
  auto triangle_walk(Hit3& best, const double& t0, Exit exit, Bvh::Pending* stack) const;
  template <class Exit>
  void search_triangles(const Vec3& origin, const Vec3& dir, double pad, double t0, Hit3& best, Exit exit) const;
  template <class Helix, class Exit>
  void search_triangles_along_helix(const Helix& helix, double t0, Hit3& best, Exit exit) const;
  /// The hit's state and contact, where a hit was found.
  template <class Flight>
  void complete(const Flight& flight, const typename Flight::State& s, FlightHit<Flight>& hit) const;

  const geometry3::Region3& region_;
  Bvh bvh_;
  Vec3 lo_, hi_;
  Vec3 straight_lo_, straight_hi_;  // the box grown by straight_reach of its size
  double slack_ = 0;
};
using Table3 = BasicTable<double, 3>;

/// `collision` (collision.hpp) for 3-D tables.
template <class Flight>
  requires(Flight::State::dimension == 3)
FlightHit<Flight> collision(const Table3& table, const Flight& flight, const typename Flight::State& s,
                            double t_end = never) {
  return table.collision(flight, s, t_end);
}

/// Position uniform in the region (rejection from the bounding box), velocity isotropic.
State3 sample_microcanonical(const Table3& table, double speed, ParticleRng& rng);

}  // namespace billiards::dynamics
