#include "billiards/analysis/chaos.hpp"

#include "billiards/analysis/boundary_map.hpp"
#include "billiards/analysis/statistics.hpp"

#include <algorithm>

namespace billiards::analysis {

namespace {

/// Total variation between a histogram of n points and the uniform law on its cells, and the
/// fraction of cells visited.
std::pair<double, double> distance_and_coverage(const std::vector<std::uint64_t>& counts) {
  std::uint64_t n = 0, visited = 0;
  for (auto c : counts) n += c, visited += c > 0;
  const double p = 1.0 / double(counts.size());
  double tv = 0;
  for (auto c : counts) tv += std::abs(double(c) / double(n) - p);
  return {tv / 2, double(visited) / double(counts.size())};
}

struct Orbit {
  LyapunovTrajectory lyapunov;
  std::vector<std::uint64_t> counts;
};

}  // namespace

ChaosVerdict chaos_of(const geometry::Region2& region, const ChaosOptions& o,
                      const std::function<void(std::size_t)>& progress) {
  const dynamics::Table table(region);
  const BoundaryCoordinates coordinates(region);
  const dynamics::FreeFlight flight;
  const auto initial = dynamics::microcanonical(table, flight, 1.0, o.seed);
  const double S = coordinates.perimeter();
  const std::size_t cells = std::size_t(o.cells_s) * std::size_t(o.cells_p);
  const auto orbits = for_each_particle(
      o.orbits, o.threads,
      [&](std::size_t i) {
        Orbit orbit{{}, std::vector<std::uint64_t>(cells)};
        TangentBasis q = initial_tangent_basis();
        std::size_t made = 0;
        const auto s0 = initial(i);
        const auto end = carry_tangent(table, flight, s0, o.collisions, q, made, [&](TangentBasis& basis, const auto& hit) {
          orthonormalize(basis, orbit.lyapunov.log_stretch);
          const double s = coordinates.s_of(table, hit) / S;
          const double p = BoundaryCoordinates::p_of(dynamics::reflect(hit.state.v, hit.normal), hit.normal);
          const int is = std::clamp(int(s * o.cells_s), 0, o.cells_s - 1);
          const int ip = std::clamp(int((p + 1) / 2 * o.cells_p), 0, o.cells_p - 1);
          ++orbit.counts[std::size_t(is) * std::size_t(o.cells_p) + std::size_t(ip)];
        });
        orbit.lyapunov.time = end.t - s0.t;
        orbit.lyapunov.collisions = made;
        orbit.lyapunov.escaped = made < o.collisions;
        return orbit;
      },
      progress);

  ChaosVerdict v;
  std::vector<LyapunovTrajectory> trajectories;
  std::vector<std::uint64_t> pooled(cells);
  v.chaotic = v.uniform = true;
  for (const auto& orbit : orbits) {
    trajectories.push_back(orbit.lyapunov);
    OrbitEvidence e;
    e.escaped = orbit.lyapunov.escaped;
    if (orbit.lyapunov.collisions > 0) {
      e.lyapunov = orbit.lyapunov.log_stretch[0] / orbit.lyapunov.time;
      e.lyapunov_per_collision = orbit.lyapunov.log_stretch[0] / double(orbit.lyapunov.collisions);
      std::tie(e.distance, e.coverage) = distance_and_coverage(orbit.counts);
    }
    for (std::size_t c = 0; c < cells; ++c) pooled[c] += orbit.counts[c];
    v.chaotic = v.chaotic && !e.escaped && e.lyapunov_per_collision > o.min_exponent_per_collision;
    v.uniform = v.uniform && !e.escaped && e.distance < o.max_distance;
    v.orbits.push_back(e);
  }
  const auto summary = summarize(std::move(trajectories));
  v.lyapunov = summary.per_time[0];
  v.lyapunov_per_collision = summary.per_collision[0];
  std::tie(v.pooled_distance, v.pooled_coverage) = distance_and_coverage(pooled);
  const double p = 1.0 / double(cells);
  v.noise_distance = double(cells) * binomial_mean_absolute_deviation(o.collisions, p) / (2 * double(o.collisions));
  return v;
}

}  // namespace billiards::analysis
