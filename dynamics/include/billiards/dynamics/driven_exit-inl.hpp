// A driven flight's search through a line or a plane, a circle or a sphere, written once over
// a number type: the guide's numbers, each gap's rounding, its windows along the guiding line,
// the sign of f' in a window, its Taylor sample, the span test of a window, and the bracketed
// Halley step that finds the root.  Included into a namespace by certified_scan.hpp (scan: PlaneGap, SphereGap
// and monotone_crossing, in double, long double and MPFR, 2-D and 3-D) and by
// lockstep_kernel.cpp (each SIMD target's lanes).  Its numbers are scalars: the dot products
// of the flight's vectors, which depend on the dimension, are its callers'.  Besides
// straight_exit-inl.hpp's traits, `L` supplies L::eps() (the number's), L::min (std::min's
// order), L::fraction(a, b) and L::two_pi().
// (No include guard: included once into each namespace.  It includes nothing: see
// straight_exit-inl.hpp.  Its lambdas are inlined always: GCC calls a lambda of sixteen lanes
// out of line, which made the lock-step search a quarter slower.)

/// What a gap's scan knows of a driven flight (forced_flight.hpp's Quiver): its guiding line
/// g0 + u τ, |u|² and 1/|u|² (0 when u = 0), |u|, the bound on the speed, the bounds |F|/(mω)
/// and |F|/(mω²) on the deviations of velocity and position from the guide's, |F|/m, and the
/// drive's ω (the rate at which the acceleration turns) and 1/ω.
template <class F>
struct GuideLanes {
  F uu, inv_uu, speed, speed_bound, wobble, delta, accel_norm, omega, inv_omega;
};

/// A flight's guide numbers from |u|² and the drive's |F|/m, ω, 1/ω and δ = |F|/(mω²).
template <class L>
GuideLanes<typename L::Num> guide_lanes(typename L::Num uu, typename L::Num accel_norm, typename L::Num omega,
                                        typename L::Num inv_omega, typename L::Num delta) {
  using Num = typename L::Num;
  const Num speed = L::sqrt(uu), wobble = accel_norm * inv_omega;
  return {uu,    L::select(uu > L::splat(0), Num(L::splat(1) / uu), L::splat(0)), speed, Num(speed + wobble), wobble,
          delta, accel_norm, omega, inv_omega};
}
/// Does the guide creep, moving less than δ per period (|u| 2π < δ ω)?  The rounding of x(τ)
/// then grows like |u|, not like the speed bound (`rounding_rate`).
template <class L>
auto creeps(const GuideLanes<typename L::Num>& g) {
  return g.speed * L::two_pi() < g.delta * g.omega;
}
/// How fast the rounding of x(τ) grows with τ: like |u| for a creeping guide (whose phase is
/// reduced as advance() reduces it: Quiver::at), else like the speed bound.
template <class L, class Truth>
typename L::Num rounding_rate(const GuideLanes<typename L::Num>& g, const Truth& creeping) {
  return L::select(creeping, g.speed, g.speed_bound);
}

/// The drive's motion, written for a number (one axis, a lane each) or a vector (`Vec`: any
/// type with + and − and a product by a number `Num`, each component computed as a number
/// would be), from the start's x_s, v_s, sin θ_s, cos θ_s and the oscillation's amplitudes
/// F/(mω²) (`amp_x`) and F/(mω) (`amp_v`).
/// The guide's velocity u = v_s − (F/mω) sin θ_s (guiding_velocity) and its start
/// g0 = x_s + (F/mω²) cos θ_s (Quiver).
template <class Vec, class Num>
Vec guide_velocity(const Vec& v_s, const Vec& amp_v, const Num& sin_s) {
  return v_s - amp_v * sin_s;
}
template <class Vec, class Num>
Vec guide_start(const Vec& x_s, const Vec& amp_x, const Num& cos_s) {
  return x_s + amp_x * cos_s;
}
/// The position and velocity τ after the start where θ has sine and cosine sin_th, cos_th: the
/// guide less the oscillation, (g0 + u τ) − (F/mω²) cos θ, and u + (F/mω) sin θ
/// (Quiver::position and motion).
template <class Vec, class Num>
Vec quiver_position(const Vec& g0, const Vec& u, const Num& tau, const Vec& amp_x, const Num& cos_th) {
  return (g0 + u * tau) - amp_x * cos_th;
}
template <class Vec, class Num>
Vec quiver_velocity(const Vec& u, const Vec& amp_v, const Num& sin_th) {
  return u + amp_v * sin_th;
}
/// The same from the start's own position and velocity, as a hit's state is made
/// (PeriodicDriveFlight::advance): (x_s + u τ) − (F/mω²)(cos θ − cos θ_s) and
/// v_s + (F/mω)(sin θ − sin θ_s), whose differences of cosines and sines keep the start's
/// position and velocity exactly at τ = 0.
template <class Vec, class Num>
Vec advanced_position(const Vec& x_s, const Vec& u, const Num& tau, const Vec& amp_x, const Num& cos_th, const Num& cos_s) {
  return (x_s + u * tau) - amp_x * (cos_th - cos_s);
}
template <class Vec, class Num>
Vec advanced_velocity(const Vec& v_s, const Vec& amp_v, const Num& sin_th, const Num& sin_s) {
  return v_s + amp_v * (sin_th - sin_s);
}

