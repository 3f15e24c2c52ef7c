// Straight flights searched in lock step: the next collisions of several particles at once, one
// particle per SIMD lane (internal to dynamics: the ensembles of free flights use it).
//
// The kernel (src/free_lanes_kernel.cpp) tries the segments, arcs and elliptic arcs in the
// scalar search's order with straight_exit-inl.hpp's exit times, the scalar search's own
// source, compiled for each SIMD target by Google Highway; so the collisions, and the
// trajectories, are the scalar search's, bit for bit.  A particle whose circle discriminant
// the filter cannot sign goes back to the scalar search.
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/free_lanes.hpp"
#include "billiards/dynamics/simd.hpp"

namespace billiards::dynamics {

namespace free_lanes {
/// The kernel that ensembles use: that of simd::chosen_target().
Kernel chosen_kernel();
/// Are the table's walls few enough for the kernels' arrays (max_walls of each kind)?
bool fits(const Table& table);
/// The table's walls (`fits`) as the kernels read them: free_flight.hpp's views.
Walls walls_of(const Table& table);
}  // namespace free_lanes

/// A table whose straight flights can be searched in lock step: without a grid (at most
/// BasicTable::grid_threshold walls), ready for `collisions`.
class FreeLockstepTable {
 public:
  static constexpr int lanes = free_lanes::lanes;
  /// Not `usable` when the table has a grid, or the kernel is none.
  FreeLockstepTable(const Table& table, const FreeFlight& flight, free_lanes::Kernel kernel = free_lanes::chosen_kernel());
  bool usable() const { return usable_; }
  /// hits[i] = collision(table, flight, *states[i], t_end[i]) for 0 < n ≤ lanes: the same hits,
  /// bit for bit (where none is found, the hit's time and wall only).
  void collisions(const State* const* states, const double* t_end, int n, FlightHit<FreeFlight>* hits) const;

 private:
  const Table* table_;
  const FreeFlight* flight_;
  free_lanes::Kernel kernel_;
  free_lanes::Walls walls_;
  bool usable_ = false;
};

}  // namespace billiards::dynamics
