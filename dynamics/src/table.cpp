#include "billiards/dynamics/table.hpp"

#include "billiards/dynamics/precision.hpp"

#include "billiards/geometry/measures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <type_traits>

namespace billiards::dynamics {

template <class Real>
BasicTable<Real>::BasicTable(const geometry::Region2& region) {
  // Each piece becomes a wall of the kind built from it, keeping its source line.
  int count = 0;
  for (const geometry::Loop* loop : region.loops()) {
    for (std::size_t i = 0; i < loop->pieces.size(); ++i) {
      std::visit([&](const auto& piece) {
        this->for_each_kind([&]<class W>(const Walls<W>&, int kind) {
          if constexpr (std::is_constructible_v<W, decltype(piece)>) {
            auto& walls = this->template mutable_walls<W>();
            const WallId id{kind, int(walls.size())};
            walls.emplace_back(piece);
            sources_[kind].push_back(loop->where[i]);
            pieces_[kind].push_back(count++);
            boxes_.emplace_back(id, geometry::bounding_box(loop->pieces[i]));
          }
        });
      }, loop->pieces[i]);
    }
  }
  const auto m = geometry::measures_of(region);
  lo_ = m.bbox_lo;
  hi_ = m.bbox_hi;
  tolerance_ = 1e-9 * (hi_ - lo_).maxCoeff();
  if (wall_count() > grid_threshold) build_grid();
  if constexpr (std::is_floating_point_v<Real>) build_classes();  // (reference tables test exactly)
}

template <class Real>
int BasicTable<Real>::Classes::cell_of(const Vec2& p) const {
  const Vec2 u = (p - origin).cwiseProduct(inverse_cell);
  if (!(u.x() >= 0 && u.y() >= 0 && u.x() < nx && u.y() < ny)) return -1;  // (NaN too)
  return int(u.y()) * nx + int(u.x());
}

template <class Real>
int BasicTable<Real>::Classes::of(const Vec2& p) const {
  const int i = cell_of(p);
  return i < 0 ? int(mixed) : int(cell[i]);
}

template <class Real>
bool BasicTable<Real>::contains(const V& p) const {
  if constexpr (std::is_floating_point_v<Real>) {
    if (const int c = fine_classes_.of(p.template cast<double>()); c != Classes::mixed) return c == Classes::inside;
  }
  return contains(p, tolerance_);
}

template <class Real>
bool BasicTable<Real>::certainly_contains(const V& p, const V& q) const {
  if constexpr (std::is_floating_point_v<Real>) {
    const int i = classes_.cell_of(p.template cast<double>()), j = classes_.cell_of(q.template cast<double>());
    if (i < 0 || j < 0) return false;
    if (i == j) return classes_.cell[i] == Classes::inside;
    // Cells next to each other, sideways or across a corner: the block of (two or four) cells
    // they span is a rectangle, convex, and holds the segment.  (A drive's oscillation
    // segment at ω = 10π is a third of a cell of the clover long: it crosses into a
    // neighbouring cell at every other check.)
    const int nx = classes_.nx, ix = i % nx, iy = i / nx, jx = j % nx, jy = j / nx;
    if (std::abs(ix - jx) > 1 || std::abs(iy - jy) > 1) return false;
    const auto inside = [&](int x, int y) { return classes_.cell[std::size_t(y) * nx + x] == Classes::inside; };
    return inside(ix, iy) && inside(jx, jy) && inside(ix, jy) && inside(jx, iy);
  }
  return false;
}

template <class Real>
void BasicTable<Real>::build_classes() {
  // 64 cells along the longer side: 90-93% of the bounding box of every bundled shape falls in
  // unmixed cells (test_geometry), where the test costs a lookup instead of a crossing count
  // over every wall.
  const Vec2 size = hi_ - lo_;
  const double h = size.maxCoeff() / 64;
  classes_.nx = std::max(1, int(std::ceil(size.x() / h)));
  classes_.ny = std::max(1, int(std::ceil(size.y() / h)));
  classes_.origin = lo_;
  classes_.inverse_cell = Vec2(classes_.nx / size.x(), classes_.ny / size.y());
  classes_.cell_size = Vec2(size.x() / classes_.nx, size.y() / classes_.ny);
  classes_.cell.assign(std::size_t(classes_.nx) * classes_.ny, Classes::mixed);
  for (int j = 0; j < classes_.ny; ++j)
    for (int i = 0; i < classes_.nx; ++i) classes_.cell[std::size_t(j) * classes_.nx + i] = class_of_cell(classes_, i, j);
  fine_classes_ = grid() ? classes_ : refined_classes(fine_refinement);
}

template <class Real>
signed char BasicTable<Real>::class_of_cell(const Classes& classes, int i, int j) const {
  const Vec2& cell = classes.cell_size;
  const V centre = (classes.origin + cell.cwiseProduct(Vec2(i + 0.5, j + 0.5))).template cast<Real>();
  if (!(wall_distance(centre) > cell.norm() / 2 + 2 * tolerance_)) return Classes::mixed;
  return contains(centre, tolerance_) ? Classes::inside : Classes::outside;
}

template <class Real>
typename BasicTable<Real>::Classes BasicTable<Real>::refined_classes(int factor) const {
  Classes fine = classes_;
  fine.nx *= factor, fine.ny *= factor;
  const Vec2 size = hi_ - lo_;
  fine.inverse_cell = Vec2(fine.nx / size.x(), fine.ny / size.y());
  fine.cell_size = Vec2(size.x() / fine.nx, size.y() / fine.ny);
  fine.cell.assign(std::size_t(fine.nx) * fine.ny, Classes::mixed);
  for (int j = 0; j < fine.ny; ++j)
    for (int i = 0; i < fine.nx; ++i) {
      const signed char coarse = classes_.cell[std::size_t(j / factor) * classes_.nx + i / factor];
      fine.cell[std::size_t(j) * fine.nx + i] = coarse == Classes::mixed ? class_of_cell(fine, i, j) : coarse;
    }
  return fine;
}

template <class Real>
bool BasicTable<Real>::contains(const V& p, double tolerance) const {
  // (At tolerance 0 the bound leaves no room for rounding: the distance decides alone.)
  auto near = [&](const auto& w) {
    return (tolerance == 0 || w.may_be_near(p, tolerance)) && w.distance(p) <= tolerance;
  };
  int winding = 0;
  const bool on_wall = any_kind([&](const auto& walls, int) {
    for (const auto& w : walls) {
      if (near(w)) return true;
      winding += w.crossings(p);
    }
    return false;
  });
  return on_wall || winding != 0;
}

template <class Real>
Real BasicTable<Real>::wall_distance(const V& p) const {
  using std::min;
  Real d = std::numeric_limits<double>::infinity();
  for_each_kind([&](const auto& walls, int) {
    for (const auto& w : walls) d = min(d, w.distance(p));
  });
  return d;
}

template <class Real>
void BasicTable<Real>::build_grid() {
  // About two walls per cell along the boundary: n walls spread over ~√n cells per side.
  const Vec2 size = hi_ - lo_;
  const double cells = 2.0 * double(wall_count());
  const double h = std::sqrt(size.x() * size.y() / cells);
  grid_.nx = std::clamp(int(std::ceil(size.x() / h)), 1, 4096);
  grid_.ny = std::clamp(int(std::ceil(size.y() / h)), 1, 4096);
  grid_.cell = Vec2(size.x() / grid_.nx, size.y() / grid_.ny);
  grid_.origin = lo_;
  std::vector<std::vector<WallId>> lists(std::size_t(grid_.nx) * grid_.ny);
  for (const auto& [id, box] : boxes_) {
    // Pad by the span slack so walls touching a cell edge are listed on both sides.
    const Vec2 pad = Vec2::Constant(tolerance_);
    const Vec2 a = (box.first - pad - lo_).cwiseQuotient(grid_.cell);
    const Vec2 b = (box.second + pad - lo_).cwiseQuotient(grid_.cell);
    for (int i = std::max(0, int(a.x())); i <= std::min(grid_.nx - 1, int(b.x())); ++i)
      for (int j = std::max(0, int(a.y())); j <= std::min(grid_.ny - 1, int(b.y())); ++j)
        lists[std::size_t(j) * grid_.nx + i].push_back(id);
  }
  grid_.start.push_back(0);
  for (const auto& l : lists) {
    grid_.walls.insert(grid_.walls.end(), l.begin(), l.end());
    grid_.start.push_back(int(grid_.walls.size()));
  }
}

template class BasicTable<double>;
template class BasicTable<long double>;
template class BasicTable<Reference>;

}  // namespace billiards::dynamics
