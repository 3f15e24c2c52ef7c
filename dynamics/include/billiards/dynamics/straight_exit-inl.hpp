// The exit time of a straight flight through a segment, a circular arc or an elliptic arc (its
// unit arc, through the ellipse's map), and the hit's contact, written once over a
// number type and included into a namespace: by straight_exit.hpp into billiards::dynamics
// (the scalar search in double, long double or MPFR), and by free_lanes_kernel.cpp into each
// SIMD target's namespace (one particle per lane).  A `Lanes` traits class `L` supplies the number
// type and its truth values; the algorithms see nothing else:
//   L::Num, L::Truth; L::splat(x), L::never(); L::select(m, a, b), L::select_truth(m, a, b),
//   L::splat_truth(a); l.none(m); l.choose(m, f, g): f() where m, else g() (a branch on a
//   bool; lanes of mixed truths compute both); l.both, l.either, l.negate (`choose`,
//   `select_truth` and `both` also take a bool for their first truth: a wall's, the same in
//   every lane);
//   L::sqrt, L::abs, L::max (std::max's order), L::neg; and
//   l.discriminant_positive_filtered(needed, D, bound, ray, arc): is the circle discriminant
//   D positive, where needed (bound(): D's forward error bound in double)?
// Every branch of the search is a selection or a `choose`, so that a vector computes each lane
// exactly as a double would: the same operations in the same order, each rounded once (no fused
// multiply-add).  This file includes nothing and opens no namespace; it may use nothing but its
// traits (a SIMD target's code may call no inline function shared with the rest of the program).
// (No include guard: included once into each namespace.)  The functions are inlined always:
// the scalar search's loops over walls (try_walls, grid_collision) run about 10% slower in a
// grid table when GCC calls the arc's out of line.

// The operands, split into numbers.  `F` is the number type, or a reference to it where the
// scalar search reads the numbers in place from the state and the wall.

/// The start of a straight flight: position, velocity, time, |v|².
template <class F, class Num = std::remove_cv_t<std::remove_reference_t<F>>>
struct RayLanes {
  F x, y, vx, vy, t;
  Num vv;
};

/// A circular arc wall (BasicArcWall, walls.hpp).  Its truths are bool where every lane holds
/// the same wall, so that the algorithms branch on them.
template <class F, class Truth>
struct ArcLanes {
  F cx, cy, r, r2, near, span_tol, from_x, from_y, to_x, to_y;
  Truth focusing, full, half;  // half: at most half a circle
};

/// A segment wall (BasicSegmentWall).
template <class F>
struct SegmentLanes {
  F ax, ay, nx, ny, dir_x, dir_y, slack, span_tol;
};

/// An elliptic arc's map u = L (x − c) (BasicEllipticArcWall, walls.hpp), which takes its
/// ellipse to the unit circle, and a straight flight to a straight flight.
template <class F>
struct EllipseMapLanes {
  F cx, cy, l00, l01, l10, l11;
};

/// The straight flight from s seen through the map: from L (x − c) with velocity L v (time is
/// not mapped).  Its exit through the elliptic arc is its exit through the arc's unit arc.
template <class L, class FR, class FW>
[[gnu::always_inline]] inline RayLanes<typename L::Num> mapped_ray(const RayLanes<FR>& s, const EllipseMapLanes<FW>& m) {
  using Num = typename L::Num;
  const Num dx = s.x - m.cx, dy = s.y - m.cy;
  const Num wx = m.l00 * s.vx + m.l01 * s.vy, wy = m.l10 * s.vx + m.l11 * s.vy;
  return {Num(m.l00 * dx + m.l01 * dy), Num(m.l10 * dx + m.l11 * dy), wx, wy, Num(s.t), Num(wx * wx + wy * wy)};
}

