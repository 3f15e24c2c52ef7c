// The drive's phase in double, written once over a number type: the exact sums and products of
// two doubles, the run's clock in two doubles, the phase's reduction to [0, 2π) in two doubles,
// its sine and cosine, and their shift to a nearby phase.  Included into a namespace by
// error_free.hpp (the scalar flights, with ScalarLanes) and by lockstep_kernel.cpp and
// free_lanes_kernel.cpp (each SIMD target's lanes), after
// phase_constants.hpp.  A `Lanes` traits class `L` supplies, besides arithmetic on L::Num:
//   L::splat(x), L::fraction(a, b) (a/b rounded once in Num), L::select(m, a, b), L::none(m),
//   L::either(m, n), L::abs, L::neg, L::trunc(x) (toward zero) and L::to_quadrant(k, s, c).
// (No include guard: included once into each namespace.  It includes nothing: see
// straight_exit-inl.hpp.  Its lambdas are inlined always: GCC calls a lambda of sixteen lanes
// out of line, which made the lock-step search a quarter slower.)

/// An unevaluated sum hi + lo (an exact sum or product, a phase in two doubles).
template <class Num>
struct Unevaluated {
  Num hi, lo;
};

/// sin and cos of one phase.
template <class Num>
struct SinCos {
  Num sin, cos;
};

/// a + b = hi + lo exactly (Knuth's TwoSum).
template <class Num>
[[gnu::always_inline]] inline Unevaluated<Num> two_sum(const Num& a, const Num& b) {
  const Num s = a + b, bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}

/// a + b = hi + lo exactly when |a| ≥ |b| or a = 0 (Dekker's FastTwoSum).
template <class Num>
[[gnu::always_inline]] inline Unevaluated<Num> fast_two_sum(const Num& a, const Num& b) {
  const Num s = a + b;
  return {s, b - (s - a)};
}

/// The run's clock hi + lo (state.hpp's Clock) after a flight of dt: to the 106 bits of hi + lo.
template <class Num>
[[gnu::always_inline]] inline Unevaluated<Num> clock_after_flight(const Unevaluated<Num>& clock, const Num& dt) {
  const auto [s, e] = two_sum(clock.hi, dt);
  return fast_two_sum(s, Num(e + clock.lo));
}

/// T − (hi + lo) rounded once (to within an ulp): the time from the clock to T.
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num clock_until(const Unevaluated<Num>& clock, const Num& T) {
  const auto [s, e] = two_sum(T, L::neg(clock.hi));
  return s + (e - clock.lo);
}

