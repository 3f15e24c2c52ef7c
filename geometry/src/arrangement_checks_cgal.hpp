// The exact checks of validation on one CGAL arrangement, generic in the traits class (see
// validate_cgal.cpp for the model and the algorithm).  `Traits` is an
// Arr_consolidated_curve_data_traits_2 whose curve data is the piece's number.
#pragma once

#include "validate_parts.hpp"

#include <CGAL/Arrangement_2.h>

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <vector>

namespace billiards::geometry::validation {

template <class Traits>
struct ArrangementChecks {
  using Arrangement = CGAL::Arrangement_2<Traits>;
  using XCurve = typename Traits::X_monotone_curve_2;
  using Point = typename Traits::Point_2;

  static Vec2 to_vec(const Point& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y())}; }

  /// All pieces in one arrangement, each curve tagged with its index in `ids`; `curve(piece,
  /// number)` makes the traits' curve of a piece.
  template <class ToCurve>
  static Arrangement arrangement_of(const Region2& r, std::vector<PieceId>& ids, ToCurve curve) {
    std::vector<typename Traits::Curve_2> curves;
    for (int k = 0; k < loop_count(r); ++k)
      for (int i = 0; i < int(loop_of(r, k).pieces.size()); ++i) {
        curves.push_back(curve(loop_of(r, k).pieces[i], int(ids.size()), loop_of(r, k).where[i]));
        ids.push_back({k, i});
      }
    Arrangement arr;
    CGAL::insert(arr, curves.begin(), curves.end());
    return arr;
  }

  static void check_no_overlap(const Region2& r, const Arrangement& arr, const std::vector<PieceId>& ids) {
    for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
      const auto& data = e->curve().data();
      if (data.size() < 2) continue;
      const int a = *data.begin(), b = *std::next(data.begin());
      fail_meeting(r, ids[a], ids[b],
                   fmt::format("overlap from {} to {}", text(to_vec(e->curve().left())),
                               text(to_vec(e->curve().right()))));
    }
  }

  /// Every vertex lies on one piece (CGAL's split of an arc into x-monotone parts) or is the
  /// joint of two consecutive pieces.
  static void check_vertices(const Region2& r, const Arrangement& arr, const std::vector<PieceId>& ids, double tol) {
    for (auto v = arr.vertices_begin(); v != arr.vertices_end(); ++v) {
      std::vector<int> at;  // the pieces through v
      auto he = v->incident_halfedges();
      const auto first = he;
      do {
        const auto& data = he->curve().data();
        at.insert(at.end(), data.begin(), data.end());
      } while (++he != first);
      std::sort(at.begin(), at.end());
      at.erase(std::unique(at.begin(), at.end()), at.end());
      const Vec2 q = to_vec(v->point());
      for (std::size_t i = 0; i < at.size(); ++i)
        for (std::size_t j = i + 1; j < at.size(); ++j)
          if (!is_joint(r, ids[at[i]], ids[at[j]], q, tol))
            fail_meeting(r, ids[at[i]], ids[at[j]], "cross or touch at " + text(q));
    }
  }

  /// Whether p, which is on no curve of the loop, is inside it: parity of the loop's crossings
  /// with the upward vertical ray from p, exact.  A curve counts when p.x ∈ [left.x, right.x),
  /// so a ray through a vertex counts it once, or twice where the loop turns back.
  static bool inside(const Point& p, const std::vector<XCurve>& loop) {
    const Traits traits;
    const auto compare_x = traits.compare_x_2_object();
    const auto compare_y_at_x = traits.compare_y_at_x_2_object();
    bool in = false;
    for (const XCurve& c : loop) {
      if (traits.is_vertical_2_object()(c)) continue;
      if (compare_x(traits.construct_min_vertex_2_object()(c), p) != CGAL::LARGER &&
          compare_x(p, traits.construct_max_vertex_2_object()(c)) == CGAL::SMALLER &&
          compare_y_at_x(p, c) == CGAL::SMALLER)
        in = !in;
    }
    return in;
  }

  static void check_nesting(const Region2& r, const Arrangement& arr, const std::vector<PieceId>& ids) {
    std::vector<std::vector<XCurve>> curves(loop_count(r));
    std::vector<Point> on(loop_count(r));  // a point on each loop
    for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
      const int k = ids[*e->curve().data().begin()].loop;
      curves[k].push_back(e->curve());
      on[k] = e->source()->point();
    }
    for (int k = 1; k < loop_count(r); ++k) {
      const SourceRef& at = loop_of(r, k).origin;
      if (!inside(on[k], curves[0])) fail(at, "the hole is not inside the outer boundary");
      for (int g = 1; g < loop_count(r); ++g)
        if (g != k && inside(on[k], curves[g]))
          fail(at, fmt::format("the hole lies inside the hole at line {}", loop_of(r, g).origin.line));
    }
  }

  /// Overlaps, then crossings, then orientation (which needs simple loops), then nesting (which
  /// needs disjoint loops).
  template <class ToCurve>
  static void run(const Region2& r, double tol, ToCurve curve) {
    std::vector<PieceId> ids;
    const Arrangement arr = arrangement_of(r, ids, curve);
    check_no_overlap(r, arr, ids);
    check_vertices(r, arr, ids, tol);
    check_orientation(r);
    check_nesting(r, arr, ids);
  }
};

}  // namespace billiards::geometry::validation
