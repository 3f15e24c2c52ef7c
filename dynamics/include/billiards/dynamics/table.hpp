// The billiard table as the dynamics sees it: the region's walls prepared for fast queries,
// kept by kind in contiguous storage, a uniform grid over them when there are many, and an
// independent point-in-region test.  Every algorithm over the walls goes through
// `for_each_kind` (all walls, kind by kind: one loop per kind, no dispatch per wall) or
// `visit` (one wall by its WallId), so a new wall kind is one more entry in `WallKinds`.
// The walls' scalar type is a parameter (table.cpp instantiates double, long double and
// precision.hpp's Reference); the grid and the bounding box are in double.
#pragma once

#include "billiards/dynamics/state.hpp"
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
class BasicTable {
 public:
  using V = Vec2T<Real>;
  using Kinds = WallKinds<Real>;
  static constexpr std::size_t kind_count = std::tuple_size_v<Kinds>;
  template <std::size_t k>
  using Kind = std::tuple_element_t<k, Kinds>;
  static_assert(std::is_same_v<Kind<wall_kind::segment>, BasicSegmentWall<Real>> &&
                std::is_same_v<Kind<wall_kind::arc>, BasicArcWall<Real>> &&
                std::is_same_v<Kind<wall_kind::elliptic_arc>, BasicEllipticArcWall<Real>>);
  /// Tables with more walls than this get a uniform grid for straight flights.
  static constexpr std::size_t grid_threshold = 24;

  explicit BasicTable(const geometry::Region2& region);

  /// The walls of one kind.
  template <class W>
  const std::vector<W>& walls() const { return std::get<std::vector<W>>(walls_); }
  const std::vector<BasicSegmentWall<Real>>& segments() const { return walls<BasicSegmentWall<Real>>(); }
  const std::vector<BasicArcWall<Real>>& arcs() const { return walls<BasicArcWall<Real>>(); }
  const std::vector<BasicEllipticArcWall<Real>>& elliptic_arcs() const { return walls<BasicEllipticArcWall<Real>>(); }
  std::size_t wall_count() const { return count_; }
  /// Every wall's id, kind by kind.
  std::vector<WallId> wall_ids() const {
    std::vector<WallId> ids;
    for_each_kind([&](const auto& walls, int kind) {
      for (int i = 0; i < int(walls.size()); ++i) ids.push_back({kind, i});
    });
    return ids;
  }
  /// fn(walls, kind) for each kind's vector of walls, in the order of WallId::kind.
  template <class Fn>
  void for_each_kind(Fn&& fn) const {
    [&]<std::size_t... k>(std::index_sequence<k...>) {
      (fn(std::get<k>(walls_), int(k)), ...);
    }(std::make_index_sequence<kind_count>{});
  }
  /// fn(walls, kind) for each kind in turn until one returns true; whether one did.
  template <class Fn>
  bool any_kind(Fn&& fn) const {
    return [&]<std::size_t... k>(std::index_sequence<k...>) {
      return (fn(std::get<k>(walls_), int(k)) || ...);
    }(std::make_index_sequence<kind_count>{});
  }
  /// fn(wall) for the wall `id`; returns what fn returns.
  template <class Fn>
  decltype(auto) visit(const WallId& id, Fn&& fn) const {
    return visit_kind<0>(id, fn);
  }
  /// The point of the wall nearest p (hit points are projected: see walls.hpp), and the
  /// region's outward unit normal there.
  std::pair<V, V> contact(const WallId& wall, const V& p) const {
    return visit(wall, [&](const auto& w) { return w.contact(p); });
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
    std::vector<WallId> walls;
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
  template <std::size_t k, class Fn>
  decltype(auto) visit_kind(const WallId& id, Fn& fn) const {
    if constexpr (k + 1 == kind_count) return fn(std::get<k>(walls_)[id.index]);
    else return id.kind == int(k) ? fn(std::get<k>(walls_)[id.index]) : visit_kind<k + 1>(id, fn);
  }
  void build_grid();
  void build_classes();
  /// The walls of each kind: std::vector of each type in Kinds.
  template <class... W>
  static std::tuple<std::vector<W>...> vectors_of(std::tuple<W...>*);
  decltype(vectors_of(static_cast<Kinds*>(nullptr))) walls_;
  std::size_t count_ = 0;
  std::array<std::vector<geometry::SourceRef>, kind_count> sources_;
  std::array<std::vector<int>, kind_count> pieces_;
  std::vector<std::pair<WallId, std::pair<Vec2, Vec2>>> boxes_;  // bounding box of each wall
  Vec2 lo_, hi_;
  double tolerance_ = 0;
  Grid grid_;
  Classes classes_;
};
using Table = BasicTable<double>;

}  // namespace billiards::dynamics
