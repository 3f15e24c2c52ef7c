// The outward crossings of a magnetic flight (a cyclotron circle, magnetic_flight.hpp) through
// segments and circular arcs, written once over a number type as straight_exit-inl.hpp's exit
// times are, with the same `Lanes` traits and wall views (it is included after that file): by
// magnetic_exit.hpp into billiards::dynamics (the scalar search in double, long double or
// MPFR), and by magnetic_lanes_kernel.cpp into each SIMD target's namespace (one flight per
// lane).  Every branch is a selection or a `choose`, each operation rounded once, so a lane
// computes what one number does, bit for bit.
//
// Along the orbit a wall's gap is F0 + B1 sin φ + B2 (1 − cos φ) in the angle turned φ, a
// quadratic form in (cos φ/2, sin φ/2): its outward zero, one per turn, is found in closed form
// as a half-angle direction u ∝ (cos ψ, sin ψ), ψ = φ/2 ∈ [0, π) (u = 0: none).  Crossings are
// compared as half angles (a cross product), so that only the earliest needs an arctangent,
// for its time (half_angle_of; a reference type's own, L::atan2 where L::reference); the state
// there needs no sine or cosine.  (No include guard: included once into each namespace.)

/// A cyclotron circle from a state (Gyration's numbers): the start x, v (v⊥ in 2-D), v turned a
/// quarter turn towards the centre w0, |Ω| and 1/|Ω|, |v|, the centre, r_c, and the rounding of
/// points on the circle.
template <class F>
struct GyrationLanes {
  F x, y, vx, vy, w0x, w0y, k, inv_k, speed, cx, cy, radius, rounding;
};

/// The cyclotron circle from the state (x, y, vx, vy) in the field Ω: k = |Ω|, inv_k = 1/k,
/// `clockwise` where Ω > 0, and `unit` 16 ε of the number type (the rounding of points on the
/// circle is unit × (|centre|∞ + r_c)).  (Gyration's constructor in 2-D.)
template <class L>
[[gnu::always_inline]] inline GyrationLanes<typename L::Num> gyration_of(
    const L&, const typename L::Num& x, const typename L::Num& y, const typename L::Num& vx,
    const typename L::Num& vy, const typename L::Num& k, const typename L::Num& inv_k, bool clockwise,
    const typename L::Num& unit) {
  using Num = typename L::Num;
  const Num w0x = clockwise ? vy : L::neg(vy), w0y = clockwise ? L::neg(vx) : vx;
  const Num speed = L::sqrt(Num(vx * vx + vy * vy));
  const Num cx = x + w0x * inv_k, cy = y + w0y * inv_k, radius = speed * inv_k;
  const Num rounding = unit * (L::max(L::abs(cx), L::abs(cy)) + radius);
  return {x, y, vx, vy, w0x, w0y, k, inv_k, speed, cx, cy, radius, rounding};
}

/// What the magnetic search reads of a wall beside its straight-flight view: the disk holding
/// it (centre, radius, and the rounding 16 ε × radius of a distance to it), and its slack.
template <class F>
struct ReachLanes {
  F cx, cy, r, pad, slack;
};

/// A half angle u ∝ (cos ψ, sin ψ), ψ ∈ [0, π); u = 0: none.
template <class Num>
struct HalfAngle {
  Num x, y;
};

/// A position and a velocity.
template <class Num>
struct PhasePoint {
  Num x, y, vx, vy;
};

/// The earliest crossing so far: its half angle, and whether some wall has given one.
template <class Num, class Truth>
struct EarliestCrossing {
  HalfAngle<Num> u;
  Truth found;
};

/// Can the orbit meet the wall's bounding disk?  Not when the disk lies wholly outside the
/// cyclotron circle or wholly inside it.  (Gyration::may_reach.)
template <class L, class FG, class FR>
[[gnu::always_inline]] inline typename L::Truth gyration_reaches(const L& l, const GyrationLanes<FG>& g,
                                                                   const ReachLanes<FR>& w) {
  using Num = typename L::Num;
  const Num margin = g.rounding + w.pad;
  const Num reach = g.radius + w.r + margin, inner = g.radius - w.r - margin;
  const Num dx = g.cx - w.cx, dy = g.cy - w.cy;
  const Num d2 = dx * dx + dy * dy;
  return l.negate(l.either(d2 > reach * reach, l.both(inner > L::splat(0), d2 < inner * inner)));
}

