// How far trajectories computed in one precision drift from the same trajectories computed in
// another (the reference, e.g. 136-bit MPFR), collision by collision.  In a chaotic billiard
// the distance grows like e^{λ k} with λ the Lyapunov exponent per collision, from the
// rounding level of the lower precision; in an integrable one it grows only polynomially.
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/geometry/pieces.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace billiards::analysis {

/// Collision points (rounded to double) of the trajectories from `starts` under `flight`, whose
/// scalar type (double, long double, dynamics::Reference) sets the precision of the whole
/// computation: [trajectory][collision].
template <class Flight>
std::vector<std::vector<Eigen::Vector2d>> collision_points(const geometry::Region2& region, const Flight& flight,
                                                           const std::vector<dynamics::State>& starts,
                                                           std::size_t collisions) {
  using Real = typename Flight::Scalar;
  const dynamics::BasicTable<Real> table(region);
  std::vector<std::vector<Eigen::Vector2d>> points;
  for (const auto& s0 : starts) {
    dynamics::BasicState<Real> s;
    s.x = s0.x.cast<Real>();
    s.v = s0.v.cast<Real>();
    s.t = s0.t;
    auto& p = points.emplace_back();
    for (const auto& h : dynamics::evolve(table, flight, flight.start(s), collisions))
      p.emplace_back(double(h.point.x()), double(h.point.y()));
  }
  return points;
}

/// The same for free flights in precision Real.
template <class Real>
std::vector<std::vector<Eigen::Vector2d>> collision_points(const geometry::Region2& region,
                                                           const std::vector<dynamics::State>& starts,
                                                           std::size_t collisions) {
  return collision_points(region, dynamics::BasicFreeFlight<Real>{}, starts, collisions);
}

/// Median over trajectories of |a − reference| at each collision (+∞ past a trajectory's end).
inline std::vector<double> median_distance(const std::vector<std::vector<Eigen::Vector2d>>& a,
                                           const std::vector<std::vector<Eigen::Vector2d>>& reference,
                                           std::size_t collisions) {
  std::vector<double> median(collisions);
  for (std::size_t k = 0; k < collisions; ++k) {
    std::vector<double> d;
    for (std::size_t i = 0; i < reference.size(); ++i)
      d.push_back(k < a[i].size() && k < reference[i].size() ? (a[i][k] - reference[i][k]).norm() : INFINITY);
    std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
    median[k] = d[d.size() / 2];
  }
  return median;
}

/// Least-squares slope of ln(distance) against the collision number over the collisions where
/// lo < distance < hi (above the rounding floor, below saturation at the table's size): the
/// growth rate per collision; NaN with fewer than 5 such collisions.
inline double exponential_growth_rate(const std::vector<double>& distance, double lo = 1e-13, double hi = 1e-4) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int m = 0;
  for (std::size_t k = 0; k < distance.size(); ++k)
    if (distance[k] > lo && distance[k] < hi) {
      const double x = double(k + 1), y = std::log(distance[k]);
      sx += x, sy += y, sxx += x * x, sxy += x * y, ++m;
    }
  return m < 5 ? NAN : (m * sxy - sx * sy) / (m * sxx - sx * sx);
}

/// The first collision (1-based) at which the distance exceeds `level`, or 0 if none does.
inline std::size_t first_exceeding(const std::vector<double>& distance, double level) {
  for (std::size_t k = 0; k < distance.size(); ++k)
    if (distance[k] > level) return k + 1;
  return 0;
}

}  // namespace billiards::analysis
