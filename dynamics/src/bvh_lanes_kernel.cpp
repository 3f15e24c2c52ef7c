// The triangle BVH's slab test (bvh_lanes.hpp), compiled once for each SIMD target of Google
// Highway (hwy/foreach_target.h includes this file again for each, in its own namespace, as
// lockstep_kernel.cpp is): slab_test-inl.hpp's test, the source of the test without a target
// too, on as many children as a vector of floats holds: the same entry times and the same
// children entered, bit for bit, so that a walk visits the same leaves in the same order on
// every target.

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

/// Highway's vector of (at most the eight children's) floats: slab_test-inl.hpp's traits.
struct VectorLanes {
  using D = hn::CappedTag<float, width>;
  using Num = hn::Vec<D>;
  static constexpr int lanes = int(hn::MaxLanes(D()));
  static Num splat(float x) { return hn::Set(D(), x); }
  static Num load(const float* p) { return hn::LoadU(D(), p); }
  static Num convert(const std::int8_t* p) {
    return hn::ConvertTo(D(), hn::PromoteTo(hn::Rebind<std::int32_t, D>(), hn::LoadU(hn::Rebind<std::int8_t, D>(), p)));
  }
  // x86's max and min of (b, a) are b where b is beyond a, else a, a NaN b included: the
  // rule of later and earlier in one instruction.  (Highway leaves Max's and Min's NaN open
  // on other targets, which keep the comparison.)
#if HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX2 || HWY_TARGET == HWY_SSE4
  static Num later(Num a, Num b) { return hn::Max(b, a); }
  static Num earlier(Num a, Num b) { return hn::Min(b, a); }
#else
  static Num later(Num a, Num b) { return hn::IfThenElse(hn::Lt(a, b), b, a); }
  static Num earlier(Num a, Num b) { return hn::IfThenElse(hn::Lt(b, a), b, a); }
#endif
  static void store(Num v, float* p) { hn::StoreU(v, D(), p); }
  static unsigned entered(Num in, Num out) {
    std::uint8_t bits[8] = {};
    hn::StoreMaskBits(D(), hn::Le(in, out), bits);
    return bits[0];
  }
};

#include "billiards/dynamics/slab_test-inl.hpp"

unsigned enter(const float* bound, const std::int8_t* cone, const Ray& ray, float tau_max, float* t_in) {
  return slab_test<VectorLanes>(bound, cone, ray, tau_max, t_in);
}

}  // namespace billiards::dynamics::bvh_lanes::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace billiards::dynamics::bvh_lanes {

Kernel kernel_of(std::int64_t target) { BILLIARDS_KERNEL_OF(target, enter) }

}  // namespace billiards::dynamics::bvh_lanes
#endif
