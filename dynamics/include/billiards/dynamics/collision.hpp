// The verbs of the dynamics: `collision` (the next wall a flight leaves through), `bounce`
// (specular reflection).  `collision` is generic over the flight model (flight.hpp).
#pragma once

#include "billiards/dynamics/flight.hpp"
#include "billiards/dynamics/free_flight.hpp"
#include "billiards/dynamics/table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace billiards::dynamics {

namespace detail {

/// The exit-time searches of a flight from one state, wall by wall: flight.exit_time(s, ...).
template <class Flight>
struct WallByWall {
  const Flight& flight;
  const typename Flight::State& s;
  template <class Wall>
  typename Flight::Scalar exit_time(const Wall& w, const typename Flight::Scalar& t_end) const {
    if constexpr (std::is_same_v<Wall, BasicEllipticArcWall<typename Flight::Scalar>> && affine_covariant<Flight> &&
                  !is_straight<Flight>)  // (straight flights: the closed form of free_flight.hpp)
      return elliptic_exit_time(flight, s, w, t_end);
    else
      return flight.exit_time(s, w, t_end);
  }
};

/// The exit-time searches from s: the flight's own `scan_from(s)` when it shares work between
/// the walls (forced_flight.hpp's DrivenScan), else wall by wall.
template <class Flight>
auto scan_from(const Flight& flight, const typename Flight::State& s) {
  if constexpr (requires { flight.scan_from(s); }) return flight.scan_from(s);
  else return WallByWall<Flight>{flight, s};
}

/// Tries one wall; keeps it if it is hit before the best so far.
template <class Real, class Scan>
inline void try_wall(const BasicTable<Real>& table, const Scan& scan, const WallId& wall, BasicHit<Real>& best) {
  const auto t = table.visit(wall, [&](const auto& w) { return scan.exit_time(w, best.t); });
  if (t < best.t) {
    best.t = t;
    best.wall = wall;
  }
}
template <class Flight>
inline void try_wall(const BasicTable<typename Flight::Scalar>& table, const Flight& flight,
                     const typename Flight::State& s, const WallId& wall, BasicHit<typename Flight::Scalar>& best) {
  try_wall(table, WallByWall<Flight>{flight, s}, wall, best);
}

/// Tries the walls of one kind (the best hit so far kept in locals, so that the loop does not
/// reload it from memory after each wall).
template <class Real, class Scan, class Wall>
inline void try_walls(const Walls<Wall>& walls, int kind, const Scan& scan, BasicHit<Real>& best) {
  const Wall* w = walls.data();
  const int n = int(walls.size());
  Real best_t = best.t;
  int best_i = -1;
  for (int i = 0; i < n; ++i) {
    const auto t = scan.exit_time(w[i], best_t);
    if (t < best_t) {
      best_t = t;
      best_i = i;
    }
  }
  best.t = best_t;
  if (best_i >= 0) best.wall = {kind, best_i};
}

/// Tries every wall of the table, kind by kind.
template <class Real, class Scan>
inline void try_every_wall(const BasicTable<Real>& table, const Scan& scan, BasicHit<Real>& best) {
  table.for_each_kind([&](const auto& walls, int kind) { try_walls(walls, kind, scan, best); });
}

/// The grid's cells (i, j) that the line p + v (t − t0), t ≥ t0, crosses, in the order in which
/// it crosses them (Amanatides–Woo), with the times it enters and leaves each: visit(i, j,
/// enter, leave) until it returns true or the line leaves the grid widened by `reach` cells on
/// every side (cells beyond the grid's have indices outside it and hold no walls).  The cell of
/// p is clamped to that widened grid: a particle on a wall may sit a hair outside.
template <class Grid, class Visit>
void walk_cells(const Grid& g, const Vec2& p, const Vec2& v, double t0, int reach, Visit visit) {
  const Vec2 rel = (p - g.origin).cwiseQuotient(g.cell);
  int i = std::clamp(int(std::floor(rel.x())), -reach, g.nx - 1 + reach);
  int j = std::clamp(int(std::floor(rel.y())), -reach, g.ny - 1 + reach);
  const int step_i = v.x() > 0 ? 1 : -1, step_j = v.y() > 0 ? 1 : -1;
  // Time at which the line crosses the next vertical / horizontal cell line.
  auto next_line = [&](int k, int step, double origin, double cell, double x, double vk) {
    if (vk == 0) return never;
    return t0 + (origin + (k + (step > 0 ? 1 : 0)) * cell - x) / vk;
  };
  double tx = next_line(i, step_i, g.origin.x(), g.cell.x(), p.x(), v.x());
  double ty = next_line(j, step_j, g.origin.y(), g.cell.y(), p.y(), v.y());
  const double dtx = v.x() != 0 ? g.cell.x() / std::abs(v.x()) : never;
  const double dty = v.y() != 0 ? g.cell.y() / std::abs(v.y()) : never;
  for (double enter = t0;; enter = std::min(tx, ty)) {
    if (visit(i, j, enter, std::min(tx, ty))) return;
    if (tx < ty) {
      i += step_i;
      tx += dtx;
    } else {
      j += step_j;
      ty += dty;
    }
    if (i < -reach || j < -reach || i >= g.nx + reach || j >= g.ny + reach) return;
  }
}

/// Straight flights through the grid (walk_cells): walls are tested cell by cell and the search
/// stops at the first cell that contains the best hit so far.
Hit grid_collision(const Table& table, const FreeFlight& flight, const State& s, double t_end);

/// The first hit before best.t among the walls of a table with a grid by a flight that stays
/// within `reach` of the line p + v (t − t0) (a driven flight: its guide, within δ): each wall
/// listed in a cell within `reach` of the line's stretch in a cell it crosses, tried once
/// (scan.exit_time), cell after cell along the line until it leaves a cell after the best hit
/// so far.  (A wall hit at t lies within reach of the line's point at t, in the stretch of a
/// cell the walk has entered by t: once the line leaves a cell after the best hit, no wall not
/// yet tried is hit earlier.)
template <class Real, class Scan>
void tube_collision(const BasicTable<Real>& table, const Scan& scan, const Vec2& p, const Vec2& v, double t0,
                    double reach, BasicHit<Real>& best) {
  const typename BasicTable<Real>::Grid& g = *table.grid();
  // (With a margin for the walls' boxes, padded by the tolerance only, and for the rounding
  // of the line's points.)
  const double d = reach + 4 * table.tolerance();
  const int r = int(std::ceil(d / std::min(g.cell.x(), g.cell.y())));
  std::vector<bool> tried(table.wall_count());  // by piece_of
  // The cells of the box of the line's stretch [enter, leave], widened by d, along one axis.
  auto cells = [&](int axis, double enter, double leave, int& lo, int& hi) {
    const double a = p[axis] + (v[axis] == 0 ? 0 : v[axis] * (enter - t0));
    const double b = v[axis] == 0 ? p[axis] : p[axis] + v[axis] * (leave - t0);
    const int n = axis == 0 ? g.nx : g.ny;
    lo = std::max(0, int(std::floor((std::min(a, b) - d - g.origin[axis]) / g.cell[axis])));
    hi = std::min(n - 1, int(std::floor((std::max(a, b) + d - g.origin[axis]) / g.cell[axis])));
  };
  walk_cells(g, p, v, t0, r, [&](int, int, double enter, double leave) {
    int x0, x1, y0, y1;
    cells(0, enter, leave, x0, x1);
    cells(1, enter, leave, y0, y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::size_t c = std::size_t(y) * g.nx + x;
        for (int k = g.start[c]; k < g.start[c + 1]; ++k) {
          const WallId& wall = g.walls[k];
          const auto piece = std::size_t(table.piece_of(wall));
          if (tried[piece]) continue;
          tried[piece] = true;
          try_wall(table, scan, wall, best);
        }
      }
    return best.t <= leave;
  });
}

}  // namespace detail

