// Lyapunov exponents of a billiard in D = 2 or 3 dimensions from its tangent dynamics (Dellago,
// Posch & Hoover 1996, PRE 53, 1485): 2D tangent vectors δΓ = (δx, δv) are carried along a
// trajectory — through each flight by the flight's linearisation, through each collision by its
// Jacobian — and re-orthonormalised (Gram–Schmidt) after every collision; the logarithms of the
// lengths the orthogonalisation removes add up to the exponents (4 in 2-D, 6 in 3-D).
//
// Flights: free, a static uniform force (2-D) and the uniform periodic drive F cos(ω t + phase)
// (2-D and 3-D).  A
// uniform force does not depend on the position, so the tangent flow of every flight is the
// free one, δx ← δx + τ δv; only the collision Jacobian sees the force, through the particle's
// acceleration a at the contact (the perturbed particle meets the wall δt earlier or later).
//
// The collision Jacobian at a wall with outward unit normal n and signed curvature κ (> 0
// focusing: dn = κ dx_c along the wall; every 3-D wall is umbilic — planes and triangles 0,
// spheres ±1/r — so one κ serves all tangent directions), hit with incoming velocity v
// (v·n > 0), R = I − 2nnᵀ:
//   δt   = −(n·δx)/(n·v),         δx_c = δx + v δt   (the shift of the contact along the wall)
//   δx'  = R δx
//   δv'  = R δv − 2(a·n) n δt − 2[(v·δn) n + (v·n) δn],   δn = κ δx_c.
#pragma once

#include "billiards/analysis/per_particle.hpp"
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/scene_run.hpp"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace billiards::analysis {

using Vec2 = geometry::Vec2;
/// Tangent vectors as columns: rows δx (D), then δv (D).
template <int D>
using BasicTangentBasis = Eigen::Matrix<double, 2 * D, 2 * D>;
using TangentBasis = BasicTangentBasis<2>;

/// The flights whose tangent dynamics is known here.
template <class Flight>
concept tangent_flight =
    std::is_same_v<Flight, dynamics::FreeFlight> || std::is_same_v<Flight, dynamics::ConstantForceFlight> ||
    std::is_same_v<Flight, dynamics::PeriodicDriveFlight> || std::is_same_v<Flight, dynamics::FreeFlight3> ||
    std::is_same_v<Flight, dynamics::PeriodicDriveFlight3>;

/// The particle's acceleration in the state `s` of the flight.
template <int D>
Eigen::Matrix<double, D, 1> acceleration_at(const dynamics::BasicFreeFlight<double, D>&,
                                            const dynamics::BasicState<double, D>&) {
  return Eigen::Matrix<double, D, 1>::Zero();
}
inline Vec2 acceleration_at(const dynamics::ConstantForceFlight& f, const dynamics::State&) { return f.accel; }
template <int D>
Eigen::Matrix<double, D, 1> acceleration_at(const dynamics::BasicPeriodicDriveFlight<double, D>& f,
                                            const dynamics::BasicDrivenState<double, D>& s) {
  return f.accel * s.cos_phase;
}

/// δx ← δx + τ δv for every tangent vector.
template <int D>
void tangent_flight_step(BasicTangentBasis<D>& q, double tau) {
  q.template topRows<D>() += tau * q.template bottomRows<D>();
}

/// The collision Jacobian (above) for incoming velocity v, outward normal n, signed curvature
/// kappa and acceleration a at the contact.
template <int D>
BasicTangentBasis<D> collision_jacobian(const Eigen::Matrix<double, D, 1>& v, const Eigen::Matrix<double, D, 1>& n,
                                        double kappa, const Eigen::Matrix<double, D, 1>& a) {
  using M = Eigen::Matrix<double, D, D>;
  const double vn = v.dot(n);
  const M I = M::Identity();
  const M R = I - 2 * n * n.transpose();
  // δt = −nᵀδx/(n·v); δx_c = P δx with P = I − v nᵀ/(n·v); δn = κ P δx.
  const M P = I - v * n.transpose() / vn;
  const M C = 2 * a.dot(n) / vn * n * n.transpose() - 2 * kappa * (n * v.transpose() + vn * I) * P;
  BasicTangentBasis<D> J = BasicTangentBasis<D>::Zero();
  J.template topLeftCorner<D, D>() = R;
  J.template bottomRightCorner<D, D>() = R;
  J.template bottomLeftCorner<D, D>() = C;
  return J;
}

/// Orthonormalises the columns of q in order (modified Gram–Schmidt); adds the log of each
/// column's length before normalisation to `logs`.
template <int D>
void orthonormalize(BasicTangentBasis<D>& q, std::array<double, 2 * D>& logs) {
  for (int j = 0; j < 2 * D; ++j) {
    for (int i = 0; i < j; ++i) q.col(j) -= q.col(i).dot(q.col(j)) * q.col(i);
    const double r = q.col(j).norm();
    logs[j] += std::log(r);
    q.col(j) /= r;
  }
}

