// The lock-step search of straight flights (free_lockstep.hpp), compiled once for each SIMD
// target of Google Highway (hwy/foreach_target.h includes this file again for each, in its own
// namespace, as lockstep_kernel.cpp is).  Its exit times are straight_exit-inl.hpp's, the
// scalar search's own source, included into each target's namespace with the traits of a
// vector of doubles, one flight per lane: the same operations in the same order, each rounded
// once (no fused multiply-add: -ffp-contract=off), so each lane's time is the scalar search's,
// bit for bit; and the walls are tried in the scalar search's order, each kept only when it is
// hit strictly earlier.  An elliptic arc is its unit arc, hit by the flight seen through the
// ellipse's map (mapped_ray), as the scalar search sees it.  The 3-D kernel does the same
// through planes and spheres with straight_exit3-inl.hpp's exit times, walls3.cpp's source.

#include "simd_targets.hpp"  // (first: the targets compiled)
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "free_lanes_kernel.cpp"
#include <hwy/foreach_target.h>  // (this file, once per target)
#include <hwy/highway.h>

#include "billiards/dynamics/free_lanes.hpp"
#include "billiards/dynamics/simd.hpp"

#include <cstdint>
#include <limits>
#include <type_traits>  // (straight_exit-inl.hpp: no code)

#pragma GCC diagnostic ignored "-Wpsabi"  // (vectors passed by value: inlined throughout)

HWY_BEFORE_NAMESPACE();
namespace billiards::dynamics::free_lanes::HWY_NAMESPACE {

namespace {

#include "double_lanes-inl.hpp"
#include "billiards/dynamics/straight_exit3-inl.hpp"

/// A plane or a sphere, the same in every lane.
PlaneLanes<Num> lanes_of(const Plane& p) {
  return {Lanes::splat(p.nx), Lanes::splat(p.ny), Lanes::splat(p.nz), Lanes::splat(p.offset), Lanes::splat(p.slack)};
}
SphereLanes<Num, bool> lanes_of(const Sphere& b) {
  return {Lanes::splat(b.cx), Lanes::splat(b.cy), Lanes::splat(b.cz),
          Lanes::splat(b.r),  Lanes::splat(b.r2), Lanes::splat(b.near), b.focusing};
}

/// The search's best hit so far, lane by lane: time, kind and index of the wall.
struct Best {
  Num t;
  Index kind, index;
  explicit Best(Num t_end) : t(t_end), kind(hn::Set(DI(), -1)), index(hn::Set(DI(), -1)) {}
  /// Keeps the wall (kind, i) in the lanes where it is hit before the best so far (the scalar
  /// search's strict <: the first of equal times).
  void keep(Num hit, int k, int i) {
    const Truth earlier = hit < t;
    t = hn::IfThenElse(earlier, hit, t);
    assign_where(earlier, k, kind);
    assign_where(earlier, i, index);
  }
  /// The lanes' hits into those from lane `first` (handed back: those `undecided`).
  void store(const Lanes& lanes, int first, Hits& hits) const {
    const DI di;
    hn::Store(t, D(), hits.t + first);
    hn::Store(kind, di, hits.kind + first);
    hn::Store(index, di, hits.index + first);
    hn::Store(hn::VecFromMask(di, hn::RebindMask(di, lanes.undecided)), di, hits.handed_back + first);
  }
};

/// The first hits of the L flights from lane `first`.
void first_hits_of(const Walls& walls, const Rays& rays, int first, Hits& hits) {
  const D d;
  Lanes lanes;
  const RayLanes<Num> s{hn::Load(d, rays.x + first), hn::Load(d, rays.y + first), hn::Load(d, rays.vx + first),
                        hn::Load(d, rays.vy + first), hn::Load(d, rays.t + first), hn::Load(d, rays.vv + first)};
  const Num t_end = hn::Load(d, rays.t_end + first);
  Best best(t_end);
  for (int i = 0; i < walls.segment_count; ++i)
    best.keep(straight_exit_time(lanes, s, lanes_of(walls.segments[i]), t_end), 0, i);
  for (int i = 0; i < walls.arc_count; ++i) best.keep(straight_exit_time(lanes, s, lanes_of(walls.arcs[i]), t_end), 1, i);
  for (int i = 0; i < walls.ellipse_count; ++i) {
    const Ellipse& e = walls.ellipses[i];
    best.keep(straight_exit_time(lanes, mapped_ray<Lanes>(s, lanes_of(e)), lanes_of(e.unit), t_end), 2, i);
  }
  best.store(lanes, first, hits);
}

/// The same in 3-D: the planes, then the spheres (Table3::collision's order of kinds).
void first_hits3_of(const Walls3& walls, const Rays3& rays, int first, Hits& hits) {
  const D d;
  Lanes lanes;
  const Ray3Lanes<Num> s{hn::Load(d, rays.x + first),  hn::Load(d, rays.y + first),  hn::Load(d, rays.z + first),
                         hn::Load(d, rays.vx + first), hn::Load(d, rays.vy + first), hn::Load(d, rays.vz + first),
                         hn::Load(d, rays.t + first),  hn::Load(d, rays.vv + first)};
  const Num t_end = hn::Load(d, rays.t_end + first);
  Best best(t_end);
  for (int i = 0; i < walls.plane_count; ++i) best.keep(straight_exit_time(lanes, s, lanes_of(walls.planes[i]), t_end), 0, i);
  for (int i = 0; i < walls.sphere_count; ++i)
    best.keep(straight_exit_time(lanes, s, lanes_of(walls.spheres[i]), t_end), 2, i);
  best.store(lanes, first, hits);
}

}  // namespace

void first_hits(const Walls& walls, const Rays& rays, Hits& hits) {
  for (int first = 0; first < lanes; first += L) first_hits_of(walls, rays, first, hits);
}
void first_hits3(const Walls3& walls, const Rays3& rays, Hits& hits) {
  for (int first = 0; first < lanes; first += L) first_hits3_of(walls, rays, first, hits);
}

}  // namespace billiards::dynamics::free_lanes::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace billiards::dynamics::free_lanes {

Kernel kernel_of(std::int64_t target) { BILLIARDS_KERNEL_OF(target, first_hits) }
Kernel3 kernel3_of(std::int64_t target) { BILLIARDS_KERNEL_OF(target, first_hits3) }

}  // namespace billiards::dynamics::free_lanes
#endif
