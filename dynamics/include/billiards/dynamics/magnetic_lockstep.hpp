// Magnetic flights searched in lock step: the next collisions of several particles at once, one
// particle per SIMD lane (internal to dynamics: the ensembles of magnetic flights use it).
//
// The kernel (src/magnetic_lanes_kernel.cpp) does what Gyration::first_hit does for the segments
// and arcs, with magnetic_exit-inl.hpp, the scalar search's own source, compiled for each SIMD
// target by Google Highway: the cyclotron circle, each flight's earliest outward crossing, its
// time (half_angle_of's arctangent) and the state there.  Elliptic arcs are then
// scanned one particle at a time up to that hit, as Gyration::hit_from scans them.  So the
// collisions, and the trajectories, are the scalar search's, bit for bit.
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/magnetic_flight.hpp"
#include "billiards/dynamics/magnetic_lanes.hpp"

namespace billiards::dynamics {

namespace magnetic_lanes {
/// The kernel that ensembles use: that of simd::chosen_target().
Kernel chosen_kernel();
}  // namespace magnetic_lanes

/// A table whose magnetic flights can be searched in lock step: at most
/// magnetic_lanes::max_walls segments and as many arcs.
class MagneticLockstepTable {
 public:
  static constexpr int lanes = magnetic_lanes::lanes;
  /// Not `usable` when the table has more walls of a kind, or the kernel is none.
  MagneticLockstepTable(const Table& table, const MagneticFlight& flight,
                        magnetic_lanes::Kernel kernel = magnetic_lanes::chosen_kernel());
  bool usable() const { return usable_; }
  /// hits[i] = collision(table, flight, *states[i], t_end[i]) for 0 < n ≤ lanes: the same hits,
  /// bit for bit (where none is found, the hit's time and wall only).
  void collisions(const State* const* states, const double* t_end, int n, FlightHit<MagneticFlight>* hits) const;

 private:
  const Table* table_;
  const MagneticFlight* flight_;
  magnetic_lanes::Kernel kernel_;
  magnetic_lanes::Walls walls_;
  bool usable_ = false;
};

}  // namespace billiards::dynamics
