// The certified root scan behind the forced flights, in 2-D and 3-D (internal to dynamics):
// root isolation only.  The flights supply f (the drive's guiding line and its bounds:
// `Quiver`, forced_flight.hpp) and the walls supply its geometry (the gaps `PlaneGap`,
// `SphereGap`, walls.hpp).
//
// For one wall, f(τ) measures how far beyond the wall the particle is τ after the flight's
// start.  The scan steps from sample to sample by the earliest time at which f could vanish
// given a bound M on |f''| (the positive root of |f| − σ f' s − M s²/2, σ = sign f), so it
// never steps over a root; near a simple root it converges like Newton's iteration from the
// safe side.  Before each sample, the guiding line of the flight may show that no collision
// can occur sooner (`earliest`): then the scan moves on without evaluating f at all, which
// costs a sine and a cosine.
#pragma once

#include "billiards/dynamics/state.hpp"
#include "billiards/dynamics/straight_exit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace billiards::dynamics::scan {

template <class Real>
inline const Real eps = std::numeric_limits<Real>::epsilon();

/// f and f' at one time of the scan, with what bounds f'' until the next sample.
template <class Real, class V = VecN<Real, 2>>
struct Sample {
  Real f, df;  // how far beyond the wall, and its rate
  Real M;      // bound on |f''| over the next `cap` time units
  Real cap;    // longest step for which M holds
  V x;         // position
};

#include "billiards/dynamics/driven_exit-inl.hpp"

/// The collision time returned for a sample p at τ within the rounding band (|f| ≤ tol, f' > 0):
/// driven_exit-inl.hpp's polished_root.
template <class Real, class S>
Real polished_root(const Real& tau, const S& p, const Real& tol) {
  return polished_root<ScalarLanes<Real>>(tau, p.f, p.df, tol);
}

/// First τ in [0, tau_end] at which f crosses zero upward at a point in the wall's span.
/// `sample(τ)` evaluates f; `earliest(τ)` returns a time ≥ τ before which no collision can
/// occur (from the guiding line and the bounded oscillation; τ itself when it cannot tell), or
/// +∞; `tolerance(τ)` is the rounding level of f at τ.  When no crossing is found, `*resume`
/// (if given) receives the first τ beyond tau_end at which the scan would sample next: a caller
/// that extends f piece by piece (an integrated flight, step by step) continues from there.
/// Inlined into each caller so that its lambdas fold into one loop (measured with callgrind:
/// 12% fewer instructions than a call).
template <bool local_band = false, class Real, class SampleFn, class EarliestFn, class SpanFn, class TolFn>
[[gnu::always_inline]] inline Real first_outward_crossing(SampleFn sample, EarliestFn earliest, SpanFn in_span,
                                                          TolFn tolerance, const Real& tau_end,
                                                          Real* resume = nullptr) {
  using std::abs;
  using std::max;
  using std::min;
  using std::sqrt;
  constexpr int max_steps = 1000000;
  Real tau = 0;
  for (int step = 0; step < max_steps; ++step) {
    if (tau <= tau_end && tau != never) tau = earliest(tau);
    if (tau > tau_end || tau == never) {  // (τ = ∞: no window ahead, with no horizon)
      if (resume) *resume = tau;
      return never;
    }
    const auto p = sample(tau);
    // τ advances by at least `floor`, over which f changes by up to |f'| floor: the band must
    // be that wide, or a root could fall between two samples that both miss it (found in MPFR,
    // where a creeping flight's rounding band was narrower than that after 1.8e9 s).  Callers'
    // tolerances include it through a bound on |f'|, except where that bound is too wide
    // (`local_band`: creeping flights, where it made touches count periods early).
    const Real floor = 4 * eps<Real> * max(tau, Real(1e-300));
    Real tol = tolerance(tau);
    if constexpr (local_band) tol = max(tol, Real(floor * abs(p.df)));
    Real s;
    if (abs(p.f) <= tol) {
      // At the wall to rounding: an outward crossing in the span is the collision.
      if (p.df > 0 && in_span(p.x)) return polished_root(tau, p, tol);
      // Otherwise no collision here.  Leaving the wall (f' < 0, as from the wall just bounced
      // off), f decreases until f' ≥ 0 and stays below f + tol + f' s + M s²/2, whose larger
      // root is the earliest return to zero.  A touch or a crossing outside the span is passed
      // by the time f needs to change by tol (a skipped crossing would be no deeper than
      // rounding: a graze).
      const Real hi = p.f + tol, disc = p.df * p.df - 2 * p.M * hi;
      s = p.df < 0 && disc > 0 ? min(Real((sqrt(disc) - p.df) / p.M), p.cap)
                               : Real(2 * tol / (abs(p.df) + sqrt(2 * p.M * tol)));
    } else {
      // Earliest zero allowed by |f''| ≤ M: the positive root of |f| − σ f' s − M s²/2.
      // Each form is free of cancellation on its side: moving away from the wall (slope < 0)
      // the first would divide by a difference of nearly equal numbers and could step past
      // the root (a ball thrown off a floor and pulled back by the force).  (Found and fixed
      // by the hard-cases suite.)
      const Real a = abs(p.f), slope = p.f < 0 ? p.df : Real(-p.df);
      const Real root = sqrt(slope * slope + 2 * p.M * a);
      const Real quadratic = p.M > 0 ? (slope >= 0 ? Real(2 * a / (slope + root)) : Real((root - slope) / p.M))
                                     : (slope > 0 ? Real(a / slope) : Real(never));
      s = min(quadratic, p.cap);
    }
    // Keep a floor so that τ advances in floating point; it is far below any physical time.
    tau += max(s, floor);
  }
  throw std::runtime_error("certified root isolation did not converge in a million steps");
}

