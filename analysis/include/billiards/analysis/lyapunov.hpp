// Lyapunov exponents of a billiard in D = 2 or 3 dimensions from its tangent dynamics (Dellago,
// Posch & Hoover 1996, PRE 53, 1485): 2D tangent vectors δΓ = (δx, δv) are carried along a
// trajectory — through each flight by the flight's linearisation, through each collision by its
// Jacobian — and re-orthonormalised (Gram–Schmidt) after every collision; the logarithms of the
// lengths the orthogonalisation removes add up to the exponents (4 in 2-D, 6 in 3-D).
//
// Flights: free, a static uniform force (2-D), the uniform periodic drive F cos(ω t + phase)
// (2-D and 3-D; in 2-D also in the quivering-wall picture), a uniform magnetic field (2-D and
// 3-D), and the field with a static force or the drive (2-D and 3-D).  Every one of them has
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
// Under a uniform force a' = a and R a − a = −2(a·n) n; in a field a = v × Ω + f, a' = (Rv) × Ω + f.
// Quivering walls (forced_flight.hpp) are the drive seen from the frame y = x + d(t), a
// translation that depends on t alone: δy = δx and δẏ = δẋ, so the tangent vectors and their
// maps are the lab's, with v the velocity relative to the walls, ẏ − ḋ, and a = a' = F cos θ/m
// (−d̈, the walls' acceleration seen from the particle).
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
#include <numbers>
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

/// Flights in a uniform magnetic field with a force, whose collision search needs a time
/// horizon (scene.hpp's searches_to_a_horizon: an orbit may circle inside the table forever).
template <class Flight>
concept horizon_flight =
    std::is_same_v<Flight, dynamics::MagneticDriveFlight> || std::is_same_v<Flight, dynamics::MagneticDriveFlight3>;

/// Flights in a uniform magnetic field (with a force or without), whose tangent flow turns δv.
template <class Flight>
concept magnetic_tangent_flight = std::is_same_v<Flight, dynamics::MagneticFlight> ||
                                  std::is_same_v<Flight, dynamics::MagneticFlight3> || horizon_flight<Flight>;

/// The flights whose tangent dynamics is known here.
template <class Flight>
concept tangent_flight =
    std::is_same_v<Flight, dynamics::FreeFlight> || std::is_same_v<Flight, dynamics::ConstantForceFlight> ||
    std::is_same_v<Flight, dynamics::PeriodicDriveFlight> || std::is_same_v<Flight, dynamics::QuiveringWallFlight> ||
    std::is_same_v<Flight, dynamics::FreeFlight3> || std::is_same_v<Flight, dynamics::PeriodicDriveFlight3> ||
    magnetic_tangent_flight<Flight>;

/// The flights of tangent_flight, as the CLI and the Python module name them when they refuse
/// a scene (a position-dependent force or a potential: the integrated FieldFlight).
inline constexpr const char* tangent_flights_named =
    "free flights, the periodic drive and a magnetic field (alone, with a static force or with the periodic "
    "drive) in 2-D and 3-D, a static force alone and quivering walls in 2-D";

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
/// v × Ω + (F/m) cos θ, the drive's phase θ carried by the state (as the periodic drive's).
template <int D>
Eigen::Matrix<double, D, 1> acceleration_at(const dynamics::BasicMagneticDriveFlight<double, D>& f,
                                            const dynamics::BasicDrivenState<double, D>& s) {
  return acceleration_at(dynamics::BasicMagneticFlight<double, D>{f.omega_c}, s) + f.accel * s.cos_phase;
}
/// Quivering walls: the lab's acceleration F cos θ/m, −d̈ (above).
inline Vec2 acceleration_at(const dynamics::QuiveringWallFlight& f, const dynamics::DrivenState& s) {
  return f.accel * s.cos_phase;
}

/// The particle's velocity relative to the wall it hits: its own, or ẏ − ḋ off quivering walls.
template <class Flight>
auto velocity_at_wall(const Flight&, const typename Flight::State& s) {
  return s.v;
}
inline Vec2 velocity_at_wall(const dynamics::QuiveringWallFlight& f, const dynamics::DrivenState& s) {
  return s.v - f.wall_velocity(s);
}

/// |Ω|, the cyclotron frequency.
template <class Flight>
  requires magnetic_tangent_flight<Flight>