/// A hit with the flight's state there, before the bounce: `collision` computes it to place the
/// hit point, and `bounce` starts from it instead of advancing the flight a second time (for
/// a driven flight, a reduction of the phase and a sine and a cosine per collision).
template <class Flight>
struct FlightHit : BasicHit<typename Flight::Scalar, Flight::State::dimension> {
  typename Flight::State state;
  /// Has the search that found the hit also certified the flight's position half way to it
  /// inside the region (Table::certainly_contains, as Trajectory's every-flight check asks)?
  /// The lock-step search does; false: not asked.
  bool midpoint_inside = false;
};

/// The flight a lane of a stream of collision searches takes next (Table3::collision_stream,
/// run_in_lockstep): from *state, up to t_end; none where state is null.
template <class State>
struct NextFlight {
  const State* state = nullptr;
  double t_end = never;
};

/// The first wall the flight from `s` leaves the region through, before `t_end`.
/// Hit::found() is false when no wall is met: for a particle inside a bounded region and
/// t_end = never, that means it has escaped.
template <class Flight>
FlightHit<Flight> collision(const BasicTable<typename Flight::Scalar>& table, const Flight& flight,
                            const typename Flight::State& s, const typename Flight::Scalar& t_end = never) {
  const auto scan = detail::scan_from(flight, s);
  // (Made in place, not assigned: copying a driven state just after its phase was stored costs
  // a store-forwarding stall per collision.)
  FlightHit<Flight> best = [&] {
    if constexpr (requires { scan.first_hit(table, t_end); }) {
      return scan.first_hit(table, t_end);  // (with the state at the hit)
    } else {
      FlightHit<Flight> hit;
      if constexpr (std::is_same_v<Flight, FreeFlight>) {
        if (table.grid()) static_cast<Hit&>(hit) = detail::grid_collision(table, flight, s, t_end);
      }
      if (!table.grid() || !std::is_same_v<Flight, FreeFlight>) {
        hit.t = t_end;
        detail::try_every_wall(table, scan, hit);
      }
      if (hit.found()) hit.state = flight.advance(s, hit.t);
      return hit;
    }
  }();
  if (best.found()) std::tie(best.point, best.normal) = table.contact(best.wall, best.state.x, best.state.v);
  return best;
}

