// What the phase-space tests (boundary map, Lyapunov exponents) share: bundled shapes and
// scenes by name, and the divergence rate of two nearby orbits (an exponent without tangent
// dynamics).
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/scene.hpp"
#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <Eigen/Core>

#include <cmath>
#include <string>

inline billiards::geometry::Shape bundled_shape(const std::string& name) {
  return billiards::geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + name);
}

/// A bundled scene with `particles` particles.
inline billiards::dynamics::Scene bundled_scene(const std::string& name, std::size_t particles) {
  billiards::dynamics::SceneOverrides o;
  o.particles = particles;
  return billiards::dynamics::load_scene(BILLIARDS_SOURCE_DIR "/scenes/" + name, o);
}

/// The flight from s to time t_end, through the bounces before it (an energy-conserving one
/// restoring the orbit's own speed after each, as `evolve` does), adding them to `bounces`.
template <class TableT, class Flight>
typename Flight::State advance_to(const TableT& table, const Flight& flight, typename Flight::State s, double t_end,
                                  std::size_t* bounces = nullptr) {
  const double v2 = s.v.squaredNorm();
  for (;;) {
    const auto hit = billiards::dynamics::collision(table, flight, s, t_end);
    if (!hit.found()) return flight.advance(s, t_end);
    billiards::dynamics::bounce(flight, s, hit);
    if constexpr (Flight::conserves_energy) billiards::dynamics::restore_speed(s.v, v2);
    if (bounces) ++*bounces;
  }
}

/// The maximal exponent of the orbit from `a` over its first `collisions` bounces (up to the end
/// of the interval in which the last falls) by Benettin et al.'s (1976) method: a second orbit
/// delta0 apart in phase space (along `shift`, a position shift), compared with the first after
/// every `interval` and put back at distance delta0 along their separation (with the first's
/// speed when the flight conserves it); the mean log growth per unit time.  (Counted in
/// bounces, as the tangent dynamics' trajectories are: under a drive the energy, and with it
/// the exponent per unit time, grows at a rate of its own along each orbit, and an orbit
/// followed for a fixed time would weigh the energies otherwise.)
template <class TableT, class Flight>
double divergence_rate(const TableT& table, const Flight& flight, typename Flight::State a,
                       const decltype(a.x)& shift, std::size_t collisions, double delta0 = 1e-9,
                       double interval = 1) {
  constexpr int D = Flight::State::dimension;
  using Phase = Eigen::Matrix<double, 2 * D, 1>;
  const auto phase_point = [](const auto& s) { return (Phase() << s.x, s.v).finished(); };
  auto b = a;
  b.x += delta0 * shift.normalized();
  const double t0 = a.t;
  std::size_t made = 0;
  int steps = 0;
  double sum = 0;
  while (made < collisions) {
    const double t = t0 + ++steps * interval;
    a = advance_to(table, flight, a, t, &made);
    b = advance_to(table, flight, b, t);
    const Phase d = phase_point(b) - phase_point(a);
    sum += std::log(d.norm() / delta0);
    const Phase renormalised = phase_point(a) + d * (delta0 / d.norm());
    b.x = renormalised.template head<D>();
    b.v = renormalised.template tail<D>();
    if constexpr (Flight::conserves_energy) b.v = b.v.normalized() * a.v.norm();
  }
  return sum / (steps * interval);
}
