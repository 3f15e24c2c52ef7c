// Helpers of the hard-cases suites (test_hard_cases_free.cpp, test_hard_cases_driven.cpp): a
// double trajectory with every flight checked, the same trajectory in 136-bit MPFR (the very
// same flight code, dynamics::Reference), and how long the two agree.
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/precision.hpp"
#include "billiards/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace hard {

using namespace billiards;
using dynamics::Reference;
using dynamics::Vec2;

inline geometry::Region2 shape(const std::string& name, const billiards::Overrides& set = {}) {
  return geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml", set).region;
}

/// A free state at x with velocity v, at t = 0.
inline dynamics::State state_at(const Vec2& x, const Vec2& v = Vec2::Zero()) {
  dynamics::State s;
  s.x = x;
  s.v = v;
  return s;
}

/// How far p lies outside the closed region (0 inside), by the table's independent
/// crossing-number test without its tolerance (Table::contains allows 1e-9 of the size).
inline double beyond(const dynamics::Table& table, const Vec2& p) {
  return table.contains(p, 0) ? 0 : table.wall_distance(p);
}

/// What went wrong, if anything, along a double trajectory.
struct Walk {
  std::vector<dynamics::Hit> hits;
  std::size_t zero_flights = 0;  // collisions at zero flight time in a row, the longest run
  double worst_beyond = -1;      // the largest `beyond` of a flight's start
  double worst_energy = 0;       // the largest |ΔE|/E (energy-conserving flights)
  bool escaped = false;          // a flight met no wall, or its midpoint left the region
};

/// `collisions` bounces of the double trajectory from s, as dynamics::evolve does them, with
/// every flight's midpoint and start checked.
template <class Flight>
Walk walk(const dynamics::Table& table, const Flight& flight, typename Flight::State s, std::size_t collisions) {
  Walk w;
  const double v2 = s.v.squaredNorm();
  std::size_t run = 0;
  for (std::size_t k = 0; k < collisions; ++k) {
    const auto hit = dynamics::collision(table, flight, s);
    if (!hit.found() || !table.contains(flight.advance(s, 0.5 * (s.t + hit.t)).x)) {
      w.escaped = true;
      break;
    }
    run = hit.t == s.t ? run + 1 : 0;
    w.zero_flights = std::max(w.zero_flights, run);
    dynamics::bounce(flight, s, hit);
    if constexpr (Flight::conserves_energy) {
      dynamics::restore_speed(s.v, v2);
      w.worst_energy = std::max(w.worst_energy, std::abs(s.v.squaredNorm() - v2) / v2);
    }
    w.worst_beyond = std::max(w.worst_beyond, beyond(table, s.x));
    w.hits.push_back(hit);
  }
  return w;
}

/// The same trajectory in MPFR: its collision points and times, rounded to double.
template <class RefFlight>
std::vector<dynamics::Hit> reference_hits(const geometry::Region2& region, const RefFlight& flight,
                                          const dynamics::State& s0, std::size_t collisions) {
  const dynamics::BasicTable<Reference> table(region);
  dynamics::BasicState<Reference> s;
  s.x = s0.x.cast<Reference>();
  s.v = s0.v.cast<Reference>();
  s.t = s0.t;
  std::vector<dynamics::Hit> out;
  for (const auto& h : dynamics::evolve(table, flight, flight.start(s), collisions)) {
    dynamics::Hit d;
    d.t = double(h.t);
    d.wall = h.wall;
    d.point = Vec2(double(h.point.x()), double(h.point.y()));
    out.push_back(d);
  }
  return out;
}

/// The number of leading collisions at which the double points are within `tol` of the
/// reference's (walls are not compared: at a corner either wall may come first).
inline std::size_t agreeing(const std::vector<dynamics::Hit>& d, const std::vector<dynamics::Hit>& ref, double tol) {
  std::size_t k = 0;
  while (k < d.size() && k < ref.size() && (d[k].point - ref[k].point).norm() <= tol) ++k;
  return k;
}

}  // namespace hard
