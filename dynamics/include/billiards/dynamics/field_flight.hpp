// Flights in a general field: m ẍ = −∇U(x) + F(x) cos(ω t + phase), for scenes whose force
// has no closed form (a position-dependent drive amplitude, a potential, or both).
//
// Integration: Dormand–Prince 5(4) with step-size control and its 4th-order continuous
// extension (Hairer, Nørsett & Wanner, "Solving ODEs I", DOPRI5).  Every accepted step is kept
// (its five dense-output coefficient vectors) in a FieldPath owned by the state the flight
// started from, so that the collision point, the energies at record times and the midpoint
// check all read the same piecewise polynomial the event search scanned.  (Boost.Odeint's dense
// output keeps only the current step inside its stepper, hence a small integrator of our own.)
//
// Events: per step, each wall's gap f along the dense output is scanned by the certified scan
// (certified_scan.hpp) with |f''| bounded by the wall's `gap_sample` (walls.hpp) from the
// acceleration bound A (a bound on |∇U|/m + |F|/m over the table's bounding box, by sampling
// with a Lipschitz margin, computed once): A for a segment, 2V²/ρ + A for an arc or an
// elliptic arc.  The scan cannot step over a crossing of the polynomial trajectory.  The scan of a wall resumes across steps where it left
// off, so walls far away cost nothing per step.  The certificate is relative to the integrated
// trajectory: a graze shallower than the integrator's error may be decided either way.
//
// Energy: with F = 0 the exact flow conserves E = ½mv² + U(x); the integrated one drifts by
// the integrator's error, which is reported (bench_field, BENCHMARKS.md) and not corrected, so
// that a run shows its own accuracy.
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/dynamics/scene.hpp"

#include <Eigen/Core>

#include <memory>
#include <optional>
#include <vector>

namespace billiards::dynamics {

/// The dense output of one integrated flight: accepted steps in order, τ measured from the
/// start state (x0, v0, t0).
struct FieldPath {
  using Vec4 = Eigen::Vector4d;  // (x, y, vx, vy)
  struct Step {
    double tau0, h;
    Vec4 r[5];  // y(τ0 + θh) = r0 + θ(r1 + (1−θ)(r2 + θ(r3 + (1−θ) r4)))
  };
  Vec2 x0, v0;
  double t0 = 0;
  std::vector<Step> steps;

  bool starts_at(const BasicState<double>& s) const { return s.t == t0 && s.x == x0 && s.v == v0; }
  double end() const { return steps.empty() ? 0 : steps.back().tau0 + steps.back().h; }
  /// (x, v) at τ ∈ [0, end()].
  Vec4 at(double tau) const;
  static Vec4 at(const Step& step, double tau);
};

/// State in a field: the state, the drive's phase, the step size to start the next flight
/// with, and (once a collision search has run from it) the flight's dense output.
struct FieldState : BasicState<double> {
  Phase phase;            // θ = ω t + phase, reduced to [0, 2π)
  double step = 0;        // first trial step of the next flight (0: choose one)
  mutable std::shared_ptr<const FieldPath> path;
};

class FieldFlight {
 public:
  using Scalar = double;
  using State = FieldState;
  static constexpr bool conserves_energy = false;  // restored by nothing: see the header comment

  /// The scene's field: `force` of kind field (F(x) cos(ωt + phase)), periodic or constant
  /// (uniform, integrated too), or none; `potential` if any.  `tolerance` is the integrator's
  /// relative tolerance (the absolute one is tolerance × the table's size).  A force that is not
  /// finite at a point of the grid on which the acceleration bound is sampled, over the table's
  /// bounding box, is bad input: InputError at the key of the field (`field_source`) or of the
  /// potential (`source`).  (parse_scene makes the flight of every scene that needs one.)
  FieldFlight(const Force& force, const std::optional<Potential>& potential, double mass, const Table& table,
              double tolerance);

  State start(const BasicState<double>& s) const;
  State advance(const State& s, double t) const;
  /// Through any wall kind (field_flight.cpp instantiates every kind of WallKinds).
  template <class Wall>
  double exit_time(const State& s, const Wall& w, double t_end) const;

  /// U(x) (0 without a potential): ensembles record E = ½mv² + U.
  double potential(const Vec2& x) const;
  double mass() const;
  /// The bound A ≥ |∇U|/m + |F|/m over the table's bounding box used by the event search.
  double acceleration_bound() const;

  /// The first wall the flight from s leaves through before t_end; keeps the flight's dense
  /// output in s.path.
  Hit first_exit(const Table& table, const State& s, double t_end) const;

  struct Model;

 private:
  std::shared_ptr<const Model> model_;
};

/// `collision` for field flights: one integration for all walls (the generic version would
/// integrate once per wall).
Hit collision(const Table& table, const FieldFlight& flight, const FieldState& s, double t_end = never);

/// Microcanonical ensemble at energy E = ½ m speed² in the field's potential: x uniform over the
/// allowed part {U(x) < E} of the table, direction uniform, |v| = √(2(E − U(x))/m).
inline auto microcanonical(const Table& table, const FieldFlight& flight, double speed, std::uint64_t seed) {
  const double E = 0.5 * flight.mass() * speed * speed;
  return [&table, flight, E, seed](std::size_t i) {
    ParticleRng rng(seed, i);
    return flight.start(sample_microcanonical(
        table, E, flight.mass(), [&](const Vec2& x) { return flight.potential(x); }, rng));
  };
}

}  // namespace billiards::dynamics