/// A sphere (in 2-D a circle) of centre c and radius r, seen from the guide: b = q0·u, cc = |q0|²
/// and |q0|₁|u|₁ (q0 = g0 − c), the numbers of |q0 + u τ|² = cc + 2bτ + uu τ²; sign +1 when the
/// region is inside (focusing), −1 outside; the rounding level of f, tol0 + tol1 τ.
template <class Num>
struct SphereGapLanes {
  Num r, sign, slack, b, cc, spread, tol0, tol1;
};

/// A stretch [start, end] of margin m in which the wall can be hit (scan::Window), where `open`.
template <class Num, class Truth>
struct WindowLanes {
  Truth open;
  Num start, end, margin;
  Truth below;  // f(start) < 0 is known
};

/// f, f' and f'' at one time of a root search (scan::Taylor's numbers).
template <class Num>
struct TaylorLanes {
  Num f, df, d2f;
};

/// The gap's rounding: tol0 from the flight's start x0 (|x0 − c|₁ + r bounds |x0 − c| + r without
/// a square root), tol1 from the rate at which the rounding of positions grows.
template <class L, class FQ, class Num = typename L::Num>
[[gnu::always_inline]] inline SphereGapLanes<Num> sphere_gap(const GuideLanes<FQ>& q, const Num& r, const Num& sign,
                                                             const Num& slack, const Num& b, const Num& cc,
                                                             const Num& spread, const Num& start_norm1,
                                                             const Num& rounding_rate) {
  const Num eps8 = L::splat(8) * L::eps();
  return {r, sign, slack, b, cc, spread, slack + eps8 * ((start_norm1 + r) + q.delta), eps8 * rounding_rate};
}

template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num tolerance(const SphereGapLanes<Num>& g, const Num& tau) {
  return g.tol0 + g.tol1 * tau;
}
/// The level below which |f| = ||p|² − r²| is within the rounding band at τ: |p| − r ≤ tol is
/// certain when ||p|² − r²| ≤ 2 tol (r − tol).
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num band(const SphereGapLanes<Num>& g, const Num& tau) {
  const Num tol = tolerance<L>(g, tau);
  return L::splat(2) * tol * (g.r - tol);
}
/// The rounding of f itself at τ (the band without the wall's slack).
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num rounding(const SphereGapLanes<Num>& g, const Num& tau) {
  return L::splat(2) * g.r * (tolerance<L>(g, tau) - g.slack);
}
/// A bound on the third derivative of ±(|p|² − r²), 2(3 v·a + p·ȧ), in a window of margin m,
/// where |p| ≤ r + 2m + δ, |v| ≤ V, |a| ≤ A and |ȧ| ≤ Aω.
template <class L, class FQ, class Num = typename L::Num>
[[gnu::always_inline]] inline Num jerk_bound(const SphereGapLanes<Num>& g, const GuideLanes<FQ>& q, const Num& margin) {
  return L::splat(2) * q.accel_norm * (L::splat(3) * q.speed_bound + (g.r + L::splat(2) * margin + q.delta) * q.omega);
}