/// The first outward zero of F0 + B1 sin φ + B2 (1 − cos φ) over one turn, as a half angle.
/// `near` is the rounding of F0: within it beyond the wall (0 ≤ F0 ≤ near) and moving out, the
/// crossing is now (u = (1, 0)), as for every flight (flight.hpp).  A touch (a double root) is
/// no crossing.  D = B1² − F0 (F0 + 2 B2), the discriminant, comes from the caller in its
/// accurate form.
template <class L>
[[gnu::always_inline]] inline HalfAngle<typename L::Num> outward_half_angle(
    const L& l, const typename L::Num& F0, const typename L::Num& B1, const typename L::Num& B2,
    const typename L::Num& D, const typename L::Num& near) {
  using Num = typename L::Num;
  const Num zero = L::splat(0);
  // Beyond the wall by rounding and moving out (or along it and curving out): now.
  const auto now = l.both(l.both(F0 >= zero, F0 <= near), l.either(B1 > zero, l.both(B1 == zero, B2 > zero)));
  const Num now_x = L::select(now, L::splat(1), zero);
  const auto crosses = l.both(l.negate(now), D > zero);  // else a miss or a touch
  if (l.none(crosses)) return {now_x, zero};
  // With c = cos ψ, s = sin ψ: F = F0 c² + 2 B1 s c + (F0 + 2 B2) s², zero where
  // tan ψ = (−B1 ± √D)/(F0 + 2 B2); F increases through the "+" root (its derivative in tan ψ
  // is 2√D there).  That root as a direction, in whichever of its two forms does not cancel:
  // from a wall just bounced off (F0 ≈ 0, B1 < 0) it is the far end of the chord, not the
  // start point.
  const Num root = L::sqrt(D);
  const auto small_b = B1 <= zero;
  const Num x = L::select(small_b, Num(F0 + L::splat(2) * B2), Num(L::neg(B1) - root));
  const Num y = L::select(small_b, Num(root - B1), F0);
  const auto turn = l.either(y < zero, l.both(y == zero, x < zero));  // ψ ∈ [0, π): one turn from now
  return {L::select(crosses, L::select(turn, L::neg(x), x), now_x), L::select(crosses, L::select(turn, L::neg(y), y), zero)};
}

/// The outward half angle through a line, or a plane parallel to the field, at the signed
/// distance `dist` beyond it, with B1 = n·v⊥ and B2 = n·w0 (n its normal): the gap is k × the
/// distance, F0 = k dist.
template <class L>
[[gnu::always_inline]] inline HalfAngle<typename L::Num> line_half_angle(
    const L& l, const typename L::Num& k, const typename L::Num& dist, const typename L::Num& B1,
    const typename L::Num& B2, const typename L::Num& speed, const typename L::Num& slack) {
  using Num = typename L::Num;
  const Num F0 = k * dist, near = k * slack;
  // D = B1² − F0 (F0 + 2 B2): as it stands on the wall; elsewhere as |v⊥|² − (k × distance of
  // the centre beyond the line)², a product free of cancellation at a graze.
  const Num disc = l.choose(L::abs(F0) <= near, [&] { return Num(B1 * B1 - F0 * (F0 + L::splat(2) * B2)); }, [&] {
    const Num mean = F0 + B2;
    return Num((speed - mean) * (speed + mean));
  });
  return outward_half_angle(l, F0, B1, B2, disc, near);
}

/// The outward crossing of the segment's line in the coming turn, whether or not within its
/// span (u = 0: none, or the orbit cannot reach the segment at all).
template <class L, class FG, class FW, class FR>
[[gnu::always_inline]] inline HalfAngle<typename L::Num> outward_crossing(const L& l, const GyrationLanes<FG>& g,
                                                                           const SegmentLanes<FW>& w,
                                                                           const ReachLanes<FR>& reach) {
  using Num = typename L::Num;
  const Num zero = L::splat(0);
  const auto reaches = gyration_reaches(l, g, reach);
  if (l.none(reaches)) return {zero, zero};
  // F = k × (distance beyond the line): F0 now, B1 = n·v0, B2 = n·w0; B1² + B2² = |v0|².
  const Num dist = w.nx * (g.x - w.ax) + w.ny * (g.y - w.ay);
  const Num B1 = w.nx * g.vx + w.ny * g.vy, B2 = w.nx * g.w0x + w.ny * g.w0y;
  const HalfAngle<Num> u = line_half_angle(l, Num(g.k), dist, B1, B2, Num(g.speed), Num(w.slack));
  return {L::select(reaches, u.x, zero), L::select(reaches, u.y, zero)};
}

