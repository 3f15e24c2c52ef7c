// Open tables: exits on the boundary and the escape times of particles through them.
//
// A shape file may list exits, each the part of one loop from one boundary point to another in
// the loop's direction (region on the left: counter-clockwise on the outer loop):
//   exits:
//     - {from: [x1, y1], to: [x2, y2]}
// A particle whose flight reaches the boundary inside an exit leaves the table there: its
// escape time is that collision's time and its collision count the bounces before.  Particles
// start microcanonically inside, or enter through the exits (a scene's `initial: {through_exit:
// {energy: E}}`) with the boundary measure cos φ ds dφ (s uniform over the exits, p = sin φ
// uniform in [−1, 1]).  For the entering
// ensemble the mean escape time is π V / (w v) (Kac's lemma with Santaló's formula), w the
// exits' total length, V the area, v the speed.
//
// In 3-D an exit is a disc on a face of the table's polyhedron (box or half-spaces):
//   exits:
//     - disc: {center: [x, y, z], radius: r}
// on the face whose plane holds the centre, and within that face.  Particles enter with the
// measure cos θ dA dΩ (position uniform on the discs, cos² θ uniform); their mean escape time
// is 4 V / (A v), A the discs' total area.
#pragma once

#include "billiards/analysis/boundary_map.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry/shape_file.hpp"
#include "billiards/geometry3/shape3_file.hpp"

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

/// An exit of a 3-D table: a disc on face `face` (the plane wall WallId{plane, face}).
struct DiscExit {
  int face = 0;
  geometry3::Vec3 center, normal, e1, e2;  // normal: the face's outward normal; e1, e2 span the face
  double radius = 0;
  geometry::SourceRef where;
};

/// The exits of a 3-D table: discs on its faces.
class Exits3 {
 public:
  explicit Exits3(std::vector<DiscExit> discs) : discs_(std::move(discs)) {}
  /// Is the hit on `wall` at x inside an exit?
  bool contains(const dynamics::WallId& wall, const geometry3::Vec3& x) const;
  /// The discs' total area A.
  double area() const;
  bool empty() const { return discs_.empty(); }
  /// A particle entering through the exits at `speed` (the measure cos θ dA dΩ).
  dynamics::State3 entering_state(double speed, dynamics::ParticleRng& rng) const;

 private:
  std::vector<DiscExit> discs_;
};

/// The exits of a 3-D shape file, validated: each disc's centre on a face of the polyhedron, the
/// disc within that face.  Throws InputError naming the file and the exit's line.
std::vector<DiscExit> read_exits3(const geometry3::Shape3& shape);

/// Particle i's initial state in an open table: enter(speed, rng) with ParticleRng(seed, i) at
/// the scene's speed if the scene says `through_exit`, else the scene's own
/// (dynamics::initial_states).  The arguments must outlive the returned function.
template <class Flight, class Enter>
std::function<typename Flight::State(std::size_t)> open_table_initial_states(const dynamics::Scene& scene,
                                                                            const dynamics::TableFor<Flight>& table,
                                                                            const Flight& flight, Enter enter) {
  if (!scene.through_exit) return dynamics::initial_states(scene, table, flight);
  const double speed = std::sqrt(2 * scene.energy / scene.mass);
  return [&scene, enter, flight, speed](std::size_t i) {
    dynamics::ParticleRng rng(scene.seed, i);
    return flight.start(enter(speed, rng));
  };
}

/// The same for a 2-D table with `exits`.
template <class Flight>
std::function<typename Flight::State(std::size_t)> open_table_initial_states(const dynamics::Scene& scene,
                                                                            const dynamics::Table& table,
                                                                            const Flight& flight,
                                                                            const BoundaryCoordinates& coordinates,
                                                                            const Exits& exits) {
  return open_table_initial_states(scene, table, flight, [&coordinates, &exits](double speed, auto& rng) {
    return entering_state(coordinates, exits, speed, rng);
  });
}

struct EscapeRecord {
  double time = 0;               // escape time after the start (NaN if it did not leave)
  std::uint64_t collisions = 0;  // bounces off walls before leaving
  bool escaped = false;          // left through an exit within the allowed collisions
  bool lost = false;             // met no wall at all: an error of the table
};

/// Kac's mean escape time of particles entering at `speed` through exits of total measure
/// `exit_measure` (length in 2-D, area in 3-D) of a table of volume V: π V/(w v) in 2-D,
/// 4 V/(A v) in 3-D (the mean chord of the entering measure, Santaló's formula).
double kac_mean_escape_time(double volume, double exit_measure, double speed, int dimension);

/// The particles that left, their escape times in particle order, and their mean with its SE.
struct EscapeSummary {
  std::vector<double> times;
  double mean = 0, se = 0;   // NaN-free: 0 when fewer than two escaped
  std::size_t lost = 0;      // met no wall
  std::size_t still_inside(std::size_t particles) const { return particles - times.size() - lost; }
};
EscapeSummary summarize(const std::vector<EscapeRecord>& records);

/// The survival probability P(t), the fraction of `particles` still inside at time t, at
/// `points` + 1 equally spaced times from 0 to the last escape.
struct Survival {
  std::vector<double> t, P;
};
Survival survival(std::vector<double> escape_times, std::size_t particles, int points = 400);

/// Each particle's escape, following it for at most `max_collisions` bounces: it leaves at the
/// first hit for which leaves(hit) is true.  Any dimension.
template <class Flight, class Initial, class Leaves>
std::vector<EscapeRecord> escape_times(const dynamics::TableFor<Flight>& table, const Flight& flight,
                                       const Initial& initial, Leaves&& leaves, std::size_t particles,
                                       std::size_t max_collisions, int threads,
                                       const std::function<void(std::size_t)>& progress = {}) {
  return for_each_particle(
      particles, threads,
      [&](std::size_t i) {
        EscapeRecord r;
        auto s = initial(i);
        const double t0 = double(s.t);
        const auto v2 = s.v.squaredNorm();
        dynamics::BasicClock<typename Flight::Scalar> clock;
        dynamics::restart_clock(flight, s, clock);
        for (std::size_t k = 0; k < max_collisions; ++k) {
          const auto hit = collision(table, flight, s);  // (by argument lookup: a flight's own overloads too)
          if (!hit.found()) return r.lost = true, r;
          if (leaves(hit)) {
            r.time = double(clock.after(hit.t)) - t0;
            r.collisions = k;
            r.escaped = true;
            return r;
          }
          bounce(flight, s, hit);
          if constexpr (Flight::conserves_energy) dynamics::restore_speed(s.v, v2);
          dynamics::restart_clock(flight, s, clock);
        }
        r.time = std::nan("");
        r.collisions = max_collisions;
        return r;
      },
      progress);
}

/// The same through the exits of a 2-D table.
template <class Flight, class Initial>
std::vector<EscapeRecord> escape_times(const dynamics::Table& table, const BoundaryCoordinates& coordinates,
                                       const Exits& exits, const Flight& flight, const Initial& initial,
                                       std::size_t particles, std::size_t max_collisions, int threads,
                                       const std::function<void(std::size_t)>& progress = {}) {
  return escape_times(
      table, flight, initial, [&](const auto& hit) { return exits.contains(coordinates.s_of(table, hit)); }, particles,
      max_collisions, threads, progress);
}

}  // namespace billiards::analysis
