// The 2-D billiard table as the dynamics sees it: the region's walls prepared for fast
// queries, kept by kind in contiguous storage (WallSet: `for_each_kind`, `any_kind`, `visit`),
// a uniform grid over them when there are many, and an independent point-in-region test.  A
// new wall kind is one more entry in `WallKinds`.
// The walls' scalar type is a parameter (table.cpp instantiates double, long double and
// precision.hpp's Reference); the grid and the bounding box are in double.
#pragma once

#include "billiards/dynamics/state.hpp"
#include "billiards/dynamics/wall_set.hpp"
#include "billiards/dynamics/walls.hpp"
#include "billiards/geometry/pieces.hpp"

#include <array>
#include <tuple>
#include <utility>
#include <vector>

namespace billiards::dynamics {

/// The wall kinds of a 2-D table, in the order of WallId::kind.
template <class Real>
using WallKinds = std::tuple<BasicSegmentWall<Real>, BasicArcWall<Real>, BasicEllipticArcWall<Real>>;

/// WallId::kind of each wall type: its position in WallKinds.
namespace wall_kind {
inline constexpr int segment = 0, arc = 1, elliptic_arc = 2;
}

template <class Real>
class BasicTable<Real, 2> : public WallSet<WallKinds<Real>> {
  using Base = WallSet<WallKinds<Real>>;

 public:
  using V = Vec2T<Real>;
  using typename Base::Kinds;
  using Base::kind_count;
  template <std::size_t k>
  using Kind = typename Base::template Kind<k>;
  using Base::walls;
  using Base::for_each_kind;
  using Base::visit;
  using Base::any_kind;
  using Base::wall_count;
  using Base::wall_ids;
  static_assert(std::is_same_v<Kind<wall_kind::segment>, BasicSegmentWall<Real>> &&
                std::is_same_v<Kind<wall_kind::arc>, BasicArcWall<Real>> &&
                std::is_same_v<Kind<wall_kind::elliptic_arc>, BasicEllipticArcWall<Real>>);
  /// Tables with more walls than this get a uniform grid for straight flights.
  static constexpr std::size_t grid_threshold = 24;

  explicit BasicTable(const geometry::Region2& region);

  const Walls<BasicSegmentWall<Real>>& segments() const { return Base::template walls<BasicSegmentWall<Real>>(); }
  const Walls<BasicArcWall<Real>>& arcs() const { return Base::template walls<BasicArcWall<Real>>(); }
  const Walls<BasicEllipticArcWall<Real>>& elliptic_arcs() const { return Base::template walls<BasicEllipticArcWall<Real>>(); }
  /// The hit point p of a flight with velocity v moved onto the wall (see walls.hpp), and the
  /// region's outward unit normal there.
  std::pair<V, V> contact(const WallId& wall, const V& p, const V& v) const {
    return visit(wall, [&](const auto& w) { return w.contact(p, v); });
  }
  V normal_at(const WallId& wall, const V& p) const {
    return visit(wall, [&](const auto& w) { return V(w.normal_at(p)); });
  }
  /// Signed curvature of the wall at p, seen from the region (> 0 focusing).
  Real curvature_at(const WallId& wall, const V& p) const {
    return visit(wall, [&](const auto& w) { return Real(w.curvature_at(p)); });
  }
  /// The source line of a wall in the shape file (for reports).
  const geometry::SourceRef& source_of(const WallId& wall) const { return sources_[wall.kind][wall.index]; }
  /// The wall's position in the shape file: its loop's pieces counted loop by loop, outer first.
  int piece_of(const WallId& wall) const { return pieces_[wall.kind][wall.index]; }

  /// Is p inside the region?  Crossing-number test, independent of the collision kernels;
  /// points within `tolerance` of a wall count as inside.  Answered at once in a cell of
  /// `fine_classes` that no wall comes near.
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
    std::vector<WallId> walls;
  };
  const Grid* grid() const { return grid_.nx ? &grid_ : nullptr; }

  /// A uniform grid over the bounding box whose cells are classified once: a cell farther from
  /// every wall than its half-diagonal and the tolerance lies wholly inside or wholly outside
  /// (no wall crosses it), as its centre does; the others are mixed.
  struct Classes {
    enum : signed char { outside = 0, inside = 1, mixed = -1 };
    Vec2 origin, inverse_cell, cell_size;  // lower corner, 1 / cell size and cell size
    int nx = 0, ny = 0;
    std::vector<signed char> cell;
    int cell_of(const Vec2& p) const;  // the index of p's cell; −1 outside the grid
    int of(const Vec2& p) const;       // the class of p's cell; mixed outside the grid
  };
  const Classes& classes() const { return classes_; }
  /// The classes refined `fine_refinement` times in a table without a grid (the cells of an
  /// inside or an outside cell keep its class, those of a mixed one are classified as a cell
  /// of `classes` is), where `contains` looks a point up: the cells a wall comes near cover a
  /// quarter of the area they do in `classes`.  With a grid, `classes` itself.  (A segment is
  /// looked up in `classes`, whose cells hold a drive's oscillation segment whole more often.)
  const Classes& fine_classes() const { return fine_classes_; }
  static constexpr int fine_refinement = 4;

 private:
  void build_grid();
  void build_classes();
  /// The class of cell (i, j) of a grid of `classes`' shape: its centre's where no wall comes
  /// within its half-diagonal and twice the tolerance, else mixed.
  signed char class_of_cell(const Classes& classes, int i, int j) const;
  Classes refined_classes(int factor) const;
  std::array<std::vector<geometry::SourceRef>, kind_count> sources_;
  std::array<std::vector<int>, kind_count> pieces_;
  std::vector<std::pair<WallId, std::pair<Vec2, Vec2>>> boxes_;  // bounding box of each wall
  Vec2 lo_, hi_;
  double tolerance_ = 0;
  Grid grid_;
  Classes classes_, fine_classes_;
};
using Table = BasicTable<double>;

}  // namespace billiards::dynamics
