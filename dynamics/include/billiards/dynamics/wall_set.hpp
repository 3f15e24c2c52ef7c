// The walls of a table, kept by kind in contiguous storage (one std::vector per wall type),
// and the loops over them every algorithm goes through: `for_each_kind` (all walls, kind by
// kind: one loop per kind, no dispatch per wall), `any_kind` (the same, stopping early) and
// `visit` (one wall by its WallId).  2-D and 3-D tables (table.hpp, table3.hpp) both derive
// from it, with their own list of kinds (WallKinds, WallKinds3).
#pragma once

#include "billiards/dynamics/state.hpp"

#include <cstddef>
#include <tuple>
#include <utility>
#include <vector>

namespace billiards::dynamics {

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
  const std::vector<Wall>& walls() const { return std::get<std::vector<Wall>>(walls_); }
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

 protected:
  template <class Wall>
  std::vector<Wall>& mutable_walls() { return std::get<std::vector<Wall>>(walls_); }

 private:
  template <std::size_t k, class Fn>
  decltype(auto) visit_kind(const WallId& id, Fn& fn) const {
    if constexpr (k + 1 == kind_count) return fn(std::get<k>(walls_)[id.index]);
    else return id.kind == int(k) ? fn(std::get<k>(walls_)[id.index]) : visit_kind<k + 1>(id, fn);
  }
  std::tuple<std::vector<W>...> walls_;
};

}  // namespace billiards::dynamics