/// ±(|p|² − r²) and its derivatives from the dot products of p = x − c, v and a: free of square
/// roots and divisions (which lengthened each iteration of the root search by a third).
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline TaylorLanes<Num> taylor(const SphereGapLanes<Num>& g, const Num& pp, const Num& pv,
                                                      const Num& vv, const Num& pa) {
  const Num two_sign = L::splat(2) * g.sign;
  return {g.sign * (pp - g.r * g.r), two_sign * pv, two_sign * (vv + pa)};
}

/// The rounding tolerance of a gap is c0 + c1 τ: the time by which a window that ends at most
/// (d + 2 tol(τ))/speed after t0 has ended, solved for τ (the margin at that time covers the
/// whole window), or +∞ when the guide is too slow to outrun the growth of the tolerance.
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num window_horizon(const Num& t0, const Num& d, const Num& c0, const Num& c1,
                                                 const Num& speed) {
  const Num two = L::splat(2), slack = speed - two * c1;
  return L::select(slack > L::splat(0), Num(t0 + (d + two * (c0 + c1 * t0)) / slack), L::never());
}

/// The time up to which a window's margin must cover the rounding of f: the horizon, or where
/// there is none, `bound()` (a window_horizon).  (The horizon itself widens a window by the
/// rounding's growth until then, ~1e-12 of the oscillation's amplitude for a horizon of 10³
/// flights, and saves a division per wall.  Ensembles have a horizon: bound() is computed only
/// where a live lane has none.)
template <class L, class Bound, class Num = typename L::Num, class Truth = typename L::Truth>
[[gnu::always_inline]] inline Num margin_time(const Num& horizon, const Truth& live, Bound bound) {
  const Truth unbounded = horizon == L::never();
  if (L::none(L::both(live, unbounded))) return horizon;
  return L::select(unbounded, bound(), horizon);
}

/// Clips the window [start, end] to [0, horizon] (scan::clip_window).
template <class L, class Num = typename L::Num, class Truth = typename L::Truth>
[[gnu::always_inline]] inline WindowLanes<Num, Truth> clip_window(const Truth& found, const Num& start, const Num& end,
                                                                  const Num& margin, const Truth& below,
                                                                  const Num& horizon) {
  const Num zero = L::splat(0);
  return {L::both(found, L::negate(L::either(end < zero, start > horizon))), L::max(start, zero), L::min(end, horizon),
          margin, L::both(below, start > zero)};
}

/// The gap's windows until `horizon`: the guide's distance from c is convex in τ, so the guide is
/// within r ± 2m of c in one interval, or in two when it passes inside r − 2m.  For a guide that
/// moves (uu > 0): none where the guide misses the sphere, or moves away from it, even with the
/// margin at the horizon (no smaller than any margin below), as most walls do.  The margin
/// covers the rounding until the horizon, or, without one, until the guide must have left.
template <class L, class FQ, class Num = typename L::Num, class Truth = typename L::Truth>
[[gnu::always_inline]] inline void windows(const SphereGapLanes<Num>& g, const GuideLanes<FQ>& q, const Num& horizon,
                                           const Truth& live, WindowLanes<Num, Truth>& first,
                                           WindowLanes<Num, Truth>& second) {
  const Num zero = L::splat(0), two = L::splat(2), &b = g.b, &cc = g.cc, &uu = q.uu;
  const Num reach = g.r + two * (q.delta + tolerance<L>(g, horizon)), k_reach = cc - reach * reach;
  const Truth out_of_reach = L::both(k_reach > zero, L::either(b >= zero, b * b < uu * k_reach));
  const Truth near = L::both(L::both(live, uu > zero), L::negate(out_of_reach));
  first.open = second.open = near;
  if (L::none(near)) return;
  const Num m = q.delta + tolerance<L>(g, margin_time<L>(horizon, live, [&]() __attribute__((always_inline)) {
                  return window_horizon<L>(Num(L::neg(b) * q.inv_uu), Num(g.r + two * q.delta), g.tol0, g.tol1, q.speed);
                }));
  // Times at which the guide is at distance ρ from c: the roots of uu τ² + 2bτ + cc − ρ², each
  // from its stable form (one division of selected operands); false where it never is.
  auto at_distance = [&](const Num& rho, Num& t1, Num& t2) __attribute__((always_inline)) {
    const Num k = cc - rho * rho, D = b * b - uu * k;
    const Num root = L::sqrt(D);
    const Truth b_neg = b <= zero;
    const Num quotient = L::select(b_neg, k, L::neg(k)) / L::select(b_neg, Num(root - b), Num(b + root));
    t2 = L::select(b_neg, Num((root - b) * q.inv_uu), quotient);
    // (0/0 for a tangent at τ = 0.)
    t1 = L::select(b_neg, L::select(root - b > zero, quotient, zero), Num(L::neg(b + root) * q.inv_uu));
    return D >= zero;
  };
  Num t1, t2, t3, t4;
  const Truth outer = L::both(near, at_distance(g.r + two * m, t1, t2));
  const Num inner = g.r - two * m;
  const Truth two_windows = L::both(inner > zero, at_distance(inner, t3, t4));
  const Truth outside_is_below = g.sign < zero;  // (beyond a dispersing circle's wall is its inside)
  first = clip_window<L>(outer, t1, L::select(two_windows, t3, t2), m, outside_is_below, horizon);
  second = clip_window<L>(L::both(outer, two_windows), t4, t2, m, L::negate(outside_is_below), horizon);
}

