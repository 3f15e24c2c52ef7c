// The exit time of a straight 3-D flight through a plane or a sphere (walls3.hpp's rules),
// written once over a number type as straight_exit-inl.hpp is for the 2-D walls, and included
// into a namespace: by straight_exit3.hpp into billiards::dynamics (the scalar search,
// walls3.cpp), and by free_lanes_kernel.cpp into each SIMD target's namespace (one particle per
// lane).  The traits `L` are straight_exit-inl.hpp's; the sphere's discriminant is signed by
// l.discriminant_positive_filtered(needed, D, bound, ray, sphere), which sees a 3-D ray.
// (No include guard: included once into each namespace.)

/// The start of a straight 3-D flight: position, velocity, time, |v|².
template <class F, class Num = std::remove_cv_t<std::remove_reference_t<F>>>
struct Ray3Lanes {
  F x, y, z, vx, vy, vz, t;
  Num vv;
};

/// A face of a convex polyhedron, n·x ≤ offset (PlaneWall).
template <class F>
struct PlaneLanes {
  F nx, ny, nz, offset, slack;
};

/// A sphere (SphereWall); `near` is 2 r × slack, "on the sphere to rounding" in units of
/// |x − c|² − r².  Its truth is a bool where every lane holds the same wall.
template <class F, class Truth>
struct SphereLanes {
  F cx, cy, cz, r, r2, near;
  Truth focusing;  // the region is inside the sphere
};

/// r²|v|² − |f × v|² (f = x − c), the cancellation-free b² − a c of the ray–sphere quadratic,
/// and the bound of its rounding in double: the rounding of f (1 ulp each), the products, the
/// cross product's components, their squares and the sums stays well under 16 ε of the
/// magnitudes r²|v|² + Σ (|f_i v_j| + |f_j v_i|)²; 32 for margin.
template <class L>
struct SphereDiscriminant {
  typename L::Num D, bound;
};
template <class L>
[[gnu::always_inline]] inline SphereDiscriminant<L> sphere_discriminant(const typename L::Num& fx, const typename L::Num& fy,
                                                                        const typename L::Num& fz, const typename L::Num& vx,
                                                                        const typename L::Num& vy, const typename L::Num& vz,
                                                                        const typename L::Num& r2v2) {
  using Num = typename L::Num;
  const Num cx = fy * vz - fz * vy, cy = fz * vx - fx * vz, cz = fx * vy - fy * vx;
  const Num sx = L::abs(fy * vz) + L::abs(fz * vy), sy = L::abs(fz * vx) + L::abs(fx * vz),
            sz = L::abs(fx * vy) + L::abs(fy * vx);
  const Num spread2 = (sx * sx + sy * sy) + sz * sz;
  return {Num(r2v2 - ((cx * cx + cy * cy) + cz * cz)),
          Num(L::splat(32 * std::numeric_limits<double>::epsilon()) * (r2v2 + spread2))};
}

/// The time the straight flight from s leaves through the plane w (before t_end), else
/// `never`: moving outward, not beyond it by more than its slack (a particle just reflected at
/// an edge may be beyond it by rounding: now).  No span: the region is the intersection of the
/// half-spaces.
template <class L, class FR, class FW>
[[gnu::always_inline]] inline typename L::Num straight_exit_time(L& l, const Ray3Lanes<FR>& s, const PlaneLanes<FW>& w,
                                                                 const typename L::Num& t_end) {
  using Num = typename L::Num;
  const Num zero = L::splat(0), no = L::never();
  const Num rate = (w.nx * s.vx + w.ny * s.vy) + w.nz * s.vz;
  const Num beyond = ((w.nx * s.x + w.ny * s.y) + w.nz * s.z) - w.offset;
  const auto exits = l.both(rate > zero, l.negate(beyond > w.slack));
  if (l.none(exits)) return no;
  const Num t = s.t + l.choose(beyond >= zero, [&] { return zero; }, [&] { return Num(L::neg(beyond) / rate); });
  return L::select(l.both(exits, t <= t_end), t, no);
}

/// The time the straight flight from s leaves the region through the sphere w (before t_end),
/// else `never`.  Region inside (focusing): through the far root; on the sphere to rounding and
/// moving out, now.  Region outside (dispersing): through the near root, only approaching; in
/// the ball by rounding only, now; deeper, the particle is not near it.  Starting outside the
/// sphere, a miss or an exact tangency (a touch, not a crossing) is no exit: the discriminant's
/// exact sign decides.
template <class L, class FR, class FW, class WT>
[[gnu::always_inline]] inline typename L::Num straight_exit_time(L& l, const Ray3Lanes<FR>& s, const SphereLanes<FW, WT>& w,
                                                                 const typename L::Num& t_end) {
  using Num = typename L::Num;
  const Num zero = L::splat(0), no = L::never();
  // |f + v τ|² − r² = a τ² + 2 b τ + c with f = x − centre.
  const Num fx = s.x - w.cx, fy = s.y - w.cy, fz = s.z - w.cz;
  const Num& a = s.vv;
  const Num b = (fx * s.vx + fy * s.vy) + fz * s.vz;
  const Num c = ((fx * fx + fy * fy) + fz * fz) - w.r2;
  const auto leaving_now = l.both(b >= zero, c >= zero);
  const auto now = [&] { return L::select(l.both(w.focusing, leaving_now), L::select(c <= w.near, s.t, no), no); };
  const auto ahead = l.select_truth(w.focusing, l.negate(leaving_now), l.both(b < zero, l.negate(c < L::neg(w.near))));
  if (l.none(ahead)) return now();
  const auto outside = c > zero;
  const SphereDiscriminant<L> disc = sphere_discriminant<L>(fx, fy, fz, s.vx, s.vy, s.vz, Num(w.r2 * a));
  const auto crossing = l.discriminant_positive_filtered(l.both(ahead, outside), disc.D, [&] { return disc.bound; }, s, w);
  const auto exits = l.both(ahead, l.either(l.negate(outside), crossing));
  if (l.none(exits)) return now();
  const Num root = L::sqrt(L::max(zero, disc.D));
  const Num dt = l.choose(w.focusing, [&] {
    // (root − b)/a, or where b > 0 the same root without cancelling, −c/(b + root).
    const auto small_b = b <= zero;
    return Num(L::select(small_b, Num(root - b), L::neg(c)) / L::select(small_b, a, Num(b + root)));
  }, [&] { return l.choose(outside, [&] { return Num(c / (root - b)); }, [&] { return zero; }); });
  const Num t = s.t + dt;
  return l.choose(l.both(exits, t <= t_end), [&] { return t; }, now);
}
