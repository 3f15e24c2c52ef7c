// The walls of a table, kept by kind in contiguous storage (one std::vector per wall type),
// and the loops over them every algorithm goes through: `for_each_kind` (all walls, kind by
// kind: one loop per kind, no dispatch per wall), `any_kind` (the same, stopping early) and
// `visit` (one wall by its WallId).  The storage is on huge pages once large (a mesh's
// triangles: huge_pages.hpp).  2-D and 3-D tables (table.hpp, table3.hpp) both derive
// from it, with their own list of kinds (WallKinds, WallKinds3).
#pragma once

#include "billiards/dynamics/huge_pages.hpp"
#include "billiards/dynamics/state.hpp"

#include <array>
#include <cstddef>
#include <tuple>
#include <utility>
#include <vector>

namespace billiards::dynamics {

/// A table's walls of one kind, contiguous (on huge pages once large).
template <class Wall>
using Walls = HugePageVector<Wall>;

template <class Kinds>
class WallSet;

template <class... W>
class WallSet<std::tuple<W...>> {
 public:
  using Kinds = std::tuple<W...>;
  static constexpr std::size_t kind_count = sizeof...(W);
  template <std::size_t k>
  using Kind = std::tuple_element_t<k, Kinds>;

  /// The walls of one kind.
  template <class Wall>
  const Walls<Wall>& walls() const { return std::get<Walls<Wall>>(walls_); }
  std::size_t wall_count() const {
    return std::apply([](const auto&... v) { return (v.size() + ... + std::size_t(0)); }, walls_);
  }
  /// Every wall's id, kind by kind.
  std::vector<WallId> wall_ids() const {
    std::vector<WallId> ids;
    for_each_kind([&](const auto& walls, int kind) {
      for (int i = 0; i < int(walls.size()); ++i) ids.push_back({kind, i});
    });
    return ids;
  }
  /// fn(walls, kind) for each kind's walls, in the order of WallId::kind.
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

 protected:
  template <class Wall>
  Walls<Wall>& mutable_walls() { return std::get<Walls<Wall>>(walls_); }

 private:
  template <std::size_t k, class Fn>
  decltype(auto) visit_kind(const WallId& id, Fn& fn) const {
    if constexpr (k + 1 == kind_count) return fn(std::get<k>(walls_)[id.index]);
    else return id.kind == int(k) ? fn(std::get<k>(walls_)[id.index]) : visit_kind<k + 1>(id, fn);
  }
  std::tuple<Walls<W>...> walls_;
};

/// The walls of the kinds a search selects (`Select<W>::value`), numbered 0, 1, … kind by kind in
/// the order of WallId::kind: for a search that keeps walls of several kinds in one list (the
/// drive's windows in time order) instead of counting kinds by name.  `visit(w, fn)` calls
/// fn(wall) for the wall numbered w through a chain of comparisons unrolled over the selected
/// kinds (one comparison for two kinds), which the compiler inlines as it would a hand-written
/// test.
template <class Set, template <class> class Select>
class NumberedWalls {
 public:
  explicit NumberedWalls(const Set& set) : set_(set) {
    static_assert(has_selected_after<0>(), "NumberedWalls selects no kind");
    int n = 0;
    set.for_each_kind([&]<class W>(const Walls<W>& walls, int kind) {
      first_[kind] = n;
      if constexpr (Select<W>::value) n += int(walls.size());
    });
    count_ = n;
  }
  int count() const { return count_; }
  WallId id(int w) const { return find<0>(w, [](const auto&, const WallId& id) { return id; }); }
  template <class Fn>
  [[gnu::always_inline]] decltype(auto) visit(int w, Fn&& fn) const {
    return find<0>(w, [&](const auto& wall, const WallId&) -> decltype(auto) { return fn(wall); });
  }

 private:
  /// fn(wall, id) for the wall numbered w, searched from kind k on.
  template <std::size_t k, class Fn>
  [[gnu::always_inline]] decltype(auto) find(int w, Fn&& fn) const {
    using W = typename Set::template Kind<k>;
    if constexpr (!Select<W>::value) {
      return find<k + 1>(w, fn);
    } else {
      if constexpr (has_selected_after<k + 1>()) {
        if (w >= first_[k + 1]) return find<k + 1>(w, fn);
      }
      const int i = w - first_[k];
      return fn(set_.template walls<W>()[i], WallId{int(k), i});
    }
  }
  template <std::size_t k>
  static constexpr bool has_selected_after() {
    if constexpr (k == Set::kind_count) return false;
    else return Select<typename Set::template Kind<k>>::value || has_selected_after<k + 1>();
  }
  const Set& set_;
  std::array<int, Set::kind_count> first_{};
  int count_ = 0;
};

}  // namespace billiards::dynamics
