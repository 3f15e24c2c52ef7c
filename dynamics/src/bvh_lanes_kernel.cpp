// The triangle BVH's slab test (bvh_lanes.hpp), compiled once for each SIMD target of Google
// Highway (hwy/foreach_target.h includes this file again for each, in its own namespace, as
// lockstep_kernel.cpp is).  The scalar test's operations (detail::BvhRay::enter, bvh3.hpp) in
// the same order, each rounded once (no fused multiply-add: -ffp-contract=off), on as many
// children as a vector of doubles holds: the same entry times and the same children entered,
// bit for bit, so that a walk visits the same leaves in the same order on every target.

#include "simd_targets.hpp"  // (first: the targets compiled)
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "bvh_lanes_kernel.cpp"
#include <hwy/foreach_target.h>  // (this file, once per target)
#include <hwy/highway.h>

#include "billiards/dynamics/bvh_lanes.hpp"

#include <cstdint>

HWY_BEFORE_NAMESPACE();
namespace billiards::dynamics::bvh_lanes::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;

unsigned enter(const float* bound, const Ray& ray, double tau_max, double* t_in) {
  const hn::CappedTag<double, width> d;  // (at most the eight children)
  const hn::Rebind<float, decltype(d)> df;
  using V = hn::Vec<decltype(d)>;
  constexpr int n = int(hn::MaxLanes(d));
  // Each axis's slabs: the bounds the ray enters and leaves through, and its numbers.
  const float *enters[3], *leaves[3];
  V grow[3], x[3], inv[3];
  for (int k = 0; k < 3; ++k) {
    enters[k] = bound + (ray.near[k] * 3 + k) * width;
    leaves[k] = bound + ((1 - ray.near[k]) * 3 + k) * width;
    grow[k] = hn::Set(d, ray.grow[k]), x[k] = hn::Set(d, ray.x[k]), inv[k] = hn::Set(d, ray.inv[k]);
  }
  unsigned mask = 0;
  for (int i = 0; i < width; i += n) {
    V in = hn::Zero(d), out = hn::Set(d, tau_max);
    for (int k = 0; k < 3; ++k) {
      const V ta = hn::Mul(hn::Sub(hn::Sub(hn::PromoteTo(d, hn::LoadU(df, enters[k] + i)), grow[k]), x[k]), inv[k]);
      const V tb = hn::Mul(hn::Sub(hn::Add(hn::PromoteTo(d, hn::LoadU(df, leaves[k] + i)), grow[k]), x[k]), inv[k]);
      in = hn::IfThenElse(hn::Lt(in, ta), ta, in);  // (as the scalar test: in < ta ? ta : in)
      out = hn::IfThenElse(hn::Lt(tb, out), tb, out);
    }
    hn::StoreU(in, d, t_in + i);
    std::uint8_t entered[8] = {};
    hn::StoreMaskBits(d, hn::Le(in, out), entered);
    mask |= unsigned(entered[0]) << i;
  }
  return mask;
}

}  // namespace billiards::dynamics::bvh_lanes::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace billiards::dynamics::bvh_lanes {

Kernel kernel_of(std::int64_t target) { BILLIARDS_KERNEL_OF(target, enter) }

}  // namespace billiards::dynamics::bvh_lanes
#endif
