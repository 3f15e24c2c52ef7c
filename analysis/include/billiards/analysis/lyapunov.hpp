// Lyapunov exponents of a billiard in D = 2 or 3 dimensions from its tangent dynamics (Dellago,
// Posch & Hoover 1996, PRE 53, 1485): 2D tangent vectors δΓ = (δx, δv) are carried along a
// trajectory — through each flight by the flight's linearisation, through each collision by its
// Jacobian — and re-orthonormalised (Gram–Schmidt) after every collision; the logarithms of the
// lengths the orthogonalisation removes add up to the exponents (4 in 2-D, 6 in 3-D).
//
// Flights: free, a static uniform force (2-D), the uniform periodic drive F cos(ω t + phase)
// (2-D and 3-D), and a uniform magnetic field (2-D and 3-D).  Every one of them has
// v̇ = A v + f(t), A linear (0, or the field's v ↦ v × Ω) and f independent of the state, so the
// tangent flow over a flight of duration τ is the linear flow itself:
//   δx ← δx + M(τ) δv,   δv ← E(τ) δv,   E = e^{Aτ}, M = ∫₀^τ E
// (E = I, M = τ I without a field).  The collision Jacobian sees the flight through the
// particle's acceleration just before (a) and just after (a') the bounce: the perturbed
// particle meets the wall δt earlier or later, and over δt it has the other acceleration.
//
// The collision Jacobian at a wall with outward unit normal n and signed curvature κ (> 0
// focusing: dn = κ dx_c along the wall; every 3-D wall is umbilic — planes and triangles 0,
// spheres ±1/r — so one κ serves all tangent directions), hit with incoming velocity v
// (v·n > 0), R = I − 2nnᵀ:
//   δt   = −(n·δx)/(n·v),         δx_c = δx + v δt   (the shift of the contact along the wall)
//   δx'  = R δx
//   δv'  = R δv + (R a − a') δt − 2[(v·δn) n + (v·n) δn],   δn = κ δx_c.
// Under a uniform force a' = a and R a − a = −2(a·n) n; in a field a = v × Ω, a' = (Rv) × Ω.
#pragma once

#include "billiards/analysis/per_particle.hpp"
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/magnetic_flight.hpp"
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

template <class Flight>
inline constexpr int dimension_of = Flight::State::dimension;

/// Flights in a uniform magnetic field, whose tangent flow turns δv.
template <class Flight>
concept magnetic_tangent_flight =
    std::is_same_v<Flight, dynamics::MagneticFlight> || std::is_same_v<Flight, dynamics::MagneticFlight3>;

/// The flights whose tangent dynamics is known here.
template <class Flight>
concept tangent_flight =
    std::is_same_v<Flight, dynamics::FreeFlight> || std::is_same_v<Flight, dynamics::ConstantForceFlight> ||
    std::is_same_v<Flight, dynamics::PeriodicDriveFlight> || std::is_same_v<Flight, dynamics::FreeFlight3> ||
    std::is_same_v<Flight, dynamics::PeriodicDriveFlight3> || magnetic_tangent_flight<Flight>;

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
/// v × Ω (2-D: Ω ẑ, so Ω (v_y, −v_x)).
inline Vec2 acceleration_at(const dynamics::MagneticFlight& f, const dynamics::State& s) {
  return f.omega_c * Vec2(s.v.y(), -s.v.x());
}
inline dynamics::Vec3 acceleration_at(const dynamics::MagneticFlight3& f, const dynamics::State3& s) {
  return s.v.cross(f.omega_c);
}

/// E(τ) = e^{Aτ} and M(τ) = ∫₀^τ E of the flight's linear part (above).
template <int D>
struct LinearFlow {
  Eigen::Matrix<double, D, D> E, M;
};

/// The field's flow: with k = |Ω|, b = Ω/k, K v = v × b and P = b bᵀ (0 in 2-D),
///   E = P + cos kτ (I − P) + sin kτ K,   M = τ P + (sin kτ/k)(I − P) + ((1 − cos kτ)/k) K,
/// the motion of magnetic_flight.hpp's header as a linear map of v0.
template <class Flight>
  requires magnetic_tangent_flight<Flight>