/// The rounding band of a scanned gap: the wall's slack, and the rounding of positions of size
/// `scale` reached at speed V after τ, in units of the gap (× `stretch` for a gap measured in
/// units other than the table's).
template <class Real>
Real rounding_band(const Real& slack, const Real& scale, const Real& V, const Real& tau, const Real& stretch = 1) {
  return slack + 16 * eps<Real> * (scale + V * tau) * stretch;
}

/// The first outward crossing of wall w, within its span, by a motion known only through
/// `at(τ)` → (x, v), τ after its start, with acceleration at most A and within `reach(τ)` of
/// its start at τ: the certified scan of the wall's gap (the wall's `gap_sample`), its
/// rounding band the wall's slack (which holds the rounding of the wall's own coordinates)
/// and that of positions of size `scale` + reach(τ).  What a flight falls back on for a wall
/// kind it has no closed form for.
template <class Real, class Wall, class At, class Reach>
Real gap_crossing(const Wall& w, At at, const Real& A, Reach reach, const Real& scale, const Real& tau_end) {
  auto sample = [&](const Real& tau) {
    const auto [x, v] = at(tau);
    return w.gap_sample(x, v, A);
  };
  auto earliest = [](const Real& tau) { return tau; };
  auto in_span = [&w](const auto& x) { return w.within_span(x); };
  auto tolerance = [&](const Real& tau) { return Real(w.slack + 16 * eps<Real> * (scale + reach(tau))); };
  return first_outward_crossing(sample, earliest, in_span, tolerance, tau_end);
}

/// The `earliest` of a driven flight: f lies within the oscillation amplitude (and rounding)
/// of its guiding part, so no collision can occur before the guide comes that close to the
/// wall — `window_start(τ)`, τ itself when it is that close — nor in a window, up to the time
/// `window_end(start)` at which the guide is twice that far, that `passes(start, end)`
/// declares out of the wall's span.  Such windows are passed one after another without
/// evaluating f.  Returns τ, a later time, or +∞ (nothing before tau_end).  `sampled_until`
/// keeps the end of the last window that could not be passed: while the scan samples its way
/// through that window, it is not decided again (sampling is always safe).
template <class Real, class StartFn, class EndFn, class Passes>
[[gnu::always_inline]] inline Real first_window(Real tau, const Real& tau_end, StartFn window_start, EndFn window_end,
                                                Passes passes, Real& sampled_until) {
  for (;;) {
    const Real start = window_start(tau);
    if (start == never || start > tau_end) return never;
    if (start < sampled_until) return start;
    const Real end = window_end(start);
    // (A window without end, of a guide standing still, is not passed: guide(∞) = g0 + 0·∞.)
    if (!(end > start) || end == never || !passes(start, end)) {
      sampled_until = end;
      return start;
    }
    if (end >= tau_end) return never;
    tau = end;
  }
}