/// Is the point (px, py) on the arc's circle within its span, ends included (and extended by
/// the span tolerance)?  BasicArcWall::within_span.
template <class L, class FW, class WT>
[[gnu::always_inline]] inline typename L::Truth within_span(const L& l, const ArcLanes<FW, WT>& w,
                                                              const typename L::Num& px, const typename L::Num& py) {
  using Num = typename L::Num;
  const Num ux = px - w.cx, uy = py - w.cy, tol = w.span_tol;
  return l.choose(w.full, [&]() __attribute__((always_inline)) { return L::splat_truth(true); }, [&]() __attribute__((always_inline)) {
    return l.choose(w.half, [&]() __attribute__((always_inline)) {  // up to half a circle: within both ends' half-planes
      const Num neg_tol = L::neg(tol);
      return l.both(w.from_x * uy - w.from_y * ux >= neg_tol, ux * w.to_y - uy * w.to_x >= neg_tol);
    }, [&]() __attribute__((always_inline)) {  // more: not strictly within the complementary arc (< π)
      return l.negate(l.both(w.to_x * uy - w.to_y * ux > tol, ux * w.from_y - uy * w.from_x > tol));
    });
  });
}

/// Is the point (px, py) on the segment's line within its span, ends included (and extended by
/// the span tolerance)?  BasicSegmentWall::within_span.
template <class L, class FW>
[[gnu::always_inline]] inline typename L::Truth within_span(const L& l, const SegmentLanes<FW>& w,
                                                              const typename L::Num& px, const typename L::Num& py) {
  using Num = typename L::Num;
  const Num along = (px - w.ax) * w.dir_x + (py - w.ay) * w.dir_y;
  return l.both(along >= L::neg(w.span_tol), along <= L::splat(1) + w.span_tol);
}

/// A hit's point on the wall and the region's outward unit normal there (the walls' `contact`).
template <class Num>
struct ContactLanes {
  Num x, y, nx, ny;
};

/// Is a Newton step s (in time) along a flight onto a curve short: at most `slack` long, and at
/// most an eighth of the chord the flight's line cuts from the curve, whose time is
/// |rate|/|w|² (rate = d|u|²/ds, u and w the position and velocity in the curve's own units, a
/// circle's about its centre, v the velocity in the table's)?
/// At grazing incidence the step from a point off the curve by rounding runs along the
/// tangent, as far as the chord's other end; the point is projected across the curve there.
/// (The arcs' and the elliptic arcs' `contact`.)
template <class L>
[[gnu::always_inline]] inline typename L::Truth short_step(const L& l, const typename L::Num& s, const typename L::Num& rate,
                                                             const typename L::Num& vx, const typename L::Num& vy,
                                                             const typename L::Num& wx, const typename L::Num& wy,
                                                             const typename L::Num& slack) {
  using Num = typename L::Num;
  const Num w1 = L::abs(wx) + L::abs(wy);  // (|w|₁² ≥ |w|²: no square root)
  return l.both(L::abs(s) * (L::abs(vx) + L::abs(vy)) <= slack, L::abs(s) * w1 * w1 <= L::abs(rate) / L::splat(8));
}

/// The point of the arc's circle on the ray from its centre through (px, py), and the region's
/// outward unit normal there: one square root and one division give both.
/// BasicArcWall::radial_contact.
template <class L, class FW, class WT>
[[gnu::always_inline]] inline ContactLanes<typename L::Num> radial_contact(const ArcLanes<FW, WT>& w, const typename L::Num& px,
                                                                           const typename L::Num& py) {
  using Num = typename L::Num;
  const Num ux = px - w.cx, uy = py - w.cy;
  const Num inv = L::splat(1) / L::sqrt(ux * ux + uy * uy);
  const Num nx = ux * inv, ny = uy * inv;
  return {w.cx + w.r * nx, w.cy + w.r * ny, L::select(w.focusing, nx, L::neg(nx)), L::select(w.focusing, ny, L::neg(ny))};
}