LinearFlow<dimension_of<Flight>> linear_flow(const Flight& flight, double tau) {
  constexpr int D = dimension_of<Flight>;
  using Mat = Eigen::Matrix<double, D, D>;
  Mat K, P = Mat::Zero();
  double k = 0;
  if constexpr (D == 2) {
    k = std::abs(flight.omega_c);
    const double sign = flight.omega_c > 0 ? 1 : -1;
    K << 0, sign, -sign, 0;  // v × (±ẑ)
  } else {
    k = flight.omega_c.norm();
    const dynamics::Vec3 b = flight.omega_c / k;
    K << 0, b.z(), -b.y(), -b.z(), 0, b.x(), b.y(), -b.x(), 0;  // v ↦ v × b
    P = b * b.transpose();
  }
  const Mat across = Mat::Identity() - P;
  const double c = std::cos(k * tau), s = std::sin(k * tau), h = std::sin(k * tau / 2);
  return {P + c * across + s * K, tau * P + (s / k) * across + (2 * h * h / k) * K};  // (1 − cos = 2 sin²(kτ/2))
}

/// The tangent flow over a flight of duration τ: δx ← δx + τ δv under a uniform force;
/// δx ← δx + M δv, δv ← E δv in a field.
template <class Flight>
void tangent_flight_step(const Flight& flight, BasicTangentBasis<dimension_of<Flight>>& q, double tau) {
  constexpr int D = dimension_of<Flight>;
  if constexpr (magnetic_tangent_flight<Flight>) {
    const auto flow = linear_flow(flight, tau);
    q.template topRows<D>() += flow.M * q.template bottomRows<D>();
    q.template bottomRows<D>() = (flow.E * q.template bottomRows<D>()).eval();
  } else {
    q.template topRows<D>() += tau * q.template bottomRows<D>();
  }
}

/// The collision Jacobian (above) for incoming velocity v, outward normal n, signed curvature
/// kappa and the accelerations a just before and a_out just after the bounce at the contact.
template <int D>
BasicTangentBasis<D> collision_jacobian(const Eigen::Matrix<double, D, 1>& v, const Eigen::Matrix<double, D, 1>& n,
                                        double kappa, const Eigen::Matrix<double, D, 1>& a,
                                        const Eigen::Matrix<double, D, 1>& a_out) {
  using M = Eigen::Matrix<double, D, D>;
  const double vn = v.dot(n);
  const M I = M::Identity();
  const M R = I - 2 * n * n.transpose();
  // δt = −nᵀδx/(n·v); δx_c = P δx with P = I − v nᵀ/(n·v); δn = κ P δx.
  const M P = I - v * n.transpose() / vn;
  const M C = -(R * a - a_out) * n.transpose() / vn - 2 * kappa * (n * v.transpose() + vn * I) * P;
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

/// Carries the tangent basis q along the trajectory from `s` through `collisions` bounces,
/// calling after(q, hit) just after each collision's Jacobian; returns the state after the last
/// bounce (fewer bounces if the particle meets no wall: `made` says how many).
template <tangent_flight Flight, class After>
typename Flight::State carry_tangent(const dynamics::TableFor<Flight>& table, const Flight& flight,
                                     typename Flight::State s, std::size_t collisions,
                                     BasicTangentBasis<dimension_of<Flight>>& q, std::size_t& made, After&& after) {
  constexpr int D = dimension_of<Flight>;
  typename Flight::State last = s;
  // (Over each flight's duration on its own clock: a difference of absolute times would be
  // rounded to ulp(t).)
  made = dynamics::evolve(table, flight, s, collisions, [&](const auto& hit, const auto& bounced, const auto& flown) {
    tangent_flight_step(flight, q, double(flown.duration));
    const double kappa = table.curvature_at(hit.wall, hit.point);
    q = collision_jacobian<D>(hit.state.v, hit.normal, kappa, acceleration_at(flight, hit.state),
                              acceleration_at(flight, bounced)) *
        q;
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
  bool trapped = false;  // on a closed magnetic orbit inside the table, meeting no wall (no exponents)
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
  if (made < collisions) {
    // A closed orbit that meets no wall circles inside the table (follow.hpp): not an escape.
    if constexpr (requires { flight.closes_orbit(end); }) (flight.closes_orbit(end) ? out.trapped : out.escaped) = true;
    else out.escaped = true;
  }
  return out;
}

/// Mean and standard error over independent trajectories.
struct Estimate {
  double mean = 0, se = 0;
};

/// The exponents of an ensemble: the spectrum per unit time and per collision, each the mean of
/// the trajectories' own with its standard error (escaped and trapped ones left out).
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
  std::size_t trapped() const {
    std::size_t n = 0;
    for (const auto& t : trajectories) n += t.trapped;
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
      if (t.escaped || t.trapped || t.collisions == 0) continue;
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