/// The sign of f' = ±p̂·v in the window [start, end] of margin m: +1 when f' > 0 throughout (f
/// then crosses zero there at most once, upward), −1 when f' < 0 (no collision), 0 when the
/// bounds cannot tell.  In the window the guide q stays within 2m of the sphere, p = q + o with
/// |o| ≤ δ, and v = u + w with |w| ≤ |F|/(mω); so |p̂·v − q̂·u| ≤ |F|/(mω) + 2δ V/|p|, and
/// q̂·u = (q·u)/|q|, whose numerator grows linearly in τ, is bounded by its values at the
/// window's ends: q̂·u > wobble throughout (outward) when q·u/|q| > wobble at the start, as
/// |q| ≤ r + 2m; < −wobble (inward) likewise at the end; compared without dividing, with the
/// rounding of q·u.
template <class L, class FQ, class Num = typename L::Num>
[[gnu::always_inline]] inline Num slope_sign(const SphereGapLanes<Num>& g, const GuideLanes<FQ>& q, const Num& start,
                                             const Num& end, const Num& margin) {
  const Num zero = L::splat(0), m2 = L::splat(2) * margin, inner = g.r - m2, outer = g.r + m2;
  const auto undecided = L::either(L::negate(end - end == zero), L::negate(inner - q.delta > zero));  // (end not finite)
  const Num qs = g.b + q.uu * start, qe = g.b + q.uu * end;
  const Num wobble = q.wobble + L::splat(2) * q.delta * q.speed_bound / (inner - q.delta);
  const Num threshold = wobble * outer + L::splat(16) * L::eps() * (g.spread + q.uu * end + q.speed_bound * outer);
  const auto outward = qs > threshold, inward = qe < L::neg(threshold);
  const Num one = L::splat(1), minus = L::splat(-1);
  const Num focusing = L::select(outward, one, L::select(inward, minus, zero));
  const Num dispersing = L::select(inward, one, L::select(outward, minus, zero));
  return L::select(undecided, zero, L::select(g.sign > zero, focusing, dispersing));
}

/// Can a point within `pad` of the segment from c + a to c + b (the guide over a window, from
/// the arc's centre c) lie in the arc's span?  The span is an intersection (up to half a circle)
/// or a union of half-planes, whose linear functions take their extremes over the segment at
/// its ends; false only when certainly not.  BasicArcWall::may_meet_span.  (|·|₁ ≥ |·| bounds
/// the rounding of the cross products without a square root.)
template <class L, class FW, class WT, class Num = typename L::Num>
[[gnu::always_inline]] inline typename L::Truth may_meet_span(const ArcLanes<FW, WT>& w, const Num& slack, const Num& pad,
                                                              const Num& ax, const Num& ay, const Num& bx,
                                                              const Num& by) {
  auto cross = [](const auto& px, const auto& py, const auto& qx, const auto& qy) __attribute__((always_inline)) { return Num(px * qy - py * qx); };
  const Num margin = w.r * (slack + pad) + L::splat(16) * L::eps() * w.r * ((L::abs(ax) + L::abs(ay)) + (L::abs(bx) + L::abs(by)));
  const Num neg_margin = L::neg(margin);
  return L::choose(w.full, []() __attribute__((always_inline)) { return L::splat_truth(true); }, [&]() __attribute__((always_inline)) {
    return L::choose(w.half, [&]() __attribute__((always_inline)) {
      return L::both(L::max(cross(w.from_x, w.from_y, ax, ay), cross(w.from_x, w.from_y, bx, by)) >= neg_margin,
                     L::max(cross(ax, ay, w.to_x, w.to_y), cross(bx, by, w.to_x, w.to_y)) >= neg_margin);
    }, [&]() __attribute__((always_inline)) {
      return L::negate(L::both(L::min(cross(w.to_x, w.to_y, ax, ay), cross(w.to_x, w.to_y, bx, by)) > margin,
                               L::min(cross(ax, ay, w.from_x, w.from_y), cross(bx, by, w.from_x, w.from_y)) > margin));
    });
  });
}

