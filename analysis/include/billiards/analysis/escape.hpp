// Open tables: exits on the boundary and the escape times of particles through them.
//
// A shape file may list exits, each the part of one loop from one boundary point to another in
// the loop's direction (region on the left: counter-clockwise on the outer loop):
//   exits:
//     - {from: [x1, y1], to: [x2, y2]}
// A particle whose flight reaches the boundary inside an exit leaves the table there: its
// escape time is that collision's time and its collision count the bounces before.  Particles
// start microcanonically inside, or enter through the exits with the boundary measure
// cos φ ds dφ (s uniform over the exits, p = sin φ uniform in [−1, 1]).  For the entering
// ensemble the mean escape time is π V / (w v) (Kac's lemma with Santaló's formula), w the
// exits' total length, V the area, v the speed.
#pragma once

#include "billiards/analysis/boundary_map.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace billiards::analysis {

/// One exit: arc lengths `from` → `to` along its loop (wrapping past the loop's end when
/// to < from), as BoundaryCoordinates measures them.
struct ExitInterval {
  int loop = 0;
  double from = 0, to = 0;
  geometry::SourceRef where;
};

class Exits {
 public:
  Exits(const BoundaryCoordinates& coordinates, std::vector<ExitInterval> exits);
  /// Is arc length s on an exit?
  bool contains(double s) const;
  /// The exits' total length w.
  double length() const { return length_; }
  /// The arc length a fraction u ∈ [0, 1) of the way through the exits, laid end to end.
  double at_fraction(double u) const;
  const std::vector<ExitInterval>& intervals() const { return exits_; }
  bool empty() const { return exits_.empty(); }

 private:
  const BoundaryCoordinates* coordinates_;
  std::vector<ExitInterval> exits_;
  std::vector<double> lengths_;
  double length_ = 0;
};

/// The exits of a shape file (its `exits:` list, read again from `shape`'s file with its
/// parameters), validated: both ends on one loop of the boundary, the interval not empty.
/// Throws InputError naming the file and the exit's line.
std::vector<ExitInterval> read_exits(const geometry::Shape& shape, const BoundaryCoordinates& coordinates);

/// A particle entering through the exits at `speed`: s uniform over the exits, p uniform.
dynamics::State entering_state(const BoundaryCoordinates& coordinates, const Exits& exits, double speed,
                               dynamics::ParticleRng& rng);

struct EscapeRecord {
  double time = 0;               // escape time after the start (NaN if it did not leave)
  std::uint64_t collisions = 0;  // bounces off walls before leaving
  bool escaped = false;          // left through an exit within the allowed collisions
  bool lost = false;             // met no wall at all: an error of the table
};

/// Each particle's escape, following it for at most `max_collisions` bounces.
template <class Flight, class Initial>
std::vector<EscapeRecord> escape_times(const dynamics::Table& table, const BoundaryCoordinates& coordinates,
                                       const Exits& exits, const Flight& flight, const Initial& initial,
                                       std::size_t particles, std::size_t max_collisions, int threads,
                                       const std::function<void(std::size_t)>& progress = {}) {
  return for_each_particle(
      particles, threads,
      [&](std::size_t i) {
        EscapeRecord r;
        auto s = initial(i);
        const double t0 = double(s.t);
        const auto v2 = s.v.squaredNorm();
        for (std::size_t k = 0; k < max_collisions; ++k) {
          const auto hit = collision(table, flight, s);  // (by argument lookup: a flight's own overloads too)
          if (!hit.found()) return r.lost = true, r;
          if (exits.contains(coordinates.s_of(table, hit))) {
            r.time = double(hit.t) - t0;
            r.collisions = k;
            r.escaped = true;
            return r;
          }
          bounce(flight, s, hit);
          if constexpr (Flight::conserves_energy) dynamics::restore_speed(s.v, v2);
        }
        r.time = std::nan("");
        r.collisions = max_collisions;
        return r;
      },
      progress);
}

}  // namespace billiards::analysis
