// The specular bounce off a wall's normal, written once over a number type and included into a
// namespace: by collision.hpp into billiards::dynamics::detail (every flight's bounce, in
// double, long double or MPFR) and by free_lanes_kernel.cpp into each SIMD target's namespace
// (the free ensembles' bounces, one particle per lane).  A `Lanes` traits class `L`
// (straight_exit-inl.hpp's) supplies L::Num, L::splat, L::select, L::none, L::abs and L::sqrt (and std::numeric_limits);
// v and n are anything indexed by component (an Eigen vector, an array of lanes) and D is their
// dimension.  The dot products v·n and |v|² are the caller's: Eigen orders a 3-D sum's terms by
// the number type, and each caller keeps its own bits.
// (No include guard: included once into each namespace.  It includes nothing: see
// straight_exit-inl.hpp.)

/// n·n − 1 for a unit vector to rounding, as (n₀² − 1) + n₁² (+ n₂²): its roundings are those of
/// generic numbers, unbiased, never that of a sum near 1 (n·n rounded near 1 resolves only ε/2
/// below 1 and ε above, a biased rounding).  No error-free product: the squares' own rounding
/// errors, ε/4 on average and of zero mean, make it noise of η's size, not a drift.
template <class L, int D, class N>
[[gnu::always_inline]] inline typename L::Num unit_excess(const N& n) {
  typename L::Num excess = n[0] * n[0] - L::splat(1);
  for (int i = 1; i < D; ++i) excess = excess + n[i] * n[i];
  return excess;
}

/// v − k n/(n·n) in place, the division by n·n as 1 − η (collision.hpp's reflect).
template <class L, int D, class V, class N>
[[gnu::always_inline]] inline void reflect_in_place(V& v, const N& n, const typename L::Num& k) {
  const typename L::Num k_excess = k * unit_excess<L, D>(n);
  for (int i = 0; i < D; ++i) v[i] = (v[i] - k * n[i]) + k_excess * n[i];
}

/// The band in which restore_speed leaves |v|² alone: relative to v2, 4 ε.
template <class Real>
inline const Real speed_band = 4 * std::numeric_limits<Real>::epsilon();

/// v rescaled to the speed² v2 where its own, now = |v|², lies outside the band about v2 (band:
/// relative to v2; collision.hpp's restore_speed).
template <class L, int D, class V>
[[gnu::always_inline]] inline void restore_speed_in_place(V& v, const typename L::Num& v2, const typename L::Num& now,
                                                          const typename L::Num& band) {
  const auto outside = L::abs(now - v2) > band * v2;
  if (L::none(outside)) return;
  const typename L::Num factor = L::sqrt(v2 / now);
  for (int i = 0; i < D; ++i) v[i] = L::select(outside, v[i] * factor, v[i]);
}