/// a·b = hi + lo exactly for |a|, |b| < 2⁹⁹⁵ (Dekker's product on Veltkamp's halves).  Not a
/// fused multiply-add: x86-64 without -mfma calls one from libm, and these are the same bits
/// on any processor (the build forbids contraction: CMakeLists.txt).
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Unevaluated<Num> two_prod(const Num& a, const Num& b) {
  auto split = [](const Num& x) __attribute__((always_inline)) {
    const Num c = L::splat(phase_constants::split) * x, high = c - (c - x);
    return Unevaluated<Num>{high, x - high};
  };
  const auto [ah, al] = split(a);
  const auto [bh, bl] = split(b);
  const Num p = a * b;
  return {p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
}

/// θ + ω τ, exact in two doubles: ω τ as its rounding and its exact error (not reduced).
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Unevaluated<Num> advance_phase(const Unevaluated<Num>& theta, const Num& omega,
                                                             const Num& tau) {
  const auto [p, e] = two_prod<L>(omega, tau);
  const auto [s, t] = two_sum(theta.hi, p);
  return {s, t + (theta.lo + e)};
}

/// a − b, unnormalized (the shift from a sampled phase to the precise one).
template <class Num>
[[gnu::always_inline]] inline Unevaluated<Num> phase_difference(const Unevaluated<Num>& a, const Unevaluated<Num>& b) {
  const auto [s, e] = two_sum(a.hi, Num(-b.hi));
  return {s, e + (a.lo - b.lo)};
}

/// θ − k·2π with 2π = C1 + C2 + C3 (phase_constants.hpp): k·C1 and k·C2 exact, and θ.hi − k·C1
/// exact (both are multiples of θ.hi's ulp) for |k| ≤ 2²⁶.
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Unevaluated<Num> minus_turns(const Unevaluated<Num>& theta, const Num& k) {
  using namespace phase_constants;
  const auto [s, e] = two_sum(Num(theta.hi - k * L::splat(C1)), L::neg(k * L::splat(C2)));
  return fast_two_sum(s, Num(e + (theta.lo - k * L::splat(C3))));
}

/// θ = hi + lo reduced to [0, 2π) (to rounding: a result within an ulp of 2π may stay there),
/// for |hi| < phase_constants::fast_limit: within 1e-23 rad of the exact remainder.  k,
/// truncated, may be off by one beside a multiple of 2π: the reduction is then made again with
/// the next k.
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Unevaluated<Num> reduce_phase_below_limit(const Unevaluated<Num>& theta) {
  using namespace phase_constants;
  const Num k = L::trunc(theta.hi * L::splat(inv_two_pi));
  const Unevaluated<Num> r = minus_turns<L>(theta, k);
  const auto below = r.hi < L::splat(0), above = r.hi >= L::splat(two_pi);
  if (L::none(L::either(below, above))) return r;
  const Unevaluated<Num> again = minus_turns<L>(theta, L::select(below, Num(k - L::splat(1)), Num(k + L::splat(1))));
  const auto redo = L::either(below, above);
  return {L::select(redo, again.hi, r.hi), L::select(redo, again.lo, r.lo)};
}

/// fdlibm's kernels (__kernel_sin, __kernel_cos): sin and cos on |x| ≤ π/4 to below one ulp.
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num kernel_sin(const Num& x) {
  const Num z = x * x;
  const Num r = L::splat(8.33333333332248946124e-03) +
                z * (L::splat(-1.98412698298579493134e-04) +
                     z * (L::splat(2.75573137070700676789e-06) +
                          z * (L::splat(-2.50507602534068634195e-08) + z * L::splat(1.58969099521155010221e-10))));
  return x + z * x * (L::splat(-1.66666666666666324348e-01) + z * r);
}
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num kernel_cos(const Num& x) {
  const Num z = x * x;
  const Num r =
      z * (L::splat(4.16666666666666019037e-02) +
           z * (L::splat(-1.38888888888741095749e-03) +
                z * (L::splat(2.48015872894767294178e-05) +
                     z * (L::splat(-2.75573143513906633035e-07) +
                          z * (L::splat(2.08757232129817482790e-09) + z * L::splat(-1.13596475577881948265e-11))))));
  const Num hz = L::splat(0.5) * z, w = L::splat(1.0) - hz;
  return w + (((L::splat(1.0) - w) - hz) + z * r);
}

/// sin θ and cos θ for |θ| < 2¹⁹π: θ = kπ/2 + x with fdlibm's two-part π/2 (the first part has
/// 33 bits, so kπ/2 is exact for k < 2²⁰), and the kernels above on x; the absolute error
/// stays within ~1.5 ulp of 1 (tested against MPFR).
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline SinCos<Num> sin_cos_below_limit(const Num& theta) {
  constexpr double two_over_pi = 6.36619772367581382433e-01, pio2_1 = 1.57079632673412561417e+00,
                   pio2_1t = 6.07710050650619224932e-11;
  // (k rounded to nearest, without SSE4.1's rounding instruction.)
  const Num k = (theta * L::splat(two_over_pi) + L::splat(0x1.8p52)) - L::splat(0x1.8p52);
  const Num x = (theta - k * L::splat(pio2_1)) - k * L::splat(pio2_1t);
  SinCos<Num> r{kernel_sin<L>(x), kernel_cos<L>(x)};
  L::to_quadrant(k, r.sin, r.cos);
  return r;
}

/// sin and cos of θ + h, |h| ≤ 0.05, from those of θ by the angle-sum formulas, with sin h and
/// cos h − 1 from their Taylor series (remainders below h⁹/9! = 5.4e-18): a fifth of a sine
/// and cosine.  The series' ratios are multiplied by their reciprocals, not divided: six
/// divisions sat on the way from a root to the hit's state (the reciprocals' rounding, ~1e-16
/// of terms below z/6 ≈ 4e-4, is far below the remainder).
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline SinCos<Num> shifted(const SinCos<Num>& at, const Num& h) {
  const Num one = L::splat(1), z = h * h;
  const Num sin_h = h * (one - z * L::fraction(1, 6) * (one - z * L::fraction(1, 20) * (one - z * L::fraction(1, 42))));
  const Num cos_h_1 = L::neg(z) * L::splat(0.5) *
                      (one - z * L::fraction(1, 12) * (one - z * L::fraction(1, 30) * (one - z * L::fraction(1, 56))));
  return {at.sin + (at.sin * cos_h_1 + at.cos * sin_h), at.cos + (at.cos * cos_h_1 - at.sin * sin_h)};
}
