// The boundary map of a 2-D table in Birkhoff coordinates (s, p), and the two sections of the
// flow beside it: a Poincaré section on a line (a plane in 3-D), and the stroboscopic section of
// a driven scene.
//
// s is the arc length along the boundary.  The outer loop comes first, from the source of its
// first piece (the first point written in the shape file) in the loop's own direction
// (counter-clockwise); then every hole in the file's order, from its first piece's source in
// its direction (clockwise), s continuing where the previous loop ended, up to the perimeter S.
// Every loop keeps the region on its left, so the unit tangent t of the direction of travel
// and the region's outward normal n satisfy n = (t_y, −t_x).
//
// p is the sine of the angle between the outgoing velocity v and the inward normal −n,
// counted positive towards t: p = v·t/|v|.  The free billiard map preserves ds dp (the
// measure cos φ ds dφ), so a chaotic, ergodic table's boundary map fills [0, S) × [−1, 1]
// uniformly.
#pragma once

#include "billiards/analysis/per_particle.hpp"
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/geometry3/region3.hpp"
#include "billiards/geometry/pieces.hpp"

#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace billiards::analysis {

using geometry::Vec2;

class BoundaryCoordinates {
 public:
  explicit BoundaryCoordinates(const geometry::Region2& region);
  /// s of the point x on piece `piece` (counted loop by loop, outer first: Table::piece_of),
  /// x projected onto the piece.
  double s_at(int piece, const Vec2& x) const;
  /// s of a hit of a table built from the same region.
  double s_of(const dynamics::Table& table, const dynamics::Hit& hit) const {
    return s_at(table.piece_of(hit.wall), hit.point);
  }
  /// p of the velocity v leaving a wall whose outward unit normal is n.
  static double p_of(const Vec2& v, const Vec2& n) { return (n.x() * v.y() - n.y() * v.x()) / v.norm(); }
  /// s at the start of every piece, then the perimeter S (piece count + 1 values).
  const std::vector<double>& piece_starts() const { return starts_; }
  /// The index in piece_starts of every loop's first piece, outer first.
  const std::vector<int>& loop_firsts() const { return loop_firsts_; }
  double perimeter() const { return starts_.back(); }
  /// The piece holding arc length s (the later one at a joint), and the point at s.
  int piece_at(double s) const;
  Vec2 point_at(double s) const;
  /// The region's outward unit normal at arc length s.
  Vec2 normal_at(double s) const;
  /// The loop (0 outer, then the holes) holding arc length s, and its range [first, end) of s.
  int loop_at(double s) const;
  std::pair<double, double> loop_range(int loop) const;
  /// The arc length of x if x lies on the boundary (within `tolerance`), else nothing.
  std::optional<double> locate(const Vec2& x, double tolerance) const;

 private:
  std::vector<geometry::Piece> pieces_;
  std::vector<double> starts_;
  std::vector<int> loop_firsts_;
  std::vector<double> origins_;  // elliptic arcs: the primitive of the arc length at the source
};

/// A hyperplane n·x = c, n a unit vector: a Poincaré section on a line (2-D) or a plane (3-D).
/// A crossing counts when the particle goes from n·x < c to n·x ≥ c.  Its coordinates: in 2-D
/// u = d·x along the line and p = d·v/|v|, d = (−n_y, n_x); in 3-D u1 = e1·x, u2 = e2·x,
/// p1 = e1·v/|v|, p2 = e2·v/|v|, where e1 is the coordinate axis least aligned with n (the first
/// of equals), made orthogonal to n, and e2 = n × e1 (for "z = 0": e1 = x̂, e2 = ŷ).
template <int D>
struct BasicSection {
  Eigen::Matrix<double, D, 1> normal;
  double offset = 0;
  /// The orthonormal basis of the hyperplane (above).
  std::array<Eigen::Matrix<double, D, 1>, D - 1> basis() const {
    if constexpr (D == 2) {
      return {Vec2(-normal.y(), normal.x())};
    } else {
      int axis = 0;
      for (int k = 1; k < 3; ++k)
        if (std::abs(normal[k]) < std::abs(normal[axis])) axis = k;
      const geometry3::Vec3 e1 = (geometry3::Vec3::Unit(axis) - normal[axis] * normal).normalized();
      return {e1, normal.cross(e1)};
    }
  }
};
using SectionLine = BasicSection<2>;
using SectionPlane = BasicSection<3>;

