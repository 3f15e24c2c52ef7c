// The lock-step search of magnetic flights (magnetic_lockstep.hpp), compiled once for each SIMD
// target of Google Highway, as free_lanes_kernel.cpp is: magnetic_exit-inl.hpp's crossings, the
// scalar search's own source, with the traits of a vector of doubles (double_lanes-inl.hpp), one
// flight per lane, each lane computing what the scalar search computes, bit for bit; the walls
// tried in the scalar search's order, each kept only where it is crossed strictly earlier.

#include "simd_targets.hpp"  // (first: the targets compiled)
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "magnetic_lanes_kernel.cpp"
#include <hwy/foreach_target.h>  // (this file, once per target)
#include <hwy/highway.h>

#include "billiards/dynamics/magnetic_lanes.hpp"
#include "billiards/dynamics/simd.hpp"

#include <cstdint>
#include <limits>
#include <type_traits>  // (straight_exit-inl.hpp: no code)

#pragma GCC diagnostic ignored "-Wpsabi"  // (vectors passed by value: inlined throughout)

HWY_BEFORE_NAMESPACE();
namespace billiards::dynamics::magnetic_lanes::HWY_NAMESPACE {

namespace {

#include "double_lanes-inl.hpp"
#include "billiards/dynamics/magnetic_exit-inl.hpp"

ReachLanes<Num> lanes_of(const Reach& r) {
  return {Lanes::splat(r.cx), Lanes::splat(r.cy), Lanes::splat(r.r), Lanes::splat(r.pad), Lanes::splat(r.slack)};
}

/// The hits of the L flights from lane `first` through the segments and arcs: as
/// Gyration::first_hit finds them, with hit_from's time and state.
void hits_of(const Walls& walls, const Flights& f, int first, Hits& out) {
  const D d;
  const DI di;
  Lanes lanes;
  const Num t0 = hn::Load(d, f.t + first), t_end = hn::Load(d, f.t_end + first);
  const GyrationLanes<Num> g =
      gyration_of(lanes, hn::Load(d, f.x + first), hn::Load(d, f.y + first), hn::Load(d, f.vx + first),
                  hn::Load(d, f.vy + first), Lanes::splat(walls.k), Lanes::splat(walls.inv_k), walls.clockwise,
                  Lanes::splat(16 * std::numeric_limits<double>::epsilon()));
  EarliestCrossing<Num, Truth> earliest{{Lanes::splat(0), Lanes::splat(0)}, Lanes::splat_truth(false)};
  Index kind = hn::Set(di, -1), index = hn::Set(di, -1);
  auto keep = [&](const auto& wall, const Reach& reach, int k, int i) {
    const Truth kept = keep_earlier_crossing(lanes, g, lanes_of(wall), lanes_of(reach), earliest);
    assign_where(kept, k, kind);
    assign_where(kept, i, index);
  };
  for (int i = 0; i < walls.straight.segment_count; ++i) keep(walls.straight.segments[i], walls.segments[i], 0, i);
  for (int i = 0; i < walls.straight.arc_count; ++i) keep(walls.straight.arcs[i], walls.arcs[i], 1, i);
  // As hit_from: the crossing's time, if before the horizon, and the state there.
  const Num t = crossing_time(lanes, g, earliest.u, t0);
  const Truth found = hn::And(earliest.found, t < t_end);
  const auto p = turned_by<Lanes>(g, earliest.u);
  hn::Store(hn::IfThenElse(found, t, t_end), d, out.t + first);
  hn::Store(hn::IfThenElse(hn::RebindMask(di, found), kind, hn::Set(di, -1)), di, out.kind + first);
  hn::Store(index, di, out.index + first);
  hn::StoreInterleaved2(p.x, p.y, d, out.position + 2 * first);
  hn::StoreInterleaved2(p.vx, p.vy, d, out.velocity + 2 * first);
}

}  // namespace

void hits(const Walls& walls, const Flights& flights, Hits& out) {
  for (int first = 0; first < lanes; first += L) hits_of(walls, flights, first, out);
}

}  // namespace billiards::dynamics::magnetic_lanes::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace billiards::dynamics::magnetic_lanes {

Kernel kernel_of(std::int64_t target) { BILLIARDS_KERNEL_OF(target, hits) }

}  // namespace billiards::dynamics::magnetic_lanes
#endif
