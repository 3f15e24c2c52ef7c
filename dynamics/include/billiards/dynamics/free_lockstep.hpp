// Straight flights searched in lock step: the next collisions of several particles at once, one
// particle per SIMD lane (internal to dynamics: the ensembles of free flights use it).
//
// The kernels (src/free_lanes_kernel.cpp) try the walls in the scalar search's order with its
// own exit times, compiled for each SIMD target by Google Highway: in 2-D the segments, arcs and
// elliptic arcs (straight_exit-inl.hpp), in 3-D the planes and spheres of a table without a mesh
// (straight_exit3-inl.hpp); so the collisions, and the trajectories, are the scalar search's,
// bit for bit.  A particle whose circle's or sphere's discriminant the filter cannot sign goes
// back to the scalar search.
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/free_lanes.hpp"
#include "billiards/dynamics/simd.hpp"
#include "billiards/dynamics/table3.hpp"

#include <cstddef>
#include <cstdint>

namespace billiards::dynamics {

namespace free_lanes {
/// The tables, walls, flights and kernel of each dimension.
template <int Dim>
struct Of;
template <>
struct Of<2> {
  using Table = dynamics::Table;
  using Walls = free_lanes::Walls;
  using Rays = free_lanes::Rays;
  using Kernel = free_lanes::Kernel;
  using Propagator = free_lanes::Propagator;
};
template <>
struct Of<3> {
  using Table = Table3;
  using Walls = Walls3;
  using Rays = Rays3;
  using Kernel = Kernel3;
  using Propagator = std::nullptr_t;  // (none: the particles leave the lanes at every hit)
};
/// The kernel that ensembles use: that of simd::chosen_target().
template <int Dim>
typename Of<Dim>::Kernel chosen_kernel();
template <>
Kernel chosen_kernel<2>();
template <>
Kernel3 chosen_kernel<3>();
/// The propagator that ensembles use: that of simd::chosen_target() (in 2-D).
template <int Dim>
typename Of<Dim>::Propagator chosen_propagator();
template <>
Propagator chosen_propagator<2>();
template <>
inline std::nullptr_t chosen_propagator<3>() { return nullptr; }
/// Are the segments and arcs few enough for the kernels' arrays (max_walls of each kind; the
/// magnetic kernel reads these two)?
bool fits(const Table& table);
/// The table's walls as the kernels read them (free_flight.hpp's views): the segments and arcs
/// (`fits`), and the elliptic arcs when they fit too.
Walls walls_of(const Table& table);
/// The planes and spheres of a 3-D table without a mesh (at most max_walls of each).
Walls3 walls_of(const Table3& table);
/// The flights as the kernels read them, lane by lane (lanes beyond n: copies of the first).
Rays rays_of(const State* const* states, const double* t_end, int n);
Rays3 rays_of(const State3* const* states, const double* t_end, int n);
/// Lane i of the particles kept in the lanes: loaded with a particle's flight from s (its t
/// 0), its clock, speed², next record (< records.count) and energies, no bounce made yet; a
/// particle's state and clock read back; and a lane without a particle (a copy of lane j's
/// flight, which never bounces: no record left).
void load(Particles& p, int i, const State& s, const Clock& clock, double v2, const Records& records, std::int64_t record,
          double* energies);
State state_in(const Particles& p, int i);
Clock clock_in(const Particles& p, int i);
void park(Particles& p, int i, int j, const Records& records);
}  // namespace free_lanes

/// A table whose straight flights can be searched in lock step: in 2-D segments, arcs and
/// elliptic arcs without a grid (at most BasicTable::grid_threshold walls) and at most
/// max_walls of each kind, in 3-D at most max_walls planes and max_walls spheres (no mesh),
/// or a mesh, whose flights' BVH walks run together instead (Table3::collision_stream); ready
/// for `collisions`.
template <int Dim>
class BasicFreeLockstepTable {
 public:
  using TableT = typename free_lanes::Of<Dim>::Table;
  using Flight = BasicFreeFlight<double, Dim>;
  using Kernel = typename free_lanes::Of<Dim>::Kernel;
  using Propagator = typename free_lanes::Of<Dim>::Propagator;
  static constexpr int lanes = free_lanes::lanes;
  /// Not `usable` when the table is not one of those, or the kernel is none (a mesh needs none).
  BasicFreeLockstepTable(const TableT& table, const Flight& flight, Kernel kernel = free_lanes::chosen_kernel<Dim>(),
                         Propagator propagator = free_lanes::chosen_propagator<Dim>());
  bool usable() const { return usable_; }
  /// hits[i] = collision(table, flight, *states[i], t_end[i]) for 0 < n ≤ lanes: the same hits,
  /// bit for bit (where none is found, the hit's time and wall only).
  void collisions(const typename Flight::State* const* states, const double* t_end, int n, FlightHit<Flight>* hits) const;
  /// Can the particles stay in the lanes across their bounces (`propagate`: a 2-D table with a
  /// propagator)?
  bool propagates() const { return usable_ && propagator_; }
  /// The particles' next hits and, in the lanes where it can, their bounces there
  /// (free_lanes::Propagator); returns the lanes left to the caller, whose hits `hit_of` gives.
  std::uint32_t propagate(const free_lanes::Records& records, free_lanes::Particles& particles,
                          free_lanes::Hits& hits) const requires(Dim == 2) {
    return propagator_(walls_, records, particles, hits);
  }
  /// The hit of lane i of the kernel's hits `out`, for the flight from s up to t_end, as
  /// `collision` makes it (`collision` itself where the lane was handed back).
  void hit_of(const free_lanes::Hits& out, int i, const typename Flight::State& s, double t_end,
              FlightHit<Flight>& hit) const;
  /// Are the flights searched as a stream (a mesh's BVH walks, Table3::collision_stream: a lane
  /// given its next flight as soon as its hit is found) rather than a batch at a time?
  bool streams() const requires(Dim == 3) { return walks_together_; }
  /// Table3::collision_stream in `lanes` lanes (where the table `streams`).
  void collision_stream(Table3::NextFlights3 next) const requires(Dim == 3) {
    table_->collision_stream(*flight_, lanes, next);
  }

 private:
  const TableT* table_;
  const Flight* flight_;
  Kernel kernel_;
  Propagator propagator_;
  typename free_lanes::Of<Dim>::Walls walls_;
  bool walks_together_;
  bool usable_;
};
using FreeLockstepTable = BasicFreeLockstepTable<2>;
using FreeLockstepTable3 = BasicFreeLockstepTable<3>;

}  // namespace billiards::dynamics
