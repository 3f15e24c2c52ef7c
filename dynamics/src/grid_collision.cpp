#include "billiards/dynamics/collision.hpp"

#include <algorithm>
#include <cmath>

namespace billiards::dynamics::detail {

Hit grid_collision(const Table& table, const FreeFlight& flight, const State& s, double t_end) {
  const Table::Grid& g = *table.grid();
  // Start in the cell of the particle (clamped: a particle on the wall may sit a hair outside).
  const Vec2 rel = (s.x - g.origin).cwiseQuotient(g.cell);
  int i = std::clamp(int(std::floor(rel.x())), 0, g.nx - 1);
  int j = std::clamp(int(std::floor(rel.y())), 0, g.ny - 1);
  const int step_i = s.v.x() > 0 ? 1 : -1, step_j = s.v.y() > 0 ? 1 : -1;
  // Time at which the flight crosses the next vertical / horizontal cell line.
  auto next_line = [&](int k, int step, double origin, double cell, double x, double v) {
    if (v == 0) return never;
    return s.t + (origin + (k + (step > 0 ? 1 : 0)) * cell - x) / v;
  };
  double tx = next_line(i, step_i, g.origin.x(), g.cell.x(), s.x.x(), s.v.x());
  double ty = next_line(j, step_j, g.origin.y(), g.cell.y(), s.x.y(), s.v.y());
  const double dtx = s.v.x() != 0 ? g.cell.x() / std::abs(s.v.x()) : never;
  const double dty = s.v.y() != 0 ? g.cell.y() / std::abs(s.v.y()) : never;

  Hit best;
  best.t = t_end;
  while (true) {
    const std::size_t c = std::size_t(j) * g.nx + i;
    for (int k = g.start[c]; k < g.start[c + 1]; ++k) try_wall(table, flight, s, g.walls[k], best);
    const double leave = std::min(tx, ty);  // when the flight leaves this cell
    if (best.t <= leave) return best;
    if (tx < ty) {
      i += step_i;
      tx += dtx;
    } else {
      j += step_j;
      ty += dty;
    }
    if (i < 0 || j < 0 || i >= g.nx || j >= g.ny) return best;
  }
}

}  // namespace billiards::dynamics::detail
