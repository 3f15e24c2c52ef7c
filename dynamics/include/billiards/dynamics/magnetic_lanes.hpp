// The lock-step search of magnetic flights (magnetic_lockstep.hpp): its plain data, what the
// kernel (src/magnetic_lanes_kernel.cpp) reads and writes, and nothing it could share with the
// rest of the program (see lockstep_lanes.hpp for why).
#pragma once

#include "billiards/dynamics/free_lanes.hpp"

#include <cstdint>

namespace billiards::dynamics::magnetic_lanes {

/// Flights searched together, one per lane, and the most walls of a kind: as for straight
/// flights (free_lanes.hpp).
inline constexpr int lanes = free_lanes::lanes;
inline constexpr int max_walls = free_lanes::max_walls;

/// What the magnetic search reads of a wall beside its straight-flight numbers (ReachLanes,
/// magnetic_exit-inl.hpp): its bounding disk, the rounding of a distance to it, its slack.
struct Reach {
  double cx, cy, r, pad, slack;
};
/// The segments and arcs of a table, and the field: |Ω|, 1/|Ω|, and whether Ω > 0 (clockwise).
struct Walls {
  free_lanes::Walls straight;
  Reach segments[max_walls], arcs[max_walls];
  double k, inv_k;
  bool clockwise;
};

/// The flights, lane by lane: the state (position, velocity, time) and horizon.
struct alignas(64) Flights {
  double x[lanes], y[lanes], vx[lanes], vy[lanes], t[lanes], t_end[lanes];
};

/// What the search found, lane by lane: the time of the earliest outward crossing through a
/// segment or an arc within its span, if before the horizon (else the horizon), that wall's
/// kind (wall_kind::segment or arc; −1: none) and index, and the state there (position and
/// velocity as pairs: each read as one vector).
struct alignas(64) Hits {
  double t[lanes], position[2 * lanes], velocity[2 * lanes];
  std::int64_t kind[lanes], index[lanes];
};

/// The kernel, as compiled for one SIMD target.
using Kernel = void (*)(const Walls& walls, const Flights& flights, Hits& hits);
/// The kernel compiled for a SIMD target (simd.hpp); nullptr for simd::scalar.
Kernel kernel_of(std::int64_t target);

}  // namespace billiards::dynamics::magnetic_lanes
