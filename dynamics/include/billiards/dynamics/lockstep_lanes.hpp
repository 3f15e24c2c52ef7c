// The lock-step kernel's plain data (lockstep.hpp): what it reads and writes, and nothing it
// could share with the rest of the program.  The kernel (src/lockstep_kernel.cpp) uses only
// this header and phase_constants.hpp, which have no inline function: compiled for each SIMD
// target, the kernel must not define an inline function that the linker could pick for the
// rest of the program too.
#pragma once

#include <cstdint>

namespace billiards::dynamics {

namespace lockstep {

/// Particles a call of the kernel searches, and the most walls it searches (a group of a
/// table's walls, scan::windows_group_walls: they fit in vectors, where each lane picks its
/// own).  (The kernel holds sixteen lanes in two AVX-512 registers, whose independent
/// operations interleave and hide each other's latency, and searches the sixteen particles
/// eight at a time on narrower targets, whose registers sixteen lanes would overflow; more
/// lanes only lengthen the rounds in which finished lanes wait for the rest.)
inline constexpr int lanes = 16;
inline constexpr int max_walls = 16;

/// A group of a table's segments and arcs, field by field (BasicSegmentWall's and
/// BasicArcWall's), the segments first as the scalar search numbers them, padded to
/// max_walls: each wall fills the fields of its kind.  (These structs are aligned to the
/// kernel's registers, so that no load of a field straddles two cache lines, which would cost
/// a second access on each of the kernel's loads.)
struct alignas(64) Walls {
  std::int64_t arc[max_walls];  // −1: an arc, 0: a segment
  double slack[max_walls];
  double cx[max_walls], cy[max_walls], r[max_walls], sign[max_walls];  // an arc
  double fx[max_walls], fy[max_walls], tx[max_walls], ty[max_walls];
  std::int64_t full[max_walls], half[max_walls];  // −1 (true) or 0
  double ax[max_walls], ay[max_walls], bx[max_walls], by[max_walls];  // a segment
  double nx[max_walls], ny[max_walls], dir_x[max_walls], dir_y[max_walls], dir_norm[max_walls], span_tol[max_walls];
  int count = 0, segments = 0;
  /// Whether the kernel makes the hits' states (Hits::made); not for an elliptic arc's unit
  /// arc, met by mapped flights, whose hits the caller makes in the table's frame.
  bool make_states = true;
};

/// The table's classified cells (BasicTable::Classes), for the flights' midpoint check.
struct Cells {
  double origin_x, origin_y, inverse_x, inverse_y;  // lower corner and 1 / cell size
  int nx, ny;
  const signed char* cell;  // Classes::cell: 1 inside
};

/// The drive, as the flights' Quiver sees it.
struct Drive {
  double omega, accel_x, accel_y, amp_x_x, amp_x_y, amp_v_x, amp_v_y, accel_norm, inv_omega, delta;
};

/// The flights of up to `lanes` particles, lane by lane (the kernel derives the rest of each
/// flight's Quiver as its constructor does).
struct alignas(64) Flights {
  double sx[lanes], sy[lanes];                                    // the state's position
  double vx[lanes], vy[lanes];                                    // and velocity
  double t[lanes];                                                // and time
  double phase_hi[lanes], phase_lo[lanes];                        // the drive's phase (Phase)
  double sin_phase[lanes], cos_phase[lanes];                      // and its sine and cosine
  double tau_end[lanes];                                          // the horizon, from the state's time
  std::int64_t active[lanes];                                     // −1: search this lane
};

/// What the search found, lane by lane: the first hit's τ and wall (its number in Walls; −1:
/// none before tau_end),
/// the drive's phase sampled there (theta = never: not sampled), or `handed_back`: the scalar
/// search must decide this lane.  Where `made`, also the flight's state at the hit (as
/// PeriodicDriveFlight::advance makes it from the sample) and the contact (Table::contact);
/// elsewhere the caller makes them.
struct alignas(64) Hits {
  double tau[lanes];
  int wall[lanes];
  double theta[lanes], sin[lanes], cos[lanes];
  bool handed_back[lanes];
  bool made[lanes];
  double t[lanes], x[lanes], y[lanes], vx[lanes], vy[lanes];      // the state at the hit
  double phase_hi[lanes], phase_lo[lanes], sin_phase[lanes], cos_phase[lanes];
  double point_x[lanes], point_y[lanes], normal_x[lanes], normal_y[lanes];  // the contact
  bool midpoint_inside[lanes];  // Table::certainly_contains of the oscillation segment at mid-flight
};

/// The kernel (lockstep_kernel.cpp), as compiled for one SIMD target.
using Kernel = void (*)(const Walls& walls, const Drive& drive, const Cells& cells, const Flights& flights, Hits& hits);

}  // namespace lockstep

}  // namespace billiards::dynamics
