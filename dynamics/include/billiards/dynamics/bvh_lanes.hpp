// The triangle BVH's slab test in SIMD lanes (bvh3.hpp): one ray against the boxes of a node's
// eight children at once, compiled for each SIMD target by Google Highway
// (src/bvh_lanes_kernel.cpp) and chosen at run time like the other kernels (simd.hpp); its
// plain data, which the kernel reads, and nothing it could share with the rest of the program
// (see lockstep_lanes.hpp for why).
#pragma once

#include <cstdint>

namespace billiards::dynamics::bvh_lanes {

/// Children of a node.
inline constexpr int width = 8;

/// A ray as the slab test reads it: origin x, the inverse inv of its direction (a zero
/// component replaced by a tiny one), the side through which it enters each slab (near: 0 lo,
/// 1 hi) and the pad signed to grow a box on that side.
struct Ray {
  double x[3], inv[3], grow[3];
  int near[3];
};

/// Bit i of the result set: the ray is inside child i's box for some τ in [0, tau_max], from
/// τ = t_in[i].  `bound`: the children's boxes as floats, [lo, hi][axis][child] (Bvh::Node).
using Kernel = unsigned (*)(const float* bound, const Ray& ray, double tau_max, double* t_in);
/// The slab test as compiled for a target (simd.hpp's bits); nullptr for simd::scalar.
Kernel kernel_of(std::int64_t target);

}  // namespace billiards::dynamics::bvh_lanes
