// The triangle BVH's slab test in SIMD lanes (bvh3.hpp): one ray against the boxes of a node's
// eight children at once, in floats, compiled for each SIMD target by Google Highway
// (src/bvh_lanes_kernel.cpp) and chosen at run time like the other kernels (simd.hpp); its
// plain data, which the kernel reads, and nothing it could share with the rest of the program
// (see lockstep_lanes.hpp for why).
#pragma once

#include <cstdint>

namespace billiards::dynamics::bvh_lanes {

/// Children of a node.
inline constexpr int width = 8;

/// A ray as the slab test reads it, in floats (detail::BvhRay makes one): for each axis the
/// origin as moved towards the side through which the ray enters the slab (`enter`) and
/// towards the side it leaves through (`leave`), the inverse `inv` of its direction (±∞
/// where that is beyond the floats), and where in a node's `bound` the children's bounds it
/// enters and leaves through start (`enter_at`, `leave_at`: the lo or the hi row, by the sign
/// of its direction; offsets, so that the test picks its rows without arithmetic);
/// `heading`, the unit direction of a straight flight, which cannot leave the region through
/// a triangle it moves away from, or zero (a path that only stays near the ray).
struct Ray {
  float enter[3], leave[3], inv[3], heading[3];
  int enter_at[3], leave_at[3];
};

/// Bit i of the result set: the ray is inside child i's box for some τ in [0, tau_max], from
/// τ = t_in[i], and does not move away from all its triangles.  `bound`: the children's boxes
/// as floats, [lo, hi][axis][child]; `cone`: [x, y, z, −t][child], the cones of their
/// triangles' normals, so that heading · (x, y, z) < −t in floats only where the heading moves
/// away from every triangle of child i (Bvh::Node).
using Kernel = unsigned (*)(const float* bound, const std::int8_t* cone, const Ray& ray, float tau_max,
                            float* t_in);
/// The slab test as compiled for a target (simd.hpp's bits); nullptr for simd::scalar.
Kernel kernel_of(std::int64_t target);

}  // namespace billiards::dynamics::bvh_lanes
