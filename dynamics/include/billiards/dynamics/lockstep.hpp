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
// The kernel is compiled twice, for AVX-512 (two registers of eight doubles hold the sixteen
// particles), chosen at run time on processors that have it, and without it (plain x86-64 or
// any other processor), which the tests compare with the scalar search everywhere (too slow to
// use: GCC emulates the lanes); it shares no inline function with the rest of the program, so
// that no AVX-512 code can reach a processor without it.
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/lockstep_lanes.hpp"

namespace billiards::dynamics {

namespace lockstep {

/// Does this processor have AVX-512 (F and DQ)?
bool has_avx512();
/// The kernel that ensembles use: AVX-512 where the processor has it, else none (the scalar
/// search: the baseline kernel's lanes, emulated, are 7× slower than it).  The
/// environment variable BILLIARDS_LOCKSTEP overrides the choice: auto, avx512, baseline (for
/// tests) or scalar (for benchmarks).
Kernel chosen_kernel();

}  // namespace lockstep

/// A table whose driven flights can be searched in lock step (arcs only, at most
/// lockstep::max_arcs of them), ready for `collisions`.
class LockstepTable {
 public:
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
  const Table* table_;
  const PeriodicDriveFlight* flight_;
  lockstep::Kernel kernel_;
  lockstep::Arcs arcs_;
  lockstep::Drive drive_;
  lockstep::Cells cells_;
  bool usable_ = false;
};

}  // namespace billiards::dynamics
