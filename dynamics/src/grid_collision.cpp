#include "billiards/dynamics/collision.hpp"

namespace billiards::dynamics::detail {

Hit grid_collision(const Table& table, const FreeFlight& flight, const State& s, double t_end) {
  const Table::Grid& g = *table.grid();
  Hit best;
  best.t = t_end;
  walk_cells(g, s.x, s.v, s.t, 0, [&](int i, int j, double, double leave) {
    const std::size_t c = std::size_t(j) * g.nx + i;
    for (int k = g.start[c]; k < g.start[c + 1]; ++k) try_wall(table, flight, s, g.walls[k], best);
    return best.t <= leave;
  });
  return best;
}

}  // namespace billiards::dynamics::detail
