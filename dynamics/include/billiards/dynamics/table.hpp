// The billiard table as the dynamics sees it: the region's walls prepared for fast queries,
// a uniform grid over them when there are many, and an independent point-in-region test.
// The walls' scalar type is a parameter (table.cpp instantiates double, long double and
// precision.hpp's Reference); the grid and the bounding box are in double.
#pragma once

#include "billiards/dynamics/walls.hpp"
#include "billiards/geometry/pieces.hpp"

#include <vector>

namespace billiards::dynamics {

template <class Real>
class BasicTable {
 public:
  using V = Vec2T<Real>;
  /// Tables with more walls than this get a uniform grid for straight flights.
  static constexpr std::size_t grid_threshold = 24;

  explicit BasicTable(const geometry::Region2& region);

  const std::vector<BasicSegmentWall<Real>>& segments() const { return segments_; }
  const std::vector<BasicArcWall<Real>>& arcs() const { return arcs_; }
  /// Walls are numbered segments first, then arcs.
  std::size_t wall_count() const { return segments_.size() + arcs_.size(); }
  bool is_arc(int wall) const { return wall >= int(segments_.size()); }
  V normal_at(int wall, const V& p) const;
  /// The point of the wall nearest p (hit points are projected: see walls.hpp), and the
  /// region's outward unit normal there.
  std::pair<V, V> contact(int wall, const V& p) const {
    if (is_arc(wall)) return arcs_[wall - segments_.size()].contact(p);
    return {segments_[wall].project(p), segments_[wall].normal};
  }
  /// The source line of a wall in the shape file (for reports).
  const geometry::SourceRef& source_of(int wall) const { return sources_[wall]; }

  /// Is p inside the region?  Crossing-number test, independent of the collision kernels;
  /// points within `tolerance` of a wall count as inside.  Answered at once in a cell of
  /// `classes` that no wall comes near.
  bool contains(const V& p) const;
  /// Is the whole segment [p, q] certainly inside?  True when both ends lie in one cell of
  /// `classes` classified inside, or in neighbouring cells (by a side or a corner) whose block
  /// is all inside (a cell, or a block of them, is convex); false when that cannot be told at
  /// once.
  bool certainly_contains(const V& p, const V& q) const;
  /// The same with another tolerance (0: the closed region, to the rounding of the test).
  bool contains(const V& p, double tolerance) const;
  /// Distance from p to the nearest wall.
  Real wall_distance(const V& p) const;
  double tolerance() const { return tolerance_; }
  Vec2 lo() const { return lo_; }
  Vec2 hi() const { return hi_; }

  /// Uniform grid: cell (i, j) lists the walls whose bounding boxes meet it.
  struct Grid {
    Vec2 origin, cell;  // lower corner and cell size
    int nx = 0, ny = 0;
    std::vector<int> start;  // CSR offsets, size nx*ny + 1
    std::vector<int> walls;
  };
  const Grid* grid() const { return grid_.nx ? &grid_ : nullptr; }

  /// A uniform grid over the bounding box whose cells are classified once: a cell farther from
  /// every wall than its half-diagonal and the tolerance lies wholly inside or wholly outside
  /// (no wall crosses it), as its centre does; the others are mixed.
  struct Classes {
    enum : signed char { outside = 0, inside = 1, mixed = -1 };
    Vec2 origin, inverse_cell;  // lower corner and 1 / cell size
    int nx = 0, ny = 0;
    std::vector<signed char> cell;
    int cell_of(const Vec2& p) const;  // the index of p's cell; −1 outside the grid
    int of(const Vec2& p) const;       // the class of p's cell; mixed outside the grid
  };
  const Classes& classes() const { return classes_; }

 private:
  void build_grid();
  void build_classes();
  std::vector<BasicSegmentWall<Real>> segments_;
  std::vector<BasicArcWall<Real>> arcs_;
  std::vector<geometry::SourceRef> sources_;
  std::vector<std::pair<Vec2, Vec2>> boxes_;  // bounding box of each wall
  Vec2 lo_, hi_;
  double tolerance_ = 0;
  Grid grid_;
  Classes classes_;
};
using Table = BasicTable<double>;

}  // namespace billiards::dynamics