/// Where the flight through the hit point (px, py) with velocity (vx, vy) meets the arc's
/// circle, and the outward normal there: one Newton step of |u + s v|² = r² (u = p − c) along
/// the flight where it is short, else the radial projection.  BasicArcWall::contact (which
/// says why).
template <class L, class FW, class WT>
[[gnu::always_inline]] inline ContactLanes<typename L::Num> arc_contact(const L& l, const ArcLanes<FW, WT>& w,
                                                                        const typename L::Num& slack, const typename L::Num& px,
                                                                        const typename L::Num& py, const typename L::Num& vx,
                                                                        const typename L::Num& vy) {
  using Num = typename L::Num;
  const Num ux = px - w.cx, uy = py - w.cy;
  const Num rate = L::splat(2) * (ux * vx + uy * vy), s = L::neg((ux * ux - w.r2) + uy * uy) / rate;
  return l.choose(short_step(l, s, rate, vx, vy, vx, vy, slack), [&]() __attribute__((always_inline)) {
    const Num qx = px + s * vx, qy = py + s * vy;
    const Num nx = (qx - w.cx) / w.r, ny = (qy - w.cy) / w.r;
    return ContactLanes<Num>{qx, qy, L::select(w.focusing, nx, L::neg(nx)), L::select(w.focusing, ny, L::neg(ny))};
  }, [&]() __attribute__((always_inline)) { return radial_contact<L>(w, px, py); });
}

/// The point of the segment nearest (px, py) (an end where its projection lies beyond it; the
/// normal's foot, not a + s (b − a), which would round along the wall too), and the normal.
/// A hit point computed near a corner may lie past the end by up to the span slack, beyond the
/// neighbouring wall; projected, it never does.  BasicSegmentWall::contact.
template <class L, class FW>
[[gnu::always_inline]] inline ContactLanes<typename L::Num> segment_contact(const SegmentLanes<FW>& w, const typename L::Num& bx,
                                                                            const typename L::Num& by, const typename L::Num& px,
                                                                            const typename L::Num& py) {
  using Num = typename L::Num;
  const Num along = (px - w.ax) * w.dir_x + (py - w.ay) * w.dir_y, d = w.nx * (px - w.ax) + w.ny * (py - w.ay);
  const auto before = along <= L::splat(0), after = along >= L::splat(1);
  return {L::select(before, Num(w.ax), L::select(after, bx, Num(px - w.nx * d))),
          L::select(before, Num(w.ay), L::select(after, by, Num(py - w.ny * d))), w.nx, w.ny};
}

