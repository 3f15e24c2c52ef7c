// Lyapunov exponents of a 2-D billiard from its tangent dynamics (Dellago, Posch & Hoover 1996,
// PRE 53, 1485): four tangent vectors δΓ = (δx, δv) are carried along a trajectory — through
// each flight by the flight's linearisation, through each collision by its Jacobian — and
// re-orthonormalised (Gram–Schmidt) after every collision; the logarithms of the lengths the
// orthogonalisation removes add up to the exponents.
//
// Flights: free, a static uniform force and the uniform periodic drive F cos(ω t + phase).  A
// uniform force does not depend on the position, so the tangent flow of every flight is the
// free one, δx ← δx + τ δv; only the collision Jacobian sees the force, through the particle's
// acceleration a at the contact (the perturbed particle meets the wall δt earlier or later).
//
// The collision Jacobian at a wall with outward unit normal n and signed curvature κ (> 0
// focusing: dn = κ dx_c along the wall), hit with incoming velocity v (v·n > 0), R = I − 2nnᵀ:
//   δt   = −(n·δx)/(n·v),         δx_c = δx + v δt   (the shift of the contact along the wall)
//   δx'  = R δx
//   δv'  = R δv − 2(a·n) n δt − 2[(v·δn) n + (v·n) δn],   δn = κ δx_c.
#pragma once

#include "billiards/analysis/per_particle.hpp"
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/forced_flight.hpp"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace billiards::analysis {

using Vec2 = geometry::Vec2;
/// Tangent vectors as columns: rows δx, δy, δvx, δvy.
using TangentBasis = Eigen::Matrix4d;

/// The flights whose tangent dynamics is known here.
template <class Flight>
concept tangent_flight = std::is_same_v<Flight, dynamics::FreeFlight> ||
                         std::is_same_v<Flight, dynamics::ConstantForceFlight> ||
                         std::is_same_v<Flight, dynamics::PeriodicDriveFlight>;

/// The particle's acceleration in the state `s` of the flight.
inline Vec2 acceleration_at(const dynamics::FreeFlight&, const dynamics::State&) { return Vec2::Zero(); }
inline Vec2 acceleration_at(const dynamics::ConstantForceFlight& f, const dynamics::State&) { return f.accel; }
inline Vec2 acceleration_at(const dynamics::PeriodicDriveFlight& f, const dynamics::DrivenState& s) {
  return f.accel * s.cos_phase;
}

/// δx ← δx + τ δv for every tangent vector.
inline void tangent_flight_step(TangentBasis& q, double tau) { q.topRows<2>() += tau * q.bottomRows<2>(); }

/// The collision Jacobian (above) for incoming velocity v, outward normal n, signed curvature
/// kappa and acceleration a at the contact.
Eigen::Matrix4d collision_jacobian(const Vec2& v, const Vec2& n, double kappa, const Vec2& a);

/// Orthonormalises the columns of q in order (modified Gram–Schmidt); adds the log of each
/// column's length before normalisation to `logs`.
void orthonormalize(TangentBasis& q, std::array<double, 4>& logs);

/// The tangent basis every trajectory starts from: a fixed orthonormal basis in general
/// position (the standard basis is not: in a table of flat walls its δx vectors never grow).
TangentBasis initial_tangent_basis();

/// Carries the tangent basis q along the trajectory from `s` through `collisions` bounces,
/// calling after(q, hit) just after each collision's Jacobian; returns the state after the last
/// bounce (fewer bounces if the particle escapes: `made` says how many).
template <tangent_flight Flight, class After>
typename Flight::State carry_tangent(const dynamics::Table& table, const Flight& flight, typename Flight::State s,
                                     std::size_t collisions, TangentBasis& q, std::size_t& made, After&& after) {
  typename Flight::State last = s;
  made = dynamics::evolve(table, flight, s, collisions, [&](const auto& hit, const auto& bounced) {
    tangent_flight_step(q, hit.t - last.t);
    const double kappa = table.curvature_at(hit.wall, hit.point);
    q = collision_jacobian(hit.state.v, hit.normal, kappa, acceleration_at(flight, hit.state)) * q;
    last = bounced;
    after(q, hit);
  });
  return last;
}

/// One trajectory's exponents: the sums of the logarithms of the stretches, its time and its
/// collisions.
struct LyapunovTrajectory {
  std::array<double, 4> log_stretch{};  // Σ log r_i, largest first
  double time = 0;
  std::uint64_t collisions = 0;
  bool escaped = false;
};

template <tangent_flight Flight>
LyapunovTrajectory lyapunov_trajectory(const dynamics::Table& table, const Flight& flight,
                                       const typename Flight::State& s, std::size_t collisions) {
  LyapunovTrajectory out;
  TangentBasis q = initial_tangent_basis();
  std::size_t made = 0;
  const auto end = carry_tangent(table, flight, s, collisions, q, made,
                                 [&](TangentBasis& basis, const auto&) { orthonormalize(basis, out.log_stretch); });
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
struct LyapunovSpectrum {
  std::array<Estimate, 4> per_time, per_collision;
  std::vector<LyapunovTrajectory> trajectories;
  std::size_t escapes() const;
  /// Trajectory i's exponent k per unit time.
  double exponent(std::size_t i, int k) const { return trajectories[i].log_stretch[k] / trajectories[i].time; }
};

LyapunovSpectrum summarize(std::vector<LyapunovTrajectory> trajectories);

template <tangent_flight Flight, class Initial>
LyapunovSpectrum lyapunov_spectrum(const dynamics::Table& table, const Flight& flight, const Initial& initial,
                                   std::size_t particles, std::size_t collisions, int threads,
                                   const std::function<void(std::size_t)>& progress = {}) {
  return summarize(for_each_particle(
      particles, threads, [&](std::size_t i) { return lyapunov_trajectory(table, flight, initial(i), collisions); },
      progress));
}

}  // namespace billiards::analysis
