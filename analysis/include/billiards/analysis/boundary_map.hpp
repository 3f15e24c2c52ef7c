// The boundary map of a 2-D table in Birkhoff coordinates (s, p), and the two sections of the
// flow beside it: a Poincaré section on a line, and the stroboscopic section of a driven scene.
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
#include "billiards/geometry/pieces.hpp"

#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <optional>
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

/// A line n·x = c of the plane, n a unit vector: a Poincaré section.  A crossing counts when the
/// particle goes from n·x < c to n·x > c; its coordinates are u = d·x along the line and
/// p = d·v/|v|, d = (−n_y, n_x).
struct SectionLine {
  Vec2 normal;
  double offset = 0;
  Vec2 direction() const { return {-normal.y(), normal.x()}; }
};

/// Rows of `bmap.npy`: particle, collision (1, 2, ...), s, p, t, energy (after the bounce).
inline constexpr std::array<const char*, 6> bmap_columns{"particle", "collision", "s", "p", "t", "energy"};
/// Rows of a line section: particle, crossing (1, 2, ...), u, p, t, energy.
inline constexpr std::array<const char*, 6> section_columns{"particle", "crossing", "u", "p", "t", "energy"};
/// Rows of a stroboscopic section: particle, period k (t = (PHASE − phase0 + 2πk)/ω), x, y, vx,
/// vy, t, energy.
inline constexpr std::array<const char*, 8> strobe_columns{"particle", "k", "x", "y", "vx", "vy", "t", "energy"};

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
/// Runs every particle for `collisions` bounces, `record(i, hit, before, after, rows)`
/// appending its rows; collects them in particle order.
template <class Flight, class Initial, class Record>
SectionRows collect(const dynamics::Table& table, const Flight& flight, const Initial& initial, std::size_t particles,
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
        const std::size_t made = dynamics::evolve(table, flight, before, collisions, [&](const auto& hit, const auto& after) {
          record(i, hit, before, after, part.rows);
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
      [&](std::size_t i, const auto& hit, const auto&, const auto& after, std::vector<double>& rows) {
        const double k = double(rows.size() / bmap_columns.size() + 1);
        rows.insert(rows.end(), {double(i), k, coordinates.s_of(table, hit), BoundaryCoordinates::p_of(after.v, hit.normal),
                                 double(after.t), dynamics::energy_of(flight, after, mass)});
      },
      progress);
}

/// The Poincaré section of free flights on a line (section_columns), over `collisions`
/// bounces of each particle: a straight flight crosses the line at most once between bounces.
template <class Initial>
SectionRows line_section(const dynamics::Table& table, const dynamics::FreeFlight& flight, const SectionLine& line,
                         const Initial& initial, std::size_t particles, std::size_t collisions, int threads,
                         double mass = 1, const std::function<void(std::size_t)>& progress = {}) {
  return detail::collect(
      table, flight, initial, particles, collisions, threads, section_columns.size(),
      [&](std::size_t i, const auto& hit, const auto& before, const auto&, std::vector<double>& rows) {
        const double f0 = line.normal.dot(before.x) - line.offset, f1 = line.normal.dot(hit.point) - line.offset;
        if (!(f0 < 0 && f1 >= 0)) return;
        const double t = before.t + (hit.t - before.t) * (f0 / (f0 - f1));
        const auto at = flight.advance(before, t);
        const double k = double(rows.size() / section_columns.size() + 1);
        rows.insert(rows.end(), {double(i), k, line.direction().dot(at.x), line.direction().dot(at.v) / at.v.norm(),
                                 t, dynamics::energy_of(flight, at, mass)});
      },
      progress);
}

/// A flight with a periodic drive: phase ω t + phase0.
template <class Flight>
concept driven_flight = requires(const Flight& f) {
  { f.omega } -> std::convertible_to<double>;
  { f.phase0 } -> std::convertible_to<double>;
};

/// The stroboscopic section of a driven flight at drive phase `phase` (strobe_columns): the
/// state at every time t ≥ 0 with ω t + phase0 = phase (mod 2π), over `collisions` bounces.
template <driven_flight Flight, class Initial>
SectionRows stroboscopic_section(const dynamics::Table& table, const Flight& flight, double phase,
                                 const Initial& initial, std::size_t particles, std::size_t collisions, int threads,
                                 double mass = 1, const std::function<void(std::size_t)>& progress = {}) {
  const double period = 2 * geometry::pi / flight.omega;
  // The first strobe time ≥ 0: (phase − phase0)/ω reduced into [0, period).
  const double first = std::fmod(std::fmod((phase - flight.phase0) / flight.omega, period) + period, period);
  return detail::collect(
      table, flight, initial, particles, collisions, threads, strobe_columns.size(),
      [&](std::size_t i, const auto& hit, const auto& before, const auto&, std::vector<double>& rows) {
        for (double k = std::ceil((before.t - first) / period);; ++k) {
          const double t = first + k * period;
          if (t < before.t) continue;
          if (t >= hit.t) break;
          const auto at = flight.advance(before, t);
          rows.insert(rows.end(), {double(i), k, at.x.x(), at.x.y(), at.v.x(), at.v.y(), t,
                                   dynamics::energy_of(flight, at, mass)});
        }
      },
      progress);
}

}  // namespace billiards::analysis