double cyclotron_rate(const Flight& flight) {
  if constexpr (dimension_of<Flight> == 2) return std::abs(flight.omega_c);
  else return flight.omega_c.norm();
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
  const double k = cyclotron_rate(flight);
  if constexpr (D == 2) {
    const double sign = flight.omega_c > 0 ? 1 : -1;
    K << 0, sign, -sign, 0;  // v × (±ẑ)
  } else {
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

/// A horizon flight's collision is searched its look-ahead at a time (magnetic_flight.hpp's
/// `lookahead`: an eighth of a cyclotron period); a particle that meets no wall in
/// wall_free_periods periods is taken to stay clear of the walls (follow.hpp's trapped orbit
/// when it is inside the table, an escape when it is not).
inline constexpr int wall_free_periods = 10000;

/// `evolve` (collision.hpp) for a horizon flight: while the search to the next horizon meets no
/// wall, the particle is advanced there and searched again, for at most wall_free_periods
/// periods.  Returns the bounces made; `s` is left after the last bounce, or where the search
/// gave up.
template <horizon_flight Flight, class Visit>
std::size_t evolve_to_horizons(const dynamics::TableFor<Flight>& table, const Flight& flight,
                               typename Flight::State& s, std::size_t collisions, Visit&& visit) {
  const double step = flight.lookahead();
  dynamics::Clock clock;
  dynamics::restart_clock(flight, s, clock);
  for (std::size_t k = 0; k < collisions; ++k) {
    auto hit = dynamics::collision(table, flight, s, s.t + step);
    for (int horizons = 1; !hit.found() && horizons < wall_free_periods * dynamics::lookaheads_per_period; ++horizons) {
      s = flight.advance(s, s.t + step);
      hit = dynamics::collision(table, flight, s, s.t + step);
    }
    if (!hit.found()) {
      s = dynamics::on_clock(s, clock);
      return k;
    }
    dynamics::bounce(flight, s, hit);
    dynamics::visit_bounce(visit, dynamics::on_clock(hit, clock), dynamics::on_clock(s, clock),
                           dynamics::Flown<double>{s.t, clock});
    dynamics::restart_clock(flight, s, clock);
  }
  s = dynamics::on_clock(s, clock);
  return collisions;
}

/// Carries the tangent basis q along the trajectory from `s` through `collisions` bounces,
/// calling after(q, hit) just after each collision's Jacobian; returns the state after the last
/// bounce.  Fewer bounces if the particle meets no wall (`made` says how many): then it returns
/// where the search for the next one ended (a horizon flight's give-up; the last bounce for the
/// others, searched without a horizon).
template <tangent_flight Flight, class After>
typename Flight::State carry_tangent(const dynamics::TableFor<Flight>& table, const Flight& flight,
                                     typename Flight::State s, std::size_t collisions,
                                     BasicTangentBasis<dimension_of<Flight>>& q, std::size_t& made, After&& after) {
  constexpr int D = dimension_of<Flight>;
  typename Flight::State last = s;
  // (Over each flight's duration on its own clock: a difference of absolute times would be
  // rounded to ulp(t).)
  const auto carry = [&](const auto& hit, const auto& bounced, const auto& flown) {
    tangent_flight_step(flight, q, double(flown.duration));
    const double kappa = table.curvature_at(hit.wall, hit.point);
    q = collision_jacobian<D>(velocity_at_wall(flight, hit.state), hit.normal, kappa,
                              acceleration_at(flight, hit.state), acceleration_at(flight, bounced)) *
        q;
    last = bounced;
    after(q, hit);
  };
  if constexpr (horizon_flight<Flight>) {
    made = evolve_to_horizons(table, flight, s, collisions, carry);
    return made < collisions ? s : last;
  } else {
    made = dynamics::evolve(table, flight, s, collisions, carry);
    return last;
  }
}

/// One trajectory's exponents: the sums of the logarithms of the stretches, its time and its
/// collisions.
template <int D>
struct BasicLyapunovTrajectory {
  std::array<double, 2 * D> log_stretch{};  // Σ log r_i, largest first
  double time = 0;
  std::uint64_t collisions = 0;
  bool escaped = false;
  bool trapped = false;  // on a magnetic orbit inside the table that meets no wall (no exponents)
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
    // A closed orbit that meets no wall circles inside the table (follow.hpp): not an escape;
    // nor is a horizon flight that has met none for wall_free_periods inside it.
    if constexpr (horizon_flight<Flight>) (table.contains(end.x) ? out.trapped : out.escaped) = true;
    else if constexpr (requires { flight.closes_orbit(end); })
      (flight.closes_orbit(end) ? out.trapped : out.escaped) = true;
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