/// The `earliest` of a driven flight whose guide creeps (moves less than δ per period, as for a
/// particle nearly at rest at a drive phase near 0): from τ, the first time ≥ τ at which the
/// oscillation segment may come within rounding of the wall.  The particle stays on that
/// segment, which moves rigidly at |u|; so while `clearance(τ)`, a lower bound on its distance
/// from the wall within the span, exceeds the rounding band, no collision can occur before
/// τ + clearance/|u|, and the scan jumps there (to the next window) instead of sampling every
/// period — 10⁸ of them for the clover scaled by 1e-6 from a speed of 1e-15.  A guide that
/// stands still (u = 0) gives a periodic f: a period scanned without a collision, or a segment
/// clear of the wall, means no collision ever.  Jumps shorter than a period stop: sampling it
/// costs no more.
template <class Q, class Real, class Clearance, class TolFn>
[[gnu::noinline]] Real creep(const Q& q, const Real& tau, const Real& tau_end, Clearance clearance, TolFn tolerance) {
  if (tau == never || tau > tau_end) return never;
  if (q.speed == 0 && tau >= q.period()) return never;
  const Real gap = clearance(tau) - 2 * tolerance(tau);
  if (!(gap > 0)) return tau;
  if (q.speed == 0) return never;
  return gap < q.speed * q.period() ? tau : Real(tau + gap / q.speed);
}


/// Scans of flights that do not creep take this instead of a clearance: their loop has no call
/// to `creep`, which, even never taken, kept the scan's state out of registers (+25%
/// instructions per collision at 320π).  `with_creep` picks one or the other.
struct NotCreeping {};

template <class Scan, class Clearance>
[[gnu::noinline]] auto creeping_scan(Scan scan, Clearance clearance) {
  return scan(clearance);
}

/// scan(clearance) for a creeping flight, in a call of its own; scan(NotCreeping{}) otherwise.
template <class Q, class Scan, class Clearance>
[[gnu::always_inline]] inline auto with_creep(const Q& q, Scan scan, Clearance clearance) {
  return q.creeping ? creeping_scan(scan, clearance) : scan(NotCreeping{});
}


/// Time, from τ0, at which the linear function ℓ(τ) = l0 + l1 (τ − τ0) first reaches level L
/// from below (ℓ(τ0) < L), or +∞.
template <class Real>
Real reach_linear(const Real& tau0, const Real& l0, const Real& l1, const Real& level) {
  if (l0 >= level) return tau0;
  return l1 > 0 ? Real(tau0 + (level - l0) / l1) : Real(never);
}

/// First τ ≥ τ0 at which |q0 + u (τ − τ0)|² crosses ρ², going outward (from inside) when
/// `outward`, inward otherwise; τ0 itself when already on that side, +∞ when never.
template <class Real, class V>
[[gnu::always_inline]] inline Real reach_radius(const Real& tau0, const V& q0, const V& u, const Real& rho, bool outward) {
  using std::sqrt;
  const Real a = u.squaredNorm(), b = q0.dot(u), c = q0.squaredNorm() - rho * rho;
  if (outward ? c >= 0 : c <= 0) return tau0;
  if (a == 0) return never;
  const Real D = b * b - a * c;
  if (D < 0) return never;  // the guiding line misses the circle of radius ρ
  if (!outward && b >= 0) return never;  // moving away
  const Real root = sqrt(D);
  if (outward) return tau0 + (b <= 0 ? Real((root - b) / a) : Real(-c / (b + root)));  // larger root
  return tau0 + c / (root - b);                                                        // smaller root
}


/// A function with the same sign and roots as f (and the same sign of slope), its first two
/// derivatives at one time, the position there, `tol`, the level below which |f| ≤ the
/// rounding tolerance of f is certain, and the flight's `Mark` there (for a driven flight the
/// drive's phase, PhaseSample: the state at a nearby time follows without another sample).
template <class Real, class V, class Mark>
struct Taylor {
  Real f, df, d2f;
  V x;
  Real tol;
  Mark mark;
};

/// A stretch [start, end] of a driven flight in which its guide is within two margins (the
/// oscillation's amplitude and rounding) of a wall's supporting line or sphere: the only times
/// at which the wall can be hit.  `below`: the guide entered it from f's negative side, so
/// f(start) < 0.  (No default values: arrays of windows are filled as they are found.)
template <class Real>
struct Window {
  Real start, end, margin;
  int wall;
  bool below;
};

/// Clips the window [start, end] to [0, horizon] (driven_exit-inl.hpp's clip_window) into
/// out[n]; returns the new count.
template <class Real>
int append_window(int n, Window<Real>* out, const Real& start, const Real& end, const Real& margin, bool below,
                  const Real& horizon) {
  return append_window(n, out, clip_window<ScalarLanes<Real>>(true, start, end, margin, below, horizon));
}
/// The window w into out[n] if it is open; returns the new count.
template <class Real>
int append_window(int n, Window<Real>* out, const WindowLanes<Real, bool>& w) {
  if (!w.open) return n;
  out[n] = {w.start, w.end, w.margin, -1, w.below};
  return n + 1;
}