/// The section of an equation "LHS = RHS" linear in x and y (and z in 3-D), as `billiard bmap
/// --section` and billiardkit.boundary_map(section=) read it: n·x = c with n a unit vector.
/// Anything else is an InputError naming `option` and the text.
template <int D>
BasicSection<D> parse_section(const std::string& text, const std::string& option);

/// Rows of `bmap.npy`: particle, collision (1, 2, ...), s, p, t, energy (after the bounce).
inline constexpr std::array<const char*, 6> bmap_columns{"particle", "collision", "s", "p", "t", "energy"};
/// Rows of a line section: particle, crossing (1, 2, ...), u, p, t, energy.
inline constexpr std::array<const char*, 6> section_columns{"particle", "crossing", "u", "p", "t", "energy"};
/// Rows of a plane section (3-D): particle, crossing, u1, u2, p1, p2, t, energy.
inline constexpr std::array<const char*, 8> section3_columns{"particle", "crossing", "u1", "u2", "p1", "p2", "t", "energy"};
/// Rows of a stroboscopic section: particle, period k (t = (PHASE − phase0 + 2πk)/ω), x, y, vx,
/// vy, t, energy.
inline constexpr std::array<const char*, 8> strobe_columns{"particle", "k", "x", "y", "vx", "vy", "t", "energy"};
/// The same in 3-D: particle, k, x, y, z, vx, vy, vz, t, energy.
inline constexpr std::array<const char*, 10> strobe3_columns{"particle", "k",  "x", "y",      "z",
                                                             "vx",       "vy", "vz", "t", "energy"};

/// What an ensemble's sections leave: the rows of every particle in index order, and which
/// particles met no wall before their last collision (escapes: an error of the table).
struct SectionRows {
  std::size_t columns = 0;
  std::vector<double> rows;
  std::vector<char> escaped;
  std::size_t row_count() const { return columns ? rows.size() / columns : 0; }
  std::size_t escapes() const {
    std::size_t n = 0;
    for (char e : escaped) n += e;
    return n;
  }
};

namespace detail {
/// Runs every particle for `collisions` bounces, `record(i, hit, before, after, flown, rows)`
/// appending its rows (`flown`: the flight from `before` on its own clock, collision.hpp's
/// Flown); collects them in particle order.
template <class Flight, class Initial, class Record>
SectionRows collect(const dynamics::TableFor<Flight>& table, const Flight& flight, const Initial& initial, std::size_t particles,
                    std::size_t collisions, int threads, std::size_t columns, Record record,
                    const std::function<void(std::size_t)>& progress) {
  struct Part {
    std::vector<double> rows;
    char escaped = 0;
  };
  const auto parts = for_each_particle(
      particles, threads,
      [&](std::size_t i) {
        Part part;
        auto before = initial(i);
        const std::size_t made =
            dynamics::evolve(table, flight, before, collisions, [&](const auto& hit, const auto& after, const auto& flown) {
              record(i, hit, before, after, flown, part.rows);
              before = after;
            });
        part.escaped = made < collisions;
        return part;
      },
      progress);
  SectionRows out{columns, {}, std::vector<char>(particles)};
  std::vector<std::vector<double>> rows(particles);
  for (std::size_t i = 0; i < particles; ++i) rows[i] = std::move(parts[i].rows), out.escaped[i] = parts[i].escaped;
  out.rows = concatenate(rows);
  return out;
}
}  // namespace detail

