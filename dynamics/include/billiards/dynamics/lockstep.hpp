// Driven flights searched in lock step: the next collisions of several particles at once, one
// particle per SIMD lane (internal to dynamics: the ensembles of driven flights use it).
//
// One driven collision is a chain of ~3 000 dependent instructions — square roots, divisions,
// a sine and a cosine, and a dozen unpredictable branches — that the processor cannot overlap
// with the next particle's (BENCHMARKS.md).  Here the search of `collision` (the walls' windows,
// the sign of f' and the span test in each, the bracketed Halley iteration) runs for `lanes`
// particles at once, branches replaced by selections.  Lane by lane it performs the same IEEE
// operations in the same order as the scalar search (scan::first_hit_in_windows), so the
// collisions, and the trajectories, are bit for bit the same; a lane that needs anything else
// (a guide that creeps or stands still, a window where the sign of f' is uncertain, an
// iteration that stalls, a phase beyond the fast sine) is handed back to the scalar search.
//
// The kernel is written once over packs of lanes and compiled by Google Highway for each SIMD
// target (SSE4, AVX2 and AVX-512 on x86-64, and `generic`, plain C++, anywhere), one chosen at
// run time: each holds the lanes in its own registers (sixteen on AVX-512, eight elsewhere)
// and performs the same operations, so every target finds the same collisions as the scalar
// search.
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/lockstep_lanes.hpp"
#include "billiards/dynamics/simd.hpp"

#include <cstdint>
#include <vector>

namespace billiards::dynamics {

namespace lockstep {

/// The kernel compiled for a SIMD target (simd.hpp); nullptr for simd::scalar.
Kernel kernel_of(std::int64_t target);
/// The kernel that ensembles use: that of simd::chosen_target().
Kernel chosen_kernel();

}  // namespace lockstep

/// A table whose driven flights can be searched in lock step (at most
/// scan::windows_in_time_order_walls walls: the segments and arcs in groups of
/// lockstep::max_walls, one call of the kernel each, and the elliptic arcs, each searched after
/// them as DrivenScan::first_hit searches it: the mapped flight through the unit arc, in lanes
/// of its own), ready for `collisions`.
class LockstepTable {
 public:
  static constexpr int lanes = lockstep::lanes;
  /// Not `usable` when the table cannot be searched in lock step, or the kernel is none.
  LockstepTable(const Table& table, const PeriodicDriveFlight& flight,
                lockstep::Kernel kernel = lockstep::chosen_kernel());
  bool usable() const { return usable_; }
  /// hits[i] = collision(table, flight, *states[i], t_end[i]) for i < n ≤ lockstep::lanes: the
  /// same hits, bit for bit; and each hit's `midpoint_inside`, Table::certainly_contains of the
  /// flight's oscillation segment half way to the hit (Trajectory's every-flight check).
  void collisions(const DrivenState* const* states, const double* t_end, int n,
                  FlightHit<PeriodicDriveFlight>* hits) const;

 private:
  /// The hit the kernel found in lane i (it made the state there, or left it to be made).
  void lane_hit(const DrivenState& s, const lockstep::Hits& out, int i, int first,
                FlightHit<PeriodicDriveFlight>& hit) const;

  const Table* table_;
  const PeriodicDriveFlight* flight_;
  lockstep::Kernel kernel_;
  /// The segments and arcs (numbered as the scalar search numbers them: the segments first) in
  /// groups of at most lockstep::max_walls, searched as scan::first_hit_in_windows searches
  /// them; `first`, the number of a group's first wall.
  struct Group {
    lockstep::Walls walls;
    int first;
  };
  std::vector<Group> groups_;
  lockstep::Drive drive_;
  lockstep::Cells cells_;
  /// Each elliptic arc's unit arc and the drive mapped with it.
  struct Mapped {
    lockstep::Walls walls;
    lockstep::Drive drive;
  };
  std::vector<Mapped> elliptic_;
  bool usable_ = false;
};

}  // namespace billiards::dynamics