/// The flight's state at a hit: the one `collision` kept, or `s` advanced to the hit.
template <class Flight>
const typename Flight::State& state_at(const Flight&, const typename Flight::State&, const FlightHit<Flight>& hit) {
  return hit.state;
}
template <class Flight>
typename Flight::State state_at(const Flight& flight, const typename Flight::State& s,
                                const BasicHit<typename Flight::Scalar, Flight::State::dimension>& hit) {
  return flight.advance(s, hit.t);
}

namespace detail {

#include "billiards/dynamics/bounce-inl.hpp"

}  // namespace detail

/// v − k n/(n·n), the same division by n·n: the reflection with k = 2(v·n), or off a moving wall
/// with k = 2((v − u)·n) (u the wall's velocity).
template <class Real, int D>
inline VecN<Real, D> reflect(const VecN<Real, D>& v, const VecN<Real, D>& n, const Real& k) {
  VecN<Real, D> reflected = v;
  detail::reflect_in_place<ScalarLanes<Real>, D>(reflected, n, k);
  return reflected;
}
/// Specular reflection off the normal n, v' = v − 2(v·n)n/(n·n).  A computed normal is a unit
/// vector to rounding only, n·n = 1 + η, and the plain v − 2(v·n)n scales the normal component
/// by 1 + 2η: after the speed is restored, the orbit turns toward the normal by η.  Contact
/// normals u/|u| with |u| ≈ 1 have η biased (+0.55 ε on average at the circle), so that turn
/// was a drift (the circle's angular momentum −1.06 ε per bounce at 1.4 rad from the tangent).
/// Here 1/(n·n) = 1 − η to O(ε²), with η from unit_excess (η exact from Dekker's products cost
/// 10% of a free clover collision; this costs nothing measurable, BENCHMARKS.md).
template <class Real, int D>
inline VecN<Real, D> reflect(const VecN<Real, D>& v, const VecN<Real, D>& n) {
  return reflect(v, n, Real(2 * v.dot(n)));
}

using detail::speed_band;

/// Rescales v to the speed² `v2` once rounding has moved |v|² out of the speed band about it.
/// Flights that conserve energy call this after every bounce, against the value at the start,
/// never against the previous bounce, so rounding cannot accumulate into a drift over 10⁹
/// bounces: |v|² stays within the band and one bounce's rounding of v2.  Not at every bounce:
/// the factor √(v2/|v|²) is then a double within a few ε of 1, and multiplying by it rounds
/// each component by another fraction of its ulp, which turns v a little, the same way at every
/// bounce (the elliptic billiard's focal product drifted −0.003 ε per bounce; with the band,
/// one bounce in tens is rescaled).
template <class Real, int D>
inline void restore_speed(Eigen::Matrix<Real, D, 1>& v, const Real& v2) {
  detail::restore_speed_in_place<ScalarLanes<Real>, D>(v, v2, Real(v.squaredNorm()), speed_band<Real>);
}