/// A line (in 3-D a plane) through a with outward unit normal n, seen from the guide: f = n·(x − a)
/// lies within B of its guiding part g_off + nu τ (g_off = n·(g0 − a), nu = n·u), with
/// |n·F|/m = n_a and |n·F|/(mω) = n_w; its rounding level is tol0 + tol1 τ.
template <class Num>
struct PlaneGapLanes {
  Num slack, n_a, n_w, B, nu, g_off, tol0, tol1;
};

/// The gap's numbers from n·F/m, n·u and n·(g0 − a) (Quiver::along's bounds); tol1 from
/// |f'| ≤ |nu| + |n·F|/(mω), so that the band covers f's change over the scan's step floor.
template <class L, class FQ, class Num = typename L::Num>
[[gnu::always_inline]] inline PlaneGapLanes<Num> plane_gap(const GuideLanes<FQ>& q, const Num& n_accel, const Num& nu,
                                                           const Num& g_off, const Num& slack) {
  const Num eps8 = L::splat(8) * L::eps(), n_a = L::abs(n_accel), n_w = n_a * q.inv_omega, B = n_w * q.inv_omega;
  return {slack, n_a, n_w, B, nu, g_off, slack + eps8 * (L::abs(g_off) + B), eps8 * (L::abs(nu) + n_w)};
}

template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num tolerance(const PlaneGapLanes<Num>& g, const Num& tau) {
  return g.tol0 + g.tol1 * tau;
}
/// The level below which |f| is within the rounding band at τ.
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num band(const PlaneGapLanes<Num>& g, const Num& tau) {
  return tolerance<L>(g, tau);
}
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num rounding(const PlaneGapLanes<Num>& g, const Num& tau) {
  return tolerance<L>(g, tau) - g.slack;
}
/// A bound on |f'''| = |n·F ω sin θ|/m.
template <class L, class FQ, class Num = typename L::Num>
[[gnu::always_inline]] inline Num jerk_bound(const PlaneGapLanes<Num>& g, const GuideLanes<FQ>& q, const Num&) {
  return g.n_a * q.omega;
}

/// The gap's window until `horizon` (the guide is linear: one at most), from the guide at −2m
/// to the guide at +2m; a guide that does not move across the line (nu = 0) has one, the whole
/// flight.
template <class L, class FQ, class Num = typename L::Num, class Truth = typename L::Truth>
[[gnu::always_inline]] inline WindowLanes<Num, Truth> window(const PlaneGapLanes<Num>& g, const GuideLanes<FQ>&,
                                                             const Num& horizon, const Truth& live) {
  const Num zero = L::splat(0), two = L::splat(2);
  const Truth still = g.nu == zero, rising = g.nu > zero;
  const Num speed = L::abs(g.nu);
  const Num m = g.B + tolerance<L>(g, margin_time<L>(horizon, live, [&]() __attribute__((always_inline)) {
                  return window_horizon<L>(zero, Num(L::abs(g.g_off) + two * g.B), g.tol0, g.tol1, speed);
                }));
  const Num inv_nu = L::splat(1) / g.nu;
  const Num from = (L::neg(two * m) - g.g_off) * inv_nu, to = (two * m - g.g_off) * inv_nu;
  const Num start = L::select(still, zero, L::select(rising, from, to));
  const Num end = L::select(still, horizon, L::select(rising, to, from));
  const Num margin = L::select(still, Num(g.B + tolerance<L>(g, horizon)), m);
  return clip_window<L>(live, start, end, margin, L::both(rising, L::negate(still)), horizon);
}

