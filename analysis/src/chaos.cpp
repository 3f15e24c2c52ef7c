#include "billiards/analysis/chaos.hpp"

#include "billiards/analysis/boundary_map.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/dynamics/table3.hpp"

#include <algorithm>

namespace billiards::analysis {

namespace {

/// Total variation between a histogram and the law `expected` on its cells, and the fraction of
/// cells visited.
std::pair<double, double> distance_and_coverage(const std::vector<std::uint64_t>& counts,
                                                const std::vector<double>& expected) {
  std::uint64_t n = 0, visited = 0;
  for (auto c : counts) n += c, visited += c > 0;
  double tv = 0;
  for (std::size_t c = 0; c < counts.size(); ++c) tv += std::abs(double(counts[c]) / double(n) - expected[c]);
  return {tv / 2, double(visited) / double(counts.size())};
}

template <int D>
struct Orbit {
  BasicLyapunovTrajectory<D> lyapunov;
  std::vector<std::uint64_t> counts;
};

/// Free orbits at speed 1 from a microcanonical start, each with its tangent dynamics and the
/// histogram of cell_of(hit) over its collisions.
template <class Flight, class CellOf>
std::vector<Orbit<dimension_of<Flight>>> orbits_of(const dynamics::TableFor<Flight>& table, const Flight& flight,
                                                   const ChaosOptions& o, std::size_t cells, CellOf&& cell_of,
                                                   const std::function<void(std::size_t)>& progress) {
  constexpr int D = dimension_of<Flight>;
  const auto initial = dynamics::microcanonical(table, flight, 1.0, o.seed);
  return for_each_particle(
      o.orbits, o.threads,
      [&](std::size_t i) {
        Orbit<D> orbit{{}, std::vector<std::uint64_t>(cells)};
        auto q = initial_tangent_basis<D>();
        std::size_t made = 0;
        const auto s0 = initial(i);
        const auto end = carry_tangent(table, flight, s0, o.collisions, q, made, [&](auto& basis, const auto& hit) {
          orthonormalize<D>(basis, orbit.lyapunov.log_stretch);
          ++orbit.counts[cell_of(hit)];
        });
        orbit.lyapunov.time = end.t - s0.t;
        orbit.lyapunov.collisions = made;
        orbit.lyapunov.escaped = made < o.collisions;
        return orbit;
      },
      progress);
}

/// The verdict on the orbits against the law `expected` of their cells.
template <int D>
ChaosVerdict verdict_of(const std::vector<Orbit<D>>& orbits, const std::vector<double>& expected, const ChaosOptions& o) {
  ChaosVerdict v;
  std::vector<BasicLyapunovTrajectory<D>> trajectories;
  std::vector<std::uint64_t> pooled(expected.size());
  v.chaotic = v.uniform = true;
  for (const auto& orbit : orbits) {
    trajectories.push_back(orbit.lyapunov);
    OrbitEvidence e;
    e.escaped = orbit.lyapunov.escaped;
    if (orbit.lyapunov.collisions > 0) {
      e.lyapunov = orbit.lyapunov.log_stretch[0] / orbit.lyapunov.time;
      e.lyapunov_per_collision = orbit.lyapunov.log_stretch[0] / double(orbit.lyapunov.collisions);
      std::tie(e.distance, e.coverage) = distance_and_coverage(orbit.counts, expected);
    }
    for (std::size_t c = 0; c < expected.size(); ++c) pooled[c] += orbit.counts[c];
    v.chaotic = v.chaotic && !e.escaped && e.lyapunov_per_collision > o.min_exponent_per_collision;
    v.uniform = v.uniform && !e.escaped && e.distance < o.max_distance;
    v.orbits.push_back(e);
  }
  const auto summary = summarize(std::move(trajectories));
  v.lyapunov = summary.per_time[0];
  v.lyapunov_per_collision = summary.per_collision[0];
  std::tie(v.pooled_distance, v.pooled_coverage) = distance_and_coverage(pooled, expected);
  for (const double p : expected) v.noise_distance += binomial_mean_absolute_deviation(o.collisions, p);
  v.noise_distance /= 2 * double(o.collisions);
  v.position_cells = int(expected.size()) / o.cells_p;
  return v;
}

int bin_of(double x, int bins) { return std::clamp(int(x * bins), 0, bins - 1); }

double polygon_area(const std::vector<geometry3::Vec3>& face) {
  geometry3::Vec3 twice = geometry3::Vec3::Zero();
  for (std::size_t k = 0; k < face.size(); ++k) twice += face[k].cross(face[(k + 1) % face.size()]);
  return twice.norm() / 2;
}

/// The walls of a 3-D table as the position cells of the chaos check: each plane face and each
/// sphere its own, a mesh's triangles one; their areas.
struct WallGroups {
  std::vector<double> areas;
  int first_sphere = 0, triangles = -1;
  explicit WallGroups(const dynamics::Table3& table) {
    if (const auto* p = std::get_if<geometry3::ConvexPolyhedron>(&table.region().outer))
      for (const auto& face : p->faces) areas.push_back(polygon_area(face));
    if (!table.triangles().empty()) {
      triangles = int(areas.size());
      double area = 0;
      for (const auto& t : table.triangles()) area += (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).norm() / 2;
      areas.push_back(area);
    }
    first_sphere = int(areas.size());
    for (const auto& b : table.spheres()) areas.push_back(4 * geometry::pi * b.radius2);
  }
  int group_of(const dynamics::WallId& w) const {
    if (w.kind == dynamics::wall_kind3::plane) return w.index;
    if (w.kind == dynamics::wall_kind3::triangle) return triangles;
    return first_sphere + w.index;
  }
};

}  // namespace

ChaosVerdict chaos_of(const geometry::Region2& region, const ChaosOptions& o,
                      const std::function<void(std::size_t)>& progress) {
  const dynamics::Table table(region);
  const BoundaryCoordinates coordinates(region);
  const double S = coordinates.perimeter();
  const std::size_t cells = std::size_t(o.cells_s) * std::size_t(o.cells_p);
  const auto orbits = orbits_of(table, dynamics::FreeFlight{}, o, cells, [&](const auto& hit) {
    const double s = coordinates.s_of(table, hit) / S;
    const double p = BoundaryCoordinates::p_of(dynamics::reflect(hit.state.v, hit.normal), hit.normal);
    return std::size_t(bin_of(s, o.cells_s)) * std::size_t(o.cells_p) + std::size_t(bin_of((p + 1) / 2, o.cells_p));
  }, progress);
  return verdict_of(orbits, std::vector<double>(cells, 1.0 / double(cells)), o);
}

ChaosVerdict chaos_of(const geometry3::Region3& region, const ChaosOptions& o,
                      const std::function<void(std::size_t)>& progress) {
  const dynamics::Table3 table(region);
  const WallGroups walls(table);
  const std::size_t cells = walls.areas.size() * std::size_t(o.cells_p);
  const auto orbits = orbits_of(table, dynamics::FreeFlight3{}, o, cells, [&](const auto& hit) {
    const double cos_theta = hit.state.v.dot(hit.normal) / hit.state.v.norm();
    return std::size_t(walls.group_of(hit.wall)) * std::size_t(o.cells_p) +
           std::size_t(bin_of(cos_theta * cos_theta, o.cells_p));
  }, progress);
  double total = 0;
  for (const double a : walls.areas) total += a;
  std::vector<double> expected;
  for (const double a : walls.areas)
    for (int k = 0; k < o.cells_p; ++k) expected.push_back(a / total / o.cells_p);
  return verdict_of(orbits, expected, o);
}

}  // namespace billiards::analysis
