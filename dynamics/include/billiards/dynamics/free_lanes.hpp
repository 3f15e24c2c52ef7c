// The lock-step search of straight flights (free_lockstep.hpp): its plain data, what the kernel
// (src/free_lanes_kernel.cpp) reads and writes, and nothing it could share with the rest of the
// program (see lockstep_lanes.hpp for why).
#pragma once

#include <cstdint>

namespace billiards::dynamics::free_lanes {

/// Flights searched together, one per lane (two AVX-512 vectors, four AVX2 or eight SSE4:
/// independent chains that hide each other's latency), and the most walls of a kind.
inline constexpr int lanes = 16;
inline constexpr int max_walls = 24;

/// A segment wall (BasicSegmentWall's fields).
struct Segment {
  double ax, ay, nx, ny, dir_x, dir_y, slack, span_tol;
};
/// A circular arc wall (BasicArcWall's fields); `half`: at most half a circle.
struct Arc {
  double cx, cy, r, r2, near, span_tol, from_x, from_y, to_x, to_y;
  bool focusing, full, half;
};
/// What the contacts of the segments and arcs read (segment_contact, arc_contact), field by
/// field (entry i: wall i of the kind), for the kernels' table lookups by each lane's wall.
struct alignas(64) ContactColumns {
  double ax[max_walls], ay[max_walls], nx[max_walls], ny[max_walls], dir_x[max_walls], dir_y[max_walls],
      bx[max_walls], by[max_walls];                                                      // segments
  double cx[max_walls], cy[max_walls], r[max_walls], r2[max_walls], slack[max_walls];  // arcs
  std::uint64_t focusing = 0;                                                           // bit i: arc i
};
/// An elliptic arc wall (BasicEllipticArcWall's fields): the map u = L (x − c) and the unit
/// arc it takes the wall to.
struct Ellipse {
  double cx, cy, l00, l01, l10, l11;
  Arc unit;
};
/// The cells that lie wholly inside of a table's fine classes (table.hpp's
/// BasicTable::fine_classes), as bits (bit j of inside[w]: cell 64 w + j): a point in one is
/// inside at a lookup, as Table::contains answers there.  None (nx = ny = 0) when the grid
/// has more cells.
struct Cells {
  static constexpr int max_words = 1060;  // (256 × 256 cells, or 260 where a side rounds up)
  double origin_x = 0, origin_y = 0, inverse_x = 0, inverse_y = 0, nx = 0, ny = 0;
  std::int64_t inside[max_words] = {};
};
/// The segments, arcs and elliptic arcs of a table, and its cells inside.
struct Walls {
  Segment segments[max_walls];
  Arc arcs[max_walls];
  Ellipse ellipses[max_walls];
  int segment_count = 0, arc_count = 0, ellipse_count = 0;
  ContactColumns contacts{};
  Cells cells{};
};

/// A face of a convex polyhedron (PlaneWall's fields).
struct Plane {
  double nx, ny, nz, offset, slack;
};
/// A sphere (SphereWall's fields; near = 2 r × slack).
struct Sphere {
  double cx, cy, cz, r, r2, near;
  bool focusing;
};
/// The planes and spheres of a 3-D table without a mesh.
struct Walls3 {
  Plane planes[max_walls];
  Sphere spheres[max_walls];
  int plane_count = 0, sphere_count = 0;
};

/// The flights, lane by lane: the state (position, velocity, time, |v|²) and horizon.
struct alignas(64) Rays {
  double x[lanes], y[lanes], vx[lanes], vy[lanes], t[lanes], vv[lanes], t_end[lanes];
};
/// The same for 3-D flights.
struct alignas(64) Rays3 {
  double x[lanes], y[lanes], z[lanes], vx[lanes], vy[lanes], vz[lanes], t[lanes], vv[lanes], t_end[lanes];
};

/// What the search found, lane by lane: the first wall's time (t_end: none), kind
/// (wall_kind::segment, arc or elliptic_arc; in 3-D wall_kind3::plane or sphere; −1: none) and
/// index; or `handed_back`: a circle's or a sphere's discriminant the filter could not sign,
/// for the scalar search to decide exactly.  Where `made` (2-D segments and arcs, by the
/// kernels of eight lanes), the hit's position (x, y) and the wall's contact point and normal
/// there, as `collision` makes them.
struct alignas(64) Hits {
  double t[lanes];
  std::int64_t kind[lanes], index[lanes];
  std::int64_t handed_back[lanes];  // −1 (true) or 0
  std::int64_t made[lanes];         // −1 (true) or 0
  double x[lanes], y[lanes], point_x[lanes], point_y[lanes], normal_x[lanes], normal_y[lanes];
};

/// The particles of a free 2-D ensemble kept in the lanes across their collisions
/// (run_in_lockstep), lane by lane: the flight (its t 0, its horizon never), the run's clock at
/// its start (state.hpp's Clock: hi + lo), the speed² the bounces restore, the next record
/// (its index into Records::times, count: none left or a lane without a particle, and its
/// time), the particle's energies (one per record time) and the bounces made in the lanes since
/// the particle was last loaded.
struct alignas(64) Particles {
  Rays rays;
  double clock_hi[lanes], clock_lo[lanes], v2[lanes], record_at[lanes];
  std::int64_t record[lanes], bounces[lanes];
  double* energies[lanes];
};
/// The record times of a run (RunOptions::record_times and +∞ after them: count + 1 entries)
/// and ½m, by which the energy ½m|v|² is recorded.
struct Records {
  const double* times;
  std::int64_t count;
  double half_mass;
};

/// The kernels, as compiled for one SIMD target: 2-D and 3-D.
using Kernel = void (*)(const Walls& walls, const Rays& rays, Hits& hits);
using Kernel3 = void (*)(const Walls3& walls, const Rays3& rays, Hits& hits);
/// The first hits of the particles' flights and, in each lane whose hit is a segment's or an
/// arc's, of a flight of nonzero time, the particle's records and bounce as
/// Trajectory::advance_to makes them: the energy at each record time the flight reaches whose
/// position is in a cell inside (`Cells`), then the position, reflection, restored speed,
/// clock, one bounce more.  Returns the lanes left to the scalar code (bit i: lane i), whose
/// particles are at the start of their flights, with the records taken so far, and whose hits
/// are in `hits`: those the propagator does not bounce, those past their last record time and
/// those that reach a record time in a cell a wall comes near.
using Propagator = std::uint32_t (*)(const Walls& walls, const Records& records, Particles& particles, Hits& hits);
/// The kernels compiled for a SIMD target (simd.hpp); nullptr for simd::scalar.
Kernel kernel_of(std::int64_t target);
Kernel3 kernel3_of(std::int64_t target);
Propagator propagator_of(std::int64_t target);

}  // namespace billiards::dynamics::free_lanes