/// A root search that could not decide (see `monotone_crossing`).
inline constexpr double undecided = -1;

/// The collision in a window w where f' > 0 throughout (slope_sign = +1): f crosses zero there
/// at most once, so Halley's iteration kept inside a bracket finds it without any risk of
/// passing an earlier root (cubic convergence: ~2 samples where the certified scan, whose steps
/// converge like Newton's, takes ~4).  A step that lands where f is certainly at its own
/// rounding (`certainly_below`: as close to the root as a polished sample) is the root without
/// a sample there; the flight's state there comes from the last sample's mark (`shifted_to`:
/// for the drive, PhaseSample::shifted).
/// `w.below`: f(start) < 0 is known (the guide entered the window from f's negative side) and
/// start need not be sampled.  Returns the root, +∞ when f does not cross zero in the window or
/// crosses outside the wall's span, or `undecided` when the iteration stalls; `*mark` keeps
/// the flight's mark at the root.
template <class Gap, class InSpan, class Real, class Mark>
Real monotone_crossing(const Gap& g, InSpan in_span, const Window<Real>& w, Mark& mark) {
  using std::abs;
  using L = ScalarLanes<Real>;
  const Real start = w.start, end = w.end;
  Real lo = start, hi = end;  // f(lo) < 0; f(hi) > 0 once `bracketed`
  bool bracketed = false;
  const Real jerk = g.jerk_bound(w);
  // The window runs from the guide at −2m to the guide at +2m: it crosses about half way.
  Real tau = w.below ? Real(start + (end - start) / 2) : start;
  for (int k = 0; k < 100; ++k) {
    const auto p = g.taylor(tau);
    const Real tol = p.tol;
    if (abs(p.f) <= tol) {
      if (!(p.df > 0)) return undecided;  // (f' > 0 was certified: only rounding could do this)
      if (!in_span(p.x)) return never;
      mark = p.mark;
      return polished_root(tau, p, tol);
    }
    if (p.f < 0) {
      if (tau >= end) return never;  // still below at the end of the window
      lo = tau;
    } else {
      if (tau == start) return never;  // above from the start, and rising
      hi = tau;
      bracketed = true;
    }
    const TaylorLanes<Real> t{p.f, p.df, p.d2f};
    const Real next = halley_next<L>(t, tau, lo, hi, bracketed);
    if (next == tau) return undecided;
    if (certainly_below<L>(t, Real(next - tau), jerk, g.rounding(next))) {
      decltype(p.x) x;
      Mark at;
      if (g.q.shifted_to(p.mark, next, x, at)) {
        if (!in_span(x)) return never;
        mark = at;
        return next;
      }
    }
    tau = next;
  }
  return undecided;
}

/// The first collision with one wall in its window [start, end], given the sign of f' there
/// (`slope_sign`): +∞ when f' < 0 throughout, the monotone search when f' > 0 throughout (which
/// keeps the flight's mark there in `*mark`), else the certified scan of the window.
template <class Gap, class InSpan, class Real, class Mark>
Real crossing_in_window(const Gap& g, InSpan in_span, const Window<Real>& w, int slope, Mark& mark) {
  if (slope < 0) return never;
  if (slope > 0) {
    const Real tau = monotone_crossing(g, in_span, w, mark);
    if (tau != undecided) return tau;
  }
  auto sample = [&](const Real& tau) { return g.sample(tau); };
  auto tolerance = [&](const Real& tau) { return g.tolerance(tau); };
  auto earliest = [&](const Real& tau) { return tau < w.start ? w.start : tau; };
  return first_outward_crossing(sample, earliest, in_span, tolerance, w.end);
}

/// Tables of more walls than this are searched wall by wall (see DrivenScan::first_hit).
inline constexpr int windows_in_time_order_walls = 24;
/// Walls whose windows are sorted and searched together (first_hit_in_windows): as many as the
/// lock-step search holds in its vectors (lockstep::max_walls), so that it searches a table
/// group by group as the scalar search does, with the same operations.
inline constexpr int windows_group_walls = 16;