/// The same through the arc's circle.
template <class L, class FG, class FW, class WT, class FR>
[[gnu::always_inline]] inline HalfAngle<typename L::Num> outward_crossing(const L& l, const GyrationLanes<FG>& g,
                                                                           const ArcLanes<FW, WT>& w,
                                                                           const ReachLanes<FR>& reach) {
  using Num = typename L::Num;
  const Num zero = L::splat(0);
  const auto reaches = gyration_reaches(l, g, reach);
  if (l.none(reaches)) return {zero, zero};
  // F = ±(k/2)(|x − c|² − r²), + for a focusing arc: beyond the wall is outside its circle.
  const Num sign = L::splat(w.focusing ? 1 : -1);
  const Num px = g.x - w.cx, py = g.y - w.cy;
  const Num F0 = sign * g.k / L::splat(2) * ((px * px + py * py) - w.r2);
  const Num B1 = sign * (px * g.vx + py * g.vy), B2 = sign * ((px * g.w0x + py * g.w0y) + g.speed * g.radius);
  const Num near = g.k * w.r * reach.slack;
  const Num disc = l.choose(L::abs(F0) <= near, [&] { return Num(B1 * B1 - F0 * (F0 + L::splat(2) * B2)); }, [&] {
    // (k/2)² ((r + ρ)² − d²)(d² − (r − ρ)²), d the distance between the centres: each factor
    // a sum of three lengths, zero at a graze.
    const Num dx = g.cx - w.cx, dy = g.cy - w.cy;
    const Num d = L::sqrt(Num(dx * dx + dy * dy));
    const Num& r = w.r;
    const Num& rho = g.radius;
    return Num(g.k * g.k / L::splat(4) * ((r - d + rho) * (r + d - rho)) * ((d + rho - r) * (d + rho + r)));
  });
  const HalfAngle<Num> u = outward_half_angle(l, F0, B1, B2, disc, near);
  return {L::select(reaches, u.x, zero), L::select(reaches, u.y, zero)};
}

/// Is the half angle u earlier than that of `best` (both ≠ 0, in [0, π))?
template <class L>
[[gnu::always_inline]] inline typename L::Truth earlier(const HalfAngle<typename L::Num>& u,
                                                       const HalfAngle<typename L::Num>& best) {
  return u.x * best.y - u.y * best.x > L::splat(0);
}

/// The position after turning by φ = 2ψ, from (cos ψ, sin ψ) ∝ u (no sine or cosine):
/// x0 + (2/k) (sin ψ cos ψ v0 + sin²ψ w0), with sin ψ cos ψ = u_x u_y/|u|².
template <class L, class FG>
[[gnu::always_inline]] inline HalfAngle<typename L::Num> position_at_half_angle(const GyrationLanes<FG>& g,
                                                                                 const HalfAngle<typename L::Num>& u) {
  using Num = typename L::Num;
  const Num scale = L::splat(2) * g.inv_k / (u.x * u.x + u.y * u.y);
  const Num sc = u.x * u.y, ss = u.y * u.y;
  return {Num(g.x + scale * (sc * g.vx + ss * g.w0x)), Num(g.y + scale * (sc * g.vy + ss * g.w0y))};
}

/// Makes the wall's outward crossing the earliest where it is earlier than the earliest so far
/// (the first of equal ones kept) and within the wall's span; returns where it did.
template <class L, class FG, class Wall, class FR>
[[gnu::always_inline]] inline typename L::Truth keep_earlier_crossing(
    L& l, const GyrationLanes<FG>& g, const Wall& w, const ReachLanes<FR>& reach,
    EarliestCrossing<typename L::Num, typename L::Truth>& best) {
  using Num = typename L::Num;
  const Num zero = L::splat(0);
  const HalfAngle<Num> u = outward_crossing(l, g, w, reach);
  const auto candidate = l.both(l.negate(l.both(u.x == zero, u.y == zero)),
                                l.either(l.negate(best.found), earlier<L>(u, best.u)));
  if (l.none(candidate)) return candidate;
  const HalfAngle<Num> p = position_at_half_angle<L>(g, u);
  const auto kept = l.both(candidate, within_span(l, w, p.x, p.y));
  best.u = {L::select(kept, u.x, best.u.x), L::select(kept, u.y, best.u.y)};
  best.found = l.either(best.found, kept);
  return kept;
}

