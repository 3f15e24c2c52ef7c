// The lock-step search of straight flights (free_lockstep.hpp), compiled once for each SIMD
// target of Google Highway (hwy/foreach_target.h includes this file again for each, in its own
// namespace, as lockstep_kernel.cpp is).  Its exit times are straight_exit-inl.hpp's, the
// scalar search's own source, included into each target's namespace with the traits of a
// vector of doubles, one flight per lane: the same operations in the same order, each rounded
// once (no fused multiply-add: -ffp-contract=off), so each lane's time is the scalar search's,
// bit for bit; and the walls are tried in the scalar search's order, each kept only when it is
// hit strictly earlier.

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

namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;  // the target's vector of doubles
using DI = hn::RebindToSigned<D>;   // and of 64-bit integers
constexpr int L = int(hn::MaxLanes(D()));
static_assert(lanes % L == 0, "the flights fill whole vectors");

/// Traits of a vector of doubles, one flight per lane (straight_exit-inl.hpp).  `undecided`
/// gathers the lanes whose circle discriminant the filter could not sign: the flight is then
/// handed back to the scalar search, which decides it exactly.
struct Lanes {
  using Num = hn::Vec<D>;
  using Truth = hn::Mask<D>;
  Truth undecided;

  Lanes() : undecided(hn::FirstN(D(), 0)) {}  // (not a default initializer: made for this target)

  static Num splat(double x) { return hn::Set(D(), x); }
  static Num never() { return splat(std::numeric_limits<double>::infinity()); }
  static Num select(Truth m, Num a, Num b) { return hn::IfThenElse(m, a, b); }
  static Truth select_truth(Truth m, Truth a, Truth b) { return hn::Or(hn::And(m, a), hn::AndNot(m, b)); }
  static Truth splat_truth(bool a) { return hn::FirstN(D(), a ? L : 0); }
  static bool none(Truth m) { return hn::AllFalse(D(), m); }
  /// f() where m, else g(): both computed, no branch (a branch on the flights' truths would be
  /// as unpredictable as their data)...
  template <class F, class G>
  static auto choose(Truth m, F f, G g) {
    return pick(m, f(), g());
  }
  /// ...but a branch on a wall's truth, the same in every lane.
  template <class F, class G>
  static auto choose(bool m, F f, G g) {
    return m ? f() : g();
  }
  static Truth select_truth(bool m, Truth a, Truth b) { return m ? a : b; }
  static Truth both(bool a, Truth b) { return a ? b : hn::FirstN(D(), 0); }
  static Truth both(Truth a, Truth b) { return hn::And(a, b); }
  static Truth either(Truth a, Truth b) { return hn::Or(a, b); }
  static Truth negate(Truth a) { return hn::Not(a); }
  static Num sqrt(Num x) { return hn::Sqrt(x); }
  static Num abs(Num x) { return hn::Abs(x); }
  static Num max(Num a, Num b) { return hn::IfThenElse(a < b, b, a); }  // (std::max's order)
  static Num neg(Num a) { return hn::Neg(a); }
  /// Lanes whose D lies within its error bound are `undecided`.
  template <class Bound, class Ray, class Arc>
  Truth discriminant_positive_filtered(Truth needed, Num D_, Bound bound, const Ray&, const Arc&) {
    const Num e = bound();
    const Truth positive = D_ > e;
    undecided = either(undecided, hn::AndNot(either(positive, D_ < neg(e)), needed));
    return both(needed, positive);
  }

 private:
  static Num pick(Truth m, Num a, Num b) { return select(m, a, b); }
  static Truth pick(Truth m, Truth a, Truth b) { return select_truth(m, a, b); }
};

#include "billiards/dynamics/straight_exit-inl.hpp"

using Num = Lanes::Num;
using Truth = Lanes::Truth;
using Index = hn::Vec<DI>;

/// The search's best hit so far, lane by lane: time, kind and index of the wall.
struct Best {
  Num t;
  Index kind, index;
  /// Keeps the wall (kind, i) in the lanes where it is hit before the best so far (the scalar
  /// search's strict <: the first of equal times).
  void keep(Num hit, int k, int i) {
    const Truth earlier = hit < t;
    const auto where = hn::RebindMask(DI(), earlier);
    t = hn::IfThenElse(earlier, hit, t);
    kind = hn::IfThenElse(where, hn::Set(DI(), k), kind);
    index = hn::IfThenElse(where, hn::Set(DI(), i), index);
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
  for (int i = 0; i < walls.segment_count; ++i) {
    const Segment& g = walls.segments[i];
    const SegmentLanes<Num> w{Lanes::splat(g.ax),    Lanes::splat(g.ay),    Lanes::splat(g.nx),
                              Lanes::splat(g.ny),    Lanes::splat(g.dir_x), Lanes::splat(g.dir_y),
                              Lanes::splat(g.slack), Lanes::splat(g.span_tol)};
    best.keep(straight_exit_time(lanes, s, w, t_end), 0, i);
  }
  for (int i = 0; i < walls.arc_count; ++i) {
    const Arc& a = walls.arcs[i];
    const ArcLanes<Num, bool> w{Lanes::splat(a.cx),     Lanes::splat(a.cy),       Lanes::splat(a.r),
                                Lanes::splat(a.r2),     Lanes::splat(a.near),     Lanes::splat(a.span_tol),
                                Lanes::splat(a.from_x), Lanes::splat(a.from_y),   Lanes::splat(a.to_x),
                                Lanes::splat(a.to_y),   a.focusing, a.full, a.half};
    best.keep(straight_exit_time(lanes, s, w, t_end), 1, i);
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
