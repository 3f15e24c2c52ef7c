// Exit times of a straight flight.  Both are closed forms; the only delicate quantity is the
// sign of the circle discriminant at grazing incidence, which is decided by a filtered
// predicate (double with a forward error bound, exact rationals when the bound cannot decide).
#include "billiards/dynamics/flight.hpp"
#include "billiards/dynamics/predicates.hpp"

#include <cmath>

namespace billiards::dynamics {

double FreeFlight::exit_time(const State& s, const SegmentWall& w, double t_end) const {
  const double rate = w.normal.dot(s.v);  // d/dt of the distance beyond the wall's line
  if (!(rate > 0)) return never;          // parallel or moving inward: no exit here
  const double beyond = w.normal.dot(s.x - w.a);
  // Beyond the line by rounding only (a particle just reflected at a joint): collide now.
  // Far beyond it: the particle is elsewhere in a non-convex region, moving away.
  if (beyond > w.slack) return never;
  const double dt = beyond >= 0 ? 0.0 : -beyond / rate;
  const double t = s.t + dt;
  if (t > t_end || !w.within_span(s.x + s.v * dt)) return never;
  return t;
}

double FreeFlight::exit_time(const State& s, const ArcWall& w, double t_end) const {
  // |f + v τ|² − r² = a τ² + 2 b τ + c with f = x − centre.
  const Vec2 f = s.x - w.center;
  const double a = s.v.squaredNorm();
  const double b = f.dot(s.v);
  const double c = f.squaredNorm() - w.radius2;
  double dt;
  // c ≈ 2 r × (distance beyond the circle): "within rounding of the circle" in c units.
  const double near = 2 * w.radius * w.slack;
  if (w.focusing) {
    // Region inside the circle: leave through the larger root.
    if (b >= 0 && c >= 0) return c <= near ? s.t : never;  // on the circle moving out: now
    // Outside the circle (a non-convex region) and moving in: a miss or a graze is no exit.
    if (c > 0 && circle_discriminant_sign_filtered(s.x, w.center, s.v, w.radius, w.radius2) <= 0)
      return never;
    // Perpendicular (cancellation-free) discriminant b² − a c = a r² − (f × v)², clamped at
    // 0 because a particle inside the circle always meets it.
    const double root = std::sqrt(std::max(0.0, circle_discriminant(f, s.v, w.radius2)));
    dt = b <= 0 ? (root - b) / a : -c / (b + root);
  } else {
    // Region outside the circle: enter it through the smaller root, only when approaching.
    if (b >= 0) return never;
    if (c <= 0) {
      // Inside the circle by rounding only: reflect now.  Deeper inside, the particle is in a
      // part of the region the circle overlaps elsewhere, and only leaves the circle ahead.
      if (c < -near) return never;
      dt = 0;
    } else {
      // A miss or an exact tangency (a touch, not a crossing) is no collision.
      if (circle_discriminant_sign_filtered(s.x, w.center, s.v, w.radius, w.radius2) <= 0) return never;
      dt = c / (std::sqrt(std::max(0.0, circle_discriminant(f, s.v, w.radius2))) - b);
    }
  }
  const double t = s.t + dt;
  if (t > t_end || !w.within_span(s.x + s.v * dt)) return never;
  return t;
}

}  // namespace billiards::dynamics
