// The triangle BVH's slab test (bvh3.hpp), written once over the traits S of a vector of floats
// and included into a namespace: by bvh3.hpp into billiards::dynamics::detail (four floats in an
// SSE2 register: the test without a SIMD target) and by bvh_lanes_kernel.cpp into each SIMD
// target's namespace (Highway's vectors).  The same operations in the same order, each rounded
// once (no fused multiply-add: -ffp-contract=off), on S::lanes children at a time: the same
// children entered at the same times on every target.  The traits: Num; lanes; splat(x);
// load(p), the floats p[0, lanes); convert(p), the bytes p[0, lanes) as floats; later(a, b),
// b where a < b, else a; earlier(a, b), b where b < a, else a (a NaN b, from 0 · ∞, is passed
// over by both); store(v, p); entered(in, out), bit i set where in ≤ out in lane i.
// (No include guard: included once into each namespace.)

/// One ray against the boxes of a node's eight children, `bound` [lo, hi][axis][child] as
/// floats: bit i of the result set where the ray is inside child i's box for some τ in
/// [0, tau_max], from τ = t_in[i], and its heading does not move away from the cone of child
/// i's normals, `cone` [x, y, z, −t][child] (bvh_lanes::Kernel).  The side of each slab the
/// ray enters through is chosen by the sign of its direction (Ray::enter_at), so that an empty
/// box is never entered.
template <class S>
[[gnu::always_inline]] inline unsigned slab_test(const float* bound, const std::int8_t* cone,
                                                 const bvh_lanes::Ray& ray, float tau_max, float* t_in) {
  using Num = typename S::Num;
  constexpr int width = bvh_lanes::width;
  // Each axis's slabs: the bounds the ray enters and leaves through, and its numbers.
  const float *enters[3], *leaves[3];
  Num enter[3], leave[3], inv[3], heading[3];
  for (int k = 0; k < 3; ++k) {
    enters[k] = bound + ray.enter_at[k], leaves[k] = bound + ray.leave_at[k];
    enter[k] = S::splat(ray.enter[k]), leave[k] = S::splat(ray.leave[k]), inv[k] = S::splat(ray.inv[k]);
    heading[k] = S::splat(ray.heading[k]);
  }
  unsigned mask = 0;
  for (int i = 0; i < width; i += S::lanes) {
    Num in = S::splat(0), out = S::splat(tau_max);
    for (int k = 0; k < 3; ++k) {
      in = S::later(in, (S::load(enters[k] + i) - enter[k]) * inv[k]);
      out = S::earlier(out, (S::load(leaves[k] + i) - leave[k]) * inv[k]);
    }
    S::store(in, t_in + i);
    const Num facing = (S::convert(cone + i) * heading[0] + S::convert(cone + width + i) * heading[1]) +
                       S::convert(cone + 2 * width + i) * heading[2];
    mask |= (S::entered(in, out) & S::entered(S::convert(cone + 3 * width + i), facing)) << i;
  }
  return mask;
}