/// +1 when f' = nu + n·(F/mω) sin θ > 0 throughout the flight, −1 when f' < 0, 0 when the bounds
/// cannot tell: the same in every window.
template <class L, class FQ, class Num = typename L::Num>
[[gnu::always_inline]] inline Num slope_sign(const PlaneGapLanes<Num>& g, const GuideLanes<FQ>& q) {
  const Num eps = L::eps(), wobble = g.n_w * (L::splat(1) + L::splat(16) * eps) + L::splat(8) * eps * q.speed;
  return L::select(g.nu > wobble, L::splat(1), L::select(g.nu < L::neg(wobble), L::splat(-1), L::splat(0)));
}

/// Can a point within `pad` of the segment [p, q] lie in the segment wall's span?  Its span is
/// the strip 0 ≤ (x − a)·dir ≤ 1, whose function takes its extremes at p or q (|dir| = dir_norm).
/// BasicSegmentWall::may_meet_span.
template <class L, class FW, class Num = typename L::Num>
[[gnu::always_inline]] inline typename L::Truth may_meet_span(const SegmentLanes<FW>& w, const Num& dir_norm, const Num& pad,
                                                              const Num& px, const Num& py, const Num& qx,
                                                              const Num& qy) {
  const Num sp = (px - w.ax) * w.dir_x + (py - w.ay) * w.dir_y, sq = (qx - w.ax) * w.dir_x + (qy - w.ay) * w.dir_y;
  const Num one = L::splat(1);
  const Num margin = (w.slack + pad) * dir_norm + L::splat(8) * L::eps() * (one + L::abs(sp) + L::abs(sq));
  return L::both(L::max(sp, sq) >= L::neg(margin), L::min(sp, sq) <= one + margin);
}

/// The root polished by one Newton step from the sample (τ, f, f') within the rounding band
/// |f| ≤ tol, f' > 0: from |f| ≤ tol (the walls' rounding, ~1e-13) to the rounding of f itself,
/// so that the collision time does not depend on where the search entered the band; the step
/// stays inside the band.  (scan::polished_root.)
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num polished_root(const Num& tau, const Num& f, const Num& df, const Num& tol) {
  const Num clamped = L::select(f < L::neg(tol), L::neg(tol), L::select(tol < f, tol, f));
  return L::max(L::splat(0), Num(tau - clamped / df));
}

/// Is |f(τ + h)| certainly below `level`, h a step of the root search from the sample p at τ?
/// Then the sample at τ + h, which would cost a sine and a cosine, is not needed: f(τ + h) lies
/// within J|h|³/6 of the quadratic model f + f'h + f''h²/2 (J bounds |f'''|), and after a
/// Halley step close to the root both are at the rounding of f.
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline typename L::Truth certainly_below(const TaylorLanes<Num>& p, const Num& h, const Num& jerk,
                                                                const Num& level) {
  const Num model = p.f + h * (p.df + h / L::splat(2) * p.d2f);
  const Num rounding = L::splat(8) * L::eps() * (L::abs(p.f) + L::abs(h * p.df) + L::abs(h * h * p.d2f));
  return L::abs(model) + jerk * L::abs(h * h * h) / L::splat(6) + rounding <= level;
}

/// The next iterate of the root search in the bracket [lo, hi] (f(lo) < 0; f(hi) > 0 once
/// `bracketed`, else hi is the window's end): Halley's step from the sample at τ where f' > 0
/// and it is defined, kept strictly inside the bracket, else bisection (or the end).
template <class L, class Num = typename L::Num>
[[gnu::always_inline]] inline Num halley_next(const TaylorLanes<Num>& p, const Num& tau, const Num& lo, const Num& hi,
                                              const typename L::Truth& bracketed) {
  const Num zero = L::splat(0), two = L::splat(2);
  const Num halley = two * p.df * p.df - p.f * p.d2f;
  const Num next = L::select(L::both(p.df > zero, halley > zero), Num(tau - two * p.f * p.df / halley), lo);
  return L::select(L::both(next > lo, next < hi), next, L::select(bracketed, Num(lo + (hi - lo) / two), hi));
}
