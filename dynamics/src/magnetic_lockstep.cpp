#include "billiards/dynamics/magnetic_lockstep.hpp"

#include "billiards/dynamics/free_lockstep.hpp"
#include "billiards/dynamics/simd.hpp"

#include <cmath>
#include <tuple>

namespace billiards::dynamics {

magnetic_lanes::Kernel magnetic_lanes::chosen_kernel() {
  static const Kernel k = kernel_of(simd::chosen_target());
  return k;
}

namespace {

magnetic_lanes::Reach reach_of(const auto& wall) {
  const auto r = reach_lanes(wall);
  return {r.cx, r.cy, r.r, r.pad, r.slack};
}

}  // namespace

MagneticLockstepTable::MagneticLockstepTable(const Table& table, const MagneticFlight& flight,
                                             magnetic_lanes::Kernel kernel)
    : table_(&table), flight_(&flight), kernel_(kernel), usable_(kernel && free_lanes::fits(table)) {
  if (!usable_) return;
  walls_.straight = free_lanes::walls_of(table);
  walls_.k = std::abs(flight.omega_c), walls_.inv_k = 1 / walls_.k, walls_.clockwise = flight.omega_c > 0;
  for (std::size_t i = 0; i < table.segments().size(); ++i) walls_.segments[i] = reach_of(table.segments()[i]);
  for (std::size_t i = 0; i < table.arcs().size(); ++i) walls_.arcs[i] = reach_of(table.arcs()[i]);
}

void MagneticLockstepTable::collisions(const State* const* states, const double* t_end, int n,
                                       FlightHit<MagneticFlight>* hits) const {
  magnetic_lanes::Flights in;
  for (int i = 0; i < lanes; ++i) {
    const int j = i < n ? i : 0;  // (lanes beyond n: a copy of the first)
    const State& s = *states[j];
    in.x[i] = s.x.x(), in.y[i] = s.x.y(), in.vx[i] = s.v.x(), in.vy[i] = s.v.y(), in.t[i] = s.t, in.t_end[i] = t_end[j];
  }
  magnetic_lanes::Hits out;
  kernel_(walls_, in, out);
  const bool scans = !table_->elliptic_arcs().empty();
  for (int i = 0; i < n; ++i) {
    const State& s = *states[i];
    auto& hit = hits[i];
    hit.t = out.t[i];
    hit.wall = out.kind[i] < 0 ? WallId{} : WallId{int(out.kind[i]), int(out.index[i])};
    hit.midpoint_inside = false;
    // As Gyration::hit_from: the walls without a closed form, scanned up to the hit so far.
    bool scanned = false;
    if (scans) {
      const Gyration<double> g(*flight_, s);
      if ((scanned = g.scan_walls_without_closed_form(*table_, hit))) std::tie(hit.state.x, hit.state.v) = g.at(hit.t - s.t);
    }
    if (!hit.found()) continue;
    if (!scanned)
      hit.state.x = Eigen::Map<const Vec2>(out.position + 2 * i), hit.state.v = Eigen::Map<const Vec2>(out.velocity + 2 * i);
    hit.state.t = hit.t;
    std::tie(hit.point, hit.normal) = table_->contact(hit.wall, hit.state.x, hit.state.v);
  }
}

}  // namespace billiards::dynamics