/// The half angle ψ ∈ [0, π] of u = (x, y), y ≥ 0, u ≠ 0: atan2(y, x), in double to 2 ulps
/// (test_magnetic_flight: against long double).  Written here, over the traits, so that one
/// number and every SIMD target's lanes give the same bits: the C library's atan2 is not a
/// vector function, and it rounds differently on processors with and without fused
/// multiply-adds.  (SLEEF's non-FMA functions agree across targets too, but its 1-ulp arctangent
/// costs 3× the C library's in one number and its 3.5-ulp one is less accurate.)  Cephes'
/// arctangent: the argument reduced to |z| ≤ tan(π/8) about 0, π/4 or π/2 by one division of
/// the components (no rounded quotient y/x in between), and a rational function of degree 4/5
/// in z².
template <class L>
[[gnu::always_inline]] inline typename L::Num half_angle_of(const L&, const HalfAngle<typename L::Num>& u) {
  using Num = typename L::Num;
  const Num zero = L::splat(0), ax = L::abs(u.x), y = u.y;
  // atan(y/ax) = base + atan(z): z = y/ax (base 0), (y − ax)/(y + ax) (π/4), −ax/y (π/2).
  const auto steep = y > L::splat(2.41421356237309504880) * ax, flat = y <= L::splat(0.66) * ax;
  const Num z = L::select(steep, L::neg(ax), L::select(flat, y, Num(y - ax))) /
                L::select(steep, y, L::select(flat, ax, Num(y + ax)));
  const Num base = L::select(steep, L::splat(1.57079632679489661923), L::select(flat, zero, L::splat(7.85398163397448309616e-1)));
  const Num tail = L::select(steep, L::splat(6.123233995736765886130e-17), L::select(flat, zero, L::splat(3.061616997868382943065e-17)));
  const Num w = z * z;
  const Num p = (((L::splat(-8.750608600031904122785e-1) * w + L::splat(-1.615753718733365076637e1)) * w +
                  L::splat(-7.500855792314704667340e1)) * w + L::splat(-1.228866684490136173410e2)) * w +
                L::splat(-6.485021904942025371773e1);
  const Num q = ((((w + L::splat(2.485846490142306297962e1)) * w + L::splat(1.650270098316988542046e2)) * w +
                  L::splat(4.328810604912902668951e2)) * w + L::splat(4.853903996359136964868e2)) * w +
                L::splat(1.945506571482613964425e2);
  const Num a = base + (z * (w * p / q) + z + tail);
  // x < 0: π − atan(y/|x|), π = pi_hi + pi_lo.
  return L::select(u.x < zero, Num(L::splat(3.14159265358979311600e0) - a + L::splat(1.22464679914735317723e-16)), a);
}

/// The time t0 + 2ψ/k at which the orbit from time t0 has turned by twice the half angle of u
/// (u ≠ 0).  (A reference type takes ψ from its own arctangent, at its precision.)
template <class L, class FG>
[[gnu::always_inline]] inline typename L::Num crossing_time(const L& l, const GyrationLanes<FG>& g,
                                                           const HalfAngle<typename L::Num>& u,
                                                           const typename L::Num& t0) {
  if constexpr (L::reference) return t0 + L::splat(2) * l.atan2(u.y, u.x) / g.k;
  else return t0 + L::splat(2) * half_angle_of(l, u) / g.k;
}

/// Position and velocity after turning by φ = 2ψ, from sin ψ and cos ψ: sin φ = 2 sin ψ cos ψ,
/// 1 − cos φ = 2 sin²ψ (accurate at small φ).
template <class L, class FG>
[[gnu::always_inline]] inline PhasePoint<typename L::Num> turned_by(const GyrationLanes<FG>& g,
                                                                      const typename L::Num& sn,
                                                                      const typename L::Num& cs) {
  using Num = typename L::Num;
  const Num sin_phi = L::splat(2) * sn * cs, one_minus_cos = L::splat(2) * sn * sn, cos_phi = (cs - sn) * (cs + sn);
  const Num a = sin_phi * g.inv_k, b = one_minus_cos * g.inv_k;
  return {Num(g.x + a * g.vx + b * g.w0x), Num(g.y + a * g.vy + b * g.w0y), Num(cos_phi * g.vx + sin_phi * g.w0x),
          Num(cos_phi * g.vy + sin_phi * g.w0y)};
}

/// The same after turning by twice the half angle of u (u ≠ 0): no sine or cosine.
template <class L, class FG>
[[gnu::always_inline]] inline PhasePoint<typename L::Num> turned_by(const GyrationLanes<FG>& g,
                                                                      const HalfAngle<typename L::Num>& u) {
  using Num = typename L::Num;
  const Num norm = L::sqrt(Num(u.x * u.x + u.y * u.y));
  return turned_by<L>(g, Num(u.y / norm), Num(u.x / norm));
}