/// The boundary map of `particles` particles over `collisions` bounces each (bmap_columns).
template <class Flight, class Initial>
SectionRows boundary_map(const dynamics::Table& table, const BoundaryCoordinates& coordinates, const Flight& flight,
                         const Initial& initial, std::size_t particles, std::size_t collisions, int threads,
                         double mass = 1, const std::function<void(std::size_t)>& progress = {}) {
  return detail::collect(
      table, flight, initial, particles, collisions, threads, bmap_columns.size(),
      [&](std::size_t i, const auto& hit, const auto&, const auto& after, const auto&, std::vector<double>& rows) {
        const double k = double(rows.size() / bmap_columns.size() + 1);
        rows.insert(rows.end(), {double(i), k, coordinates.s_of(table, hit), BoundaryCoordinates::p_of(after.v, hit.normal),
                                 double(after.t), dynamics::energy_of(flight, after, mass)});
      },
      progress);
}

/// The flights whose crossings of a section are found here: straight ones (in closed form), and
/// those under a uniform force, static or periodic, in 2-D and 3-D (by root finding on the
/// flight itself, below).
/// The flights of section_flight, as the CLI and the Python module name them when they refuse
/// a scene.
inline constexpr const char* section_flights_named =
    "free flights and a uniform force, static (2-D) or periodic (lab picture)";

template <class Flight>
concept section_flight =
    dynamics::is_straight<Flight> || std::is_same_v<Flight, dynamics::ConstantForceFlight> ||
    std::is_same_v<Flight, dynamics::PeriodicDriveFlight> || std::is_same_v<Flight, dynamics::PeriodicDriveFlight3>;

namespace detail {

/// The zeros of t ↦ f(t) on [a, b] where f(a) and f(b) differ in sign (f(a) < 0 ≤ f(b) or the
/// reverse), by bisection to the last bit.
template <class F>
double bisect(F&& f, double a, double b) {
  const bool rising = f(a) < 0;
  for (;;) {
    const double m = 0.5 * (a + b);
    if (!(m > a && m < b)) return b;
    ((f(m) < 0) == rising ? a : b) = m;
  }
}

/// Times in (s.t, b) at which the flight's acceleration along n may change sign: none under a
/// static force; under the periodic drive the zeros of cos θ, θ = θ_s + ω (t − s.t) from the
/// state's phase θ_s (in [0, 2π)).
template <class Flight>
std::vector<double> acceleration_turns(const Flight& flight, const typename Flight::State& s, double b) {
  std::vector<double> turns;
  if constexpr (requires { flight.omega; }) {
    const double half = geometry::pi / flight.omega;
    const double first = s.t + (geometry::pi / 2 - double(s.phase)) / flight.omega;
    for (double k = std::ceil((s.t - first) / half); first + k * half < b; ++k)
      if (first + k * half > s.t) turns.push_back(first + k * half);
  }
  return turns;
}

/// The times in (before.t, t_end] at which the flight from `before` crosses the section
/// upward.  Between the acceleration's turns, n·v is monotone, so it has at most one zero; that
/// zero splits the interval into pieces on which n·x is monotone, each crossing the section at
/// most once.  Straight flights cross once at most, found in closed form.
template <section_flight Flight>
void upward_crossings(const Flight& flight, const typename Flight::State& before, double t_end,
                      const BasicSection<Flight::State::dimension>& section, std::vector<double>& out) {
  const auto f = [&](double t) { return section.normal.dot(flight.advance(before, t).x) - section.offset; };
  if constexpr (dynamics::is_straight<Flight>) {
    const double f0 = section.normal.dot(before.x) - section.offset, f1 = f(t_end);
    if (f0 < 0 && f1 >= 0) out.push_back(before.t + (t_end - before.t) * (f0 / (f0 - f1)));
  } else {
    const auto g = [&](double t) { return section.normal.dot(flight.advance(before, t).v); };
    std::vector<double> knots{double(before.t)};
    for (const double t : acceleration_turns(flight, before, t_end)) knots.push_back(t);
    knots.push_back(t_end);
    for (std::size_t k = 0; k + 1 < knots.size(); ++k) {
      std::vector<double> pieces{knots[k]};
      if ((g(knots[k]) < 0) != (g(knots[k + 1]) < 0)) pieces.push_back(bisect(g, knots[k], knots[k + 1]));
      pieces.push_back(knots[k + 1]);
      for (std::size_t j = 0; j + 1 < pieces.size(); ++j)
        if (f(pieces[j]) < 0 && f(pieces[j + 1]) >= 0) out.push_back(bisect(f, pieces[j], pieces[j + 1]));
    }
  }
}

}  // namespace detail