/// The tangent basis every trajectory starts from: a fixed orthonormal basis in general
/// position (the standard basis is not: in a table of flat walls its δx vectors never grow).
template <int D>
BasicTangentBasis<D> initial_tangent_basis() {
  BasicTangentBasis<D> q;
  for (int i = 0; i < 2 * D; ++i)
    for (int j = 0; j < 2 * D; ++j) q(i, j) = std::sin(1.0 + 2 * D * i + j) + (i == j ? 2 : 0);
  std::array<double, 2 * D> ignored{};
  orthonormalize<D>(q, ignored);
  return q;
}

template <class Flight>
inline constexpr int dimension_of = Flight::State::dimension;

/// Carries the tangent basis q along the trajectory from `s` through `collisions` bounces,
/// calling after(q, hit) just after each collision's Jacobian; returns the state after the last
/// bounce (fewer bounces if the particle escapes: `made` says how many).
template <tangent_flight Flight, class After>
typename Flight::State carry_tangent(const dynamics::TableFor<Flight>& table, const Flight& flight,
                                     typename Flight::State s, std::size_t collisions,
                                     BasicTangentBasis<dimension_of<Flight>>& q, std::size_t& made, After&& after) {
  constexpr int D = dimension_of<Flight>;
  typename Flight::State last = s;
  made = dynamics::evolve(table, flight, s, collisions, [&](const auto& hit, const auto& bounced) {
    tangent_flight_step<D>(q, hit.t - last.t);
    const double kappa = table.curvature_at(hit.wall, hit.point);
    q = collision_jacobian<D>(hit.state.v, hit.normal, kappa, acceleration_at(flight, hit.state)) * q;
    last = bounced;
    after(q, hit);
  });
  return last;
}

/// One trajectory's exponents: the sums of the logarithms of the stretches, its time and its
/// collisions.
template <int D>
struct BasicLyapunovTrajectory {
  std::array<double, 2 * D> log_stretch{};  // Σ log r_i, largest first
  double time = 0;
  std::uint64_t collisions = 0;
  bool escaped = false;
};
using LyapunovTrajectory = BasicLyapunovTrajectory<2>;

template <tangent_flight Flight>
BasicLyapunovTrajectory<dimension_of<Flight>> lyapunov_trajectory(const dynamics::TableFor<Flight>& table,
                                                                  const Flight& flight,
                                                                  const typename Flight::State& s,
                                                                  std::size_t collisions) {
  constexpr int D = dimension_of<Flight>;
  BasicLyapunovTrajectory<D> out;
  auto q = initial_tangent_basis<D>();
  std::size_t made = 0;
  const auto end = carry_tangent(table, flight, s, collisions, q, made,
                                 [&](auto& basis, const auto&) { orthonormalize<D>(basis, out.log_stretch); });
  out.time = double(end.t - s.t);
  out.collisions = made;
  out.escaped = made < collisions;
  return out;
}

/// Mean and standard error over independent trajectories.
struct Estimate {
  double mean = 0, se = 0;
};

/// The exponents of an ensemble: the spectrum per unit time and per collision, each the mean of
/// the trajectories' own with its standard error.
template <int D>
struct BasicLyapunovSpectrum {
  static constexpr int exponents = 2 * D;
  std::array<Estimate, 2 * D> per_time, per_collision;
  std::vector<BasicLyapunovTrajectory<D>> trajectories;
  std::size_t escapes() const {
    std::size_t n = 0;
    for (const auto& t : trajectories) n += t.escaped;
    return n;
  }
  /// Trajectory i's exponent k per unit time.
  double exponent(std::size_t i, int k) const { return trajectories[i].log_stretch[k] / trajectories[i].time; }
};
using LyapunovSpectrum = BasicLyapunovSpectrum<2>;

/// The mean and its standard error of each column of the rows (the trajectories' exponents).
Estimate estimate_of(const std::vector<double>& values);

template <int D>
BasicLyapunovSpectrum<D> summarize(std::vector<BasicLyapunovTrajectory<D>> trajectories) {
  BasicLyapunovSpectrum<D> out;
  out.trajectories = std::move(trajectories);
  for (int k = 0; k < 2 * D; ++k) {
    std::vector<double> per_time, per_collision;
    for (const auto& t : out.trajectories) {
      if (t.escaped || t.collisions == 0) continue;
      per_time.push_back(t.log_stretch[k] / t.time);
      per_collision.push_back(t.log_stretch[k] / double(t.collisions));
    }
    if (per_time.size() < 2) continue;
    out.per_time[k] = estimate_of(per_time);
    out.per_collision[k] = estimate_of(per_collision);
  }
  return out;
}

template <tangent_flight Flight, class Initial>
BasicLyapunovSpectrum<dimension_of<Flight>> lyapunov_spectrum(const dynamics::TableFor<Flight>& table,
                                                              const Flight& flight, const Initial& initial,
                                                              std::size_t particles, std::size_t collisions,
                                                              int threads,
                                                              const std::function<void(std::size_t)>& progress = {}) {
  return summarize(for_each_particle(
      particles, threads, [&](std::size_t i) { return lyapunov_trajectory(table, flight, initial(i), collisions); },
      progress));
}

}  // namespace billiards::analysis