/// The time the straight flight from s leaves the region through the arc w (before t_end),
/// else `never`.  BasicFreeFlight::exit_time (free_flight.hpp) for every number type.
template <class L, class FR, class FW, class WT>
[[gnu::always_inline]] inline typename L::Num straight_exit_time(L& l, const RayLanes<FR>& s, const ArcLanes<FW, WT>& w,
                                   const typename L::Num& t_end) {
  using Num = typename L::Num;
  const Num zero = L::splat(0), no = L::never();
  // |f + v τ|² − r² = a τ² + 2 b τ + c with f = x − centre.
  const Num fx = s.x - w.cx, fy = s.y - w.cy;
  const Num& a = s.vv;
  const Num b = fx * s.vx + fy * s.vy;
  const Num c = (fx * fx + fy * fy) - w.r2;
  // c ≈ 2 r × (distance beyond the circle): "within rounding of the circle" in c units.
  const Num neg_near = L::neg(w.near);
  const auto moving_in = b < zero, beyond = c > w.near;
  // Region inside the circle (focusing): leave through the larger root.  On the circle moving
  // out (b ≥ 0, c ≥ 0): now, if on it to rounding; else ahead.
  // Region outside the circle (dispersing): enter through the smaller root, only approaching.
  // Inside the circle by rounding only (−near ≤ c ≤ 0): reflect now.  Deeper inside, the
  // particle is in a part of the region the circle overlaps elsewhere, and only leaves the
  // circle ahead.
  const auto leaving_now = l.both(l.negate(moving_in), c >= zero);
  const auto now = [&] { return L::select(l.both(w.focusing, leaving_now), L::select(c <= w.near, s.t, no), no); };
  const auto ahead = l.select_truth(w.focusing, l.negate(leaving_now), l.both(moving_in, c >= neg_near));
  if (l.none(ahead)) return now();
  // Starting away from the circle (focusing: outside it, in a non-convex region; dispersing:
  // outside it), a miss or a graze (a touch, not a crossing) is no exit: the sign of the
  // discriminant in its perpendicular form, the accurate one there.
  const Num fxv = fx * s.vy - fy * s.vx, r2a = w.r2 * a;
  const Num D_line = r2a - fxv * fxv;  // r²|v|² − (f × v)²
  const auto needs_sign = l.select_truth(w.focusing, beyond, c > zero);
  const auto crossing = l.discriminant_positive_filtered(l.both(ahead, needs_sign), D_line, [&] {
    // D's forward error bound in double: the rounding of f, r², the products and the difference
    // (doubled from the bound measured).
    const Num spread = L::abs(fx * s.vy) + L::abs(fy * s.vx);
    return Num(L::splat(16 * std::numeric_limits<double>::epsilon()) * (r2a + spread * spread));
  }, s, w);
  const auto exits = l.both(ahead, l.either(l.negate(needs_sign), crossing));
  if (l.none(exits)) return now();
  const Num dt = l.choose(w.focusing, [&] {
    // On the circle to rounding (|c| ≤ near; just reflected off it): the chord of a particle
    // exactly on it, −2b/a, which returns to the particle's own radius (the hit point is then
    // projected onto the circle).  Solving for the circle itself from a start inside it by
    // rounding δ would lengthen the chord by δ/(v·n) and tilt the velocity toward the normal
    // at the next bounce, always the same way: a drift of the angle of incidence.  Only at
    // grazing angles below the start's own rounding (b² < a|c|) is the chord set by that
    // rounding, a|c| in either direction, so that the particle leaves its start.  Inside:
    // b² − a c with c < 0 is a sum of two non-negative terms.  Either way D ≥ b², so the far
    // root is never before the end of the chord.  (The perpendicular form cancels at grazing
    // incidence: below an angle of 1e-8 it gives half that chord or less, the point where the
    // particle moves along the tangent, and the particle would collide again at once, forever.)
    const Num D = l.choose(beyond, [&] { return L::max(zero, D_line); }, [&] {
      return L::select(c < neg_near, Num(b * b - a * c), L::max(Num(b * b), Num(a * L::abs(c))));
    });
    const Num root = L::sqrt(D);
    // (root − b)/a, or where b > 0 the same root without cancelling, −c/(b + root): one
    // division of selected operands.
    const auto small_b = b <= zero;
    return Num(L::select(small_b, Num(root - b), L::neg(c)) / L::select(small_b, a, Num(b + root)));
  }, [&] {
    return l.choose(c <= zero, [&] { return zero; }, [&] { return Num(c / (L::sqrt(L::max(zero, D_line)) - b)); });
  });
  const Num t = s.t + dt;
  const auto hit = l.both(exits, l.both(l.negate(t > t_end), within_span(l, w, s.x + s.vx * dt, s.y + s.vy * dt)));
  return l.choose(hit, [&] { return t; }, now);
}

/// The time the straight flight from s leaves through the segment w (before t_end), else
/// `never`: moving outward across the line, within the span where it crosses.  Beyond the line
/// by rounding only (a particle just reflected at a joint): now.  Far beyond it: the particle
/// is elsewhere in a non-convex region, moving away.
template <class L, class FR, class FW>
[[gnu::always_inline]] inline typename L::Num straight_exit_time(L& l, const RayLanes<FR>& s, const SegmentLanes<FW>& w, const typename L::Num& t_end) {
  using Num = typename L::Num;
  const Num zero = L::splat(0), no = L::never();
  const Num rate = w.nx * s.vx + w.ny * s.vy;  // d/dt of the distance beyond the wall's line
  const auto outward = rate > zero;
  if (l.none(outward)) return no;
  const Num beyond = w.nx * (s.x - w.ax) + w.ny * (s.y - w.ay);
  const auto exits = l.both(outward, l.negate(beyond > w.slack));
  if (l.none(exits)) return no;
  const Num dt = l.choose(beyond >= zero, [&] { return zero; }, [&] { return Num(L::neg(beyond) / rate); });
  const Num t = s.t + dt;
  const auto in_time = l.both(exits, l.negate(t > t_end));
  if (l.none(in_time)) return no;
  return L::select(l.both(in_time, within_span(l, w, s.x + s.vx * dt, s.y + s.vy * dt)), t, no);
}