/// The Poincaré section on a line (2-D, section_columns) or a plane (3-D, section3_columns),
/// over `collisions` bounces of each particle: the upward crossings of every flight, found on
/// the flight itself on its own clock (the state's t = 0 at its start), their times then
/// made absolute.
template <section_flight Flight, class Initial>
SectionRows line_section(const dynamics::TableFor<Flight>& table, const Flight& flight,
                         const BasicSection<Flight::State::dimension>& section, const Initial& initial,
                         std::size_t particles, std::size_t collisions, int threads, double mass = 1,
                         const std::function<void(std::size_t)>& progress = {}) {
  constexpr int D = Flight::State::dimension;
  const auto basis = section.basis();
  const std::size_t columns = D == 2 ? section_columns.size() : section3_columns.size();
  return detail::collect(
      table, flight, initial, particles, collisions, threads, columns,
      [&](std::size_t i, const auto&, const auto& before, const auto&, const auto& flown, std::vector<double>& rows) {
        auto start = before;
        start.t = 0;
        std::vector<double> times;
        detail::upward_crossings(flight, start, double(flown.duration), section, times);
        for (const double tau : times) {
          const auto at = flight.advance(start, tau);
          const double k = double(rows.size() / columns + 1);
          rows.push_back(double(i));
          rows.push_back(k);
          for (const auto& e : basis) rows.push_back(e.dot(at.x));
          for (const auto& e : basis) rows.push_back(e.dot(at.v) / at.v.norm());
          rows.push_back(flown.start.after(tau));
          rows.push_back(dynamics::energy_of(flight, at, mass));
        }
      },
      progress);
}

/// A flight with a periodic drive: phase ω t + phase0.
template <class Flight>
concept driven_flight = requires(const Flight& f) {
  { f.omega } -> std::convertible_to<double>;
  { f.phase0 } -> std::convertible_to<double>;
};

/// The stroboscopic section of a driven flight at drive phase `phase` (strobe_columns, in 3-D
/// strobe3_columns): the state at every time t ≥ 0 with ω t + phase0 = phase (mod 2π), over
/// `collisions` bounces.  Each flight's strobe instants are found on its own clock, from the
/// drive's phase its state carries: τ with θ_s + ω τ = phase (mod 2π).
template <driven_flight Flight, class Initial>
SectionRows stroboscopic_section(const dynamics::TableFor<Flight>& table, const Flight& flight, double phase,
                                 const Initial& initial, std::size_t particles, std::size_t collisions, int threads,
                                 double mass = 1, const std::function<void(std::size_t)>& progress = {}) {
  const double period = 2 * geometry::pi / flight.omega;
  // The first strobe time ≥ 0: (phase − phase0)/ω reduced into [0, period).
  const double first = std::fmod(std::fmod((phase - flight.phase0) / flight.omega, period) + period, period);
  constexpr bool in_3d = dynamics::is_3d<Flight>;
  return detail::collect(
      table, flight, initial, particles, collisions, threads, in_3d ? strobe3_columns.size() : strobe_columns.size(),
      [&](std::size_t i, const auto&, const auto& before, const auto&, const auto& flown, std::vector<double>& rows) {
        auto start = before;
        start.t = 0;
        const double tau0 = double(dynamics::reduce_phase(dynamics::Phase(phase) - start.phase)) / flight.omega;
        for (double j = 0;; ++j) {
          const double tau = tau0 + j * period;
          if (tau >= flown.duration) break;
          const auto at = flight.advance(start, tau);
          const double t = flown.start.after(tau);
          rows.insert(rows.end(), {double(i), std::round((t - first) / period)});
          rows.insert(rows.end(), at.x.data(), at.x.data() + at.x.size());
          rows.insert(rows.end(), at.v.data(), at.v.data() + at.v.size());
          rows.insert(rows.end(), {t, dynamics::energy_of(flight, at, mass)});
        }
      },
      progress);
}

}  // namespace billiards::analysis
