// A 3-D region prepared for collision queries: plane, triangle and sphere walls, and a
// bounding-volume hierarchy over the triangles of a mesh.
#pragma once

#include "billiards/dynamics/random.hpp"
#include "billiards/dynamics3/driven3.hpp"
#include "billiards/dynamics3/walls3.hpp"
#include "billiards/geometry3/region3.hpp"

#include <vector>

namespace billiards::dynamics3 {

/// Where and when a flight leaves the region through a wall.
struct Hit3 {
  double t = never;
  int wall = -1;  // planes first, then triangles (in BVH order), then spheres
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::Zero();  // outward unit normal at `point`
  bool found() const { return wall >= 0; }
};

/// A driven flight's hit with the flight's state there, before the bounce: `bounce` starts from
/// it instead of advancing the flight a second time (as dynamics::FlightHit in 2-D).
struct DrivenHit3 : Hit3 {
  DrivenState3 state;
};

/// Median-split BVH over triangles; boxes are padded by the walls' slack so that a ray
/// within rounding of a triangle is never culled by its box.
class Bvh {
 public:
  struct Node {
    Vec3 lo, hi;
    int first = 0, count = 0;  // a leaf: triangles [first, first + count) of `order`
    int right = 0;             // an inner node: left child is the next node, right child here
  };
  Bvh() = default;
  Bvh(const std::vector<TriangleWall>& triangles, double pad);
  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<int>& order() const { return order_; }

 private:
  int build(const std::vector<TriangleWall>& tris, int first, int count, double pad);
  std::vector<Node> nodes_;
  std::vector<int> order_;
};

class Table3 {
 public:
  /// Keeps a reference to `region` (for point location), which must outlive the table.
  explicit Table3(const geometry3::Region3& region);

  /// The first wall the straight flight from `s` leaves the region through, before `t_end`.
  /// For a particle inside the region and t_end = never, found() == false means an escape.
  Hit3 collision(const State3& s, double t_end = never) const;
  /// The same for the paper's drive (the BVH walked along the guiding line, boxes grown by the
  /// oscillation's amplitude |F|/(mω²)), with the flight's state at the hit.
  DrivenHit3 collision(const PeriodicDriveFlight3& flight, const DrivenState3& s, double t_end = never) const;
  /// Is x in the closed region (the independent point-in-region test of geometry3)?
  bool contains(const Vec3& x) const { return geometry3::contains(region_, x); }
  /// The walls, in the order of Hit3::wall.
  const std::vector<PlaneWall>& planes() const { return planes_; }
  const std::vector<TriangleWall>& triangles() const { return triangles_; }
  const std::vector<SphereWall>& spheres() const { return spheres_; }
  const geometry3::Region3& region() const { return region_; }
  std::size_t wall_count() const { return planes_.size() + triangles_.size() + spheres_.size(); }
  const Vec3& lo() const { return lo_; }  // bounding box
  const Vec3& hi() const { return hi_; }

 private:
  template <class Exit>
  void search_triangles(const Vec3& origin, const Vec3& dir, double pad, double t0, Hit3& best, Exit exit) const;
  Vec3 normal_at(int wall, const Vec3& x) const;

  const geometry3::Region3& region_;
  std::vector<PlaneWall> planes_;
  std::vector<TriangleWall> triangles_;
  std::vector<SphereWall> spheres_;
  Bvh bvh_;
  Vec3 lo_, hi_;
  double slack_ = 0;
};

/// Specular reflection at the hit, restoring the speed² `v2` of the particle's start (so that
/// rounding cannot accumulate into an energy drift).
void bounce(State3& s, const Hit3& hit, double v2);

/// Moves the driven particle to the hit (the state `collision` kept there) and reflects it
/// (its energy changes in flight).
void bounce(const PeriodicDriveFlight3& flight, DrivenState3& s, const DrivenHit3& hit);

// The verbs of dynamics/collision.hpp for 3-D tables, so that the ensemble code
// (dynamics/ensemble.hpp) runs 3-D flights unchanged.
inline Hit3 collision(const Table3& table, const FreeFlight3&, const State3& s, double t_end = never) {
  return table.collision(s, t_end);
}
inline DrivenHit3 collision(const Table3& table, const PeriodicDriveFlight3& flight, const DrivenState3& s,
                      double t_end = never) {
  return table.collision(flight, s, t_end);
}
/// Moves the free particle to the hit and reflects it (the ensemble restores its speed).
inline void bounce(const FreeFlight3&, State3& s, const Hit3& hit) {
  s.x = hit.point;
  s.t = hit.t;
  s.v -= 2 * s.v.dot(hit.normal) * hit.normal;
}

/// Position uniform in the region (rejection from the bounding box), velocity isotropic.
State3 sample_microcanonical(const Table3& table, double speed, dynamics::ParticleRng& rng);

}  // namespace billiards::dynamics3