/// The first collision of a driven flight with walls 0 … walls − 1 of `visit`, at most
/// windows_group_walls of them, before τ = tau_best: see first_hit_in_windows.
template <class Real, class Visit, class Mark>
void first_hit_in_group(int walls, Visit visit, Real& tau_best, int& best_wall, Mark& mark) {
  using std::min;
  // The windows as they are found (uninitialized storage), and their order of opening sorted
  // by insertion, stable: cheaper than swapping the windows themselves.
  Window<Real> windows[2 * windows_group_walls];
  unsigned char order[2 * windows_group_walls];
  int count = 0;
  for (int w = 0; w < walls; ++w)
    visit(w, [&](const auto& gap, const auto&, const auto&) {
      for (int n = count + gap.windows(tau_best, windows + count); count < n; ++count) {
        windows[count].wall = w;
        int i = count;
        for (; i > 0 && windows[order[i - 1]].start > windows[count].start; --i) order[i] = order[i - 1];
        order[i] = static_cast<unsigned char>(count);
      }
    });
  for (int k = 0; k < count && windows[order[k]].start <= tau_best; ++k)
    visit(windows[order[k]].wall, [&](const auto& gap, const auto& passes, const auto& in_span) {
      auto window = windows[order[k]];
      window.end = min(window.end, tau_best);
      // The sign of f' first: it rules out the window the flight leaves its last wall through
      // (one a flight) at half the cost of the span test.
      const int slope = gap.slope_sign(window);
      if (slope < 0 || passes(window.start, window.end)) return;
      Mark sampled;
      const Real tau = crossing_in_window(gap, in_span, window, slope, sampled);
      if (tau < tau_best) {
        tau_best = tau;
        best_wall = window.wall;
        mark = sampled;
      }
    });
}

/// The first collision of a driven flight with any of `walls` walls before τ = tau_best:
/// tau_best, best_wall and `mark` (the flight's mark at the root, when the monotone search
/// found it) are updated.  The walls are taken in groups of windows_group_walls, in order, each
/// group up to the best collision found before it; a group's windows until then are computed
/// in closed form and searched in the order in which they open, so the search stops at the
/// first window that opens after the best collision found and the walls beyond it are never
/// sampled.  `visit(w, fn)` calls fn(gap, passes, in_span) for wall w: its gap (the wall's
/// `gap_along`), passes(start, end), true when the particle cannot reach the wall's span in the
/// window, and the span test in_span(x).  Not for creeping flights (see `creep`), whose gaps
/// these are.
template <class Real, class Visit, class Mark>
void first_hit_in_windows(int walls, Visit visit, Real& tau_best, int& best_wall, Mark& mark) {
  if (walls > windows_in_time_order_walls) throw std::logic_error("first_hit_in_windows: too many walls");
  for (int first = 0; first < walls; first += windows_group_walls) {
    auto in_group = [&](int w, auto&& fn) { visit(first + w, fn); };
    int group_best = -1;
    first_hit_in_group(std::min(walls - first, windows_group_walls), in_group, tau_best, group_best, mark);
    if (group_best >= 0) best_wall = first + group_best;
  }
}

/// The scan of a driven flight through one wall (`first_outward_crossing` of the gap g) whose
/// `earliest` passes the windows it can (`first_window`) and, for a creeping flight, lets
/// `creep`'s jumps and the windows take turns until neither moves on.  `passes(τ, end)` may
/// declare a window [τ, end] free of collisions (the wall's span is out of reach) and
/// `clearance(τ)` bounds the distance of the oscillation segment from the wall within its span
/// from below (see `creep`), or is NotCreeping (see `with_creep`).  +∞ if no collision.
template <class Q, class Gap, class Passes, class InSpan, class Clearance, class Real>
[[gnu::always_inline]] inline Real scan_windows(const Q& q, const Gap& g, Passes passes, InSpan in_span,
                                                Clearance clearance, const Real& tau_end) {
  auto sample = [&](const Real& tau) { return g.sample(tau); };
  auto tolerance = [&](const Real& tau) { return g.tolerance(tau); };
  auto window_start = [&](const Real& tau) { return g.window_start(tau); };
  auto window_end = [&](const Real& start) { return g.window_end(start, tau_end); };
  Real sampled_until = -1;
  auto earliest = [&](const Real& tau) {
    Real t = first_window(tau, tau_end, window_start, window_end, passes, sampled_until);
    if constexpr (!std::is_same_v<Clearance, NotCreeping>) {
      for (;;) {  // jumps and windows in turn, until neither moves on
        const Real next = creep(q, t, tau_end, clearance, tolerance);
        if (next == t || next == never) return next;
        t = first_window(next, tau_end, window_start, window_end, passes, sampled_until);
      }
    }
    return t;
  };
  return first_outward_crossing<!std::is_same_v<Clearance, NotCreeping>>(sample, earliest, in_span, tolerance, tau_end);
}

}  // namespace billiards::dynamics::scan
