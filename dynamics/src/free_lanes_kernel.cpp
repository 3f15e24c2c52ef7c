// The lock-step search of straight flights (free_lockstep.hpp), compiled once for each SIMD
// target of Google Highway (hwy/foreach_target.h includes this file again for each, in its own
// namespace, as lockstep_kernel.cpp is).  Its exit times are straight_exit-inl.hpp's, the
// scalar search's own source, included into each target's namespace with the traits of a
// vector of doubles, one flight per lane: the same operations in the same order, each rounded
// once (no fused multiply-add: -ffp-contract=off), so each lane's time is the scalar search's,
// bit for bit; and the walls are tried in the scalar search's order, each kept only when it is
// hit strictly earlier.  An elliptic arc is its unit arc, hit by the flight seen through the
// ellipse's map (mapped_ray), as the scalar search sees it.

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

/// The search's best hit so far, lane by lane: time, kind and index of the wall.
struct Best {
  Num t;
  Index kind, index;
  /// Keeps the wall (kind, i) in the lanes where it is hit before the best so far (the scalar
  /// search's strict <: the first of equal times).
  void keep(Num hit, int k, int i) {
    const Truth earlier = hit < t;
    t = hn::IfThenElse(earlier, hit, t);
    assign_where(earlier, k, kind);
    assign_where(earlier, i, index);
  }
};

/// The first hits of the L flights from lane `first`.
void first_hits_of(const Walls& walls, const Rays& rays, int first, Hits& hits) {
  const D d;
  const DI di;
  Lanes lanes;
  const RayLanes<Num> s{hn::Load(d, rays.x + first), hn::Load(d, rays.y + first), hn::Load(d, rays.vx + first),
                        hn::Load(d, rays.vy + first), hn::Load(d, rays.t + first), hn::Load(d, rays.vv + first)};
  const Num t_end = hn::Load(d, rays.t_end + first);
  Best best{t_end, hn::Set(di, -1), hn::Set(di, -1)};
  for (int i = 0; i < walls.segment_count; ++i)
    best.keep(straight_exit_time(lanes, s, lanes_of(walls.segments[i]), t_end), 0, i);
  for (int i = 0; i < walls.arc_count; ++i) best.keep(straight_exit_time(lanes, s, lanes_of(walls.arcs[i]), t_end), 1, i);
  for (int i = 0; i < walls.ellipse_count; ++i) {
    const Ellipse& e = walls.ellipses[i];
    best.keep(straight_exit_time(lanes, mapped_ray<Lanes>(s, lanes_of(e)), lanes_of(e.unit), t_end), 2, i);
  }
  hn::Store(best.t, d, hits.t + first);
  hn::Store(best.kind, di, hits.kind + first);
  hn::Store(best.index, di, hits.index + first);
  hn::Store(hn::VecFromMask(di, hn::RebindMask(di, lanes.undecided)), di, hits.handed_back + first);
}

}  // namespace

void first_hits(const Walls& walls, const Rays& rays, Hits& hits) {
  for (int first = 0; first < lanes; first += L) first_hits_of(walls, rays, first, hits);
}

}  // namespace billiards::dynamics::free_lanes::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace billiards::dynamics::free_lanes {

Kernel kernel_of(std::int64_t target) { BILLIARDS_KERNEL_OF(target, first_hits) }

}  // namespace billiards::dynamics::free_lanes
#endif