/// Moves the particle to the collision and reflects it there.  `HitT` is BasicHit or the
/// FlightHit `collision` returns.
template <class Flight, class HitT>
void bounce(const Flight& flight, typename Flight::State& s, const HitT& hit) {
  s = state_at(flight, s, hit);
  s.x = hit.point;
  s.v = reflect(s.v, hit.normal);
}

/// Starts the particle's next flight on its own clock: the time of the flight just made moves
/// from the state (its t) to the run's clock, and the state's t becomes 0.  The collision
/// loops do this after every bounce, so that a flight's times are resolved to its own rounding
/// however long the run (state.hpp's BasicClock).  Every flight's law reads only the time since
/// its start: a drive's phase is carried in the state (forced_flight.hpp's BasicDrivenState).
template <class Flight>
void restart_clock(const Flight&, typename Flight::State& s, BasicClock<typename Flight::Scalar>& clock) {
  clock.add(s.t);
  s.t = 0;
}

/// A hit (and the flight's state at it) or a state as callers see it: its time absolute, the
/// clock's time plus the flight's own.
template <class T, class Clock>
T on_clock(T event, const Clock& clock) {
  if constexpr (requires { event.state.t; }) event.state.t = clock.after(event.state.t);
  event.t = clock.after(event.t);
  return event;
}

/// A flight as it was made on its own clock: its duration (the hit's time on the flight's
/// clock, which started at 0) and the run's clock at its start.  What a visitor of `evolve`
/// needs to work inside a flight (a tangent flow over its duration, a section's crossings)
/// without differences of absolute times, which would be rounded to ulp(t).
template <class Real>
struct Flown {
  Real duration;
  const BasicClock<Real>& start;
};

/// visit(hit, state), or visit(hit, state, flown) when the visitor takes the flight's Flown too.
template <class Visit, class HitT, class State, class Real>
void visit_bounce(Visit& visit, const HitT& hit, const State& s, const Flown<Real>& flown) {
  if constexpr (std::is_invocable_v<Visit&, const HitT&, const State&, const Flown<Real>&>)
    visit(hit, s, flown);
  else
    visit(hit, s);
}

/// Follows the particle from `s` through its next `collisions` bounces (fewer if it meets no
/// wall: an escape), calling visit(hit, state) with the state just after each bounce, times
/// absolute (or visit(hit, state, flown) with the flight's Flown too, when it takes three
/// arguments); energy-conserving flights restore the speed after every bounce.  Each flight
/// runs on its own clock (restart_clock).  Returns the bounces made.  Any table (2-D or 3-D):
/// `collision` and `bounce` are found by overload resolution.
template <class TableT, class Flight, class Visit>
std::size_t evolve(const TableT& table, const Flight& flight, typename Flight::State s, std::size_t collisions,
                   Visit&& visit) {
  using Real = typename Flight::Scalar;
  const auto v2 = s.v.squaredNorm();
  BasicClock<Real> clock;
  restart_clock(flight, s, clock);
  for (std::size_t k = 0; k < collisions; ++k) {
    const auto hit = collision(table, flight, s);
    if (!hit.found()) return k;
    bounce(flight, s, hit);
    if constexpr (Flight::conserves_energy) restore_speed(s.v, v2);
    visit_bounce(visit, on_clock(hit, clock), on_clock(s, clock), Flown<Real>{s.t, clock});
    restart_clock(flight, s, clock);
  }
  return collisions;
}

/// The next `collisions` hits of the particle from `s` (fewer on an escape).
template <class Flight>
std::vector<BasicHit<typename Flight::Scalar>> evolve(const BasicTable<typename Flight::Scalar>& table,
                                                      const Flight& flight, typename Flight::State s,
                                                      std::size_t collisions) {
  std::vector<BasicHit<typename Flight::Scalar>> hits;
  evolve(table, flight, s, collisions, [&](const auto& hit, const auto&) { hits.push_back(hit); });
  return hits;
}

}  // namespace billiards::dynamics
