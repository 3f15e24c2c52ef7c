// Lyapunov exponents from tangent dynamics (analysis/lyapunov.hpp) against what is known
// without that code: the tangent map against finite differences of two trajectories (free
// flights on every wall kind, the periodic drive in the lab and off quivering walls, a static
// force, a magnetic field alone and with a force), zero exponents in the integrable circle (in
// a field too), square and ellipse, the conjugate pairing of the spectrum, the Sinai table's
// maximal exponent from the wave-front curvature recursion written here, and in a field, with
// a force or off quivering walls from the divergence of two nearby orbits
// (phase_space_helpers.hpp).
#include "cli_helpers.hpp"
#include "phase_space_helpers.hpp"

#include "billiards/analysis/lyapunov.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace billiards;
using analysis::TangentBasis;

namespace {

Eigen::Vector4d phase_point(const dynamics::State& s) { return {s.x.x(), s.x.y(), s.v.x(), s.v.y()}; }

/// The tangent map over `collisions` bounces (to half way to the next) against central
/// differences of perturbed trajectories (phase_space_helpers.hpp's advance_to, which searches
/// each flight to the time asked), column by column.
template <class Flight>
void check_against_finite_differences(const dynamics::Table& table, const Flight& flight,
                                      const typename Flight::State& s, std::size_t collisions) {
  TangentBasis q = TangentBasis::Identity();
  std::size_t made = 0;
  const auto end = analysis::carry_tangent(table, flight, s, collisions, q, made, [](auto&, const auto&) {});
  REQUIRE(made == collisions);
  const auto next = dynamics::collision(table, flight, end, end.t + 100);  // (a horizon flight needs one)
  REQUIRE(next.found());
  const double t_end = 0.5 * (end.t + next.t);
  analysis::tangent_flight_step(flight, q, t_end - end.t);
  const double h = 1e-7;
  for (int j = 0; j < 4; ++j) {
    auto plus = s, minus = s;
    const auto shift = [&](auto& state, double sign) {
      if (j < 2) state.x[j] += sign * h;
      else state.v[j - 2] += sign * h;
    };
    shift(plus, 1);
    shift(minus, -1);
    const Eigen::Vector4d fd = (phase_point(advance_to(table, flight, plus, t_end)) -
                                phase_point(advance_to(table, flight, minus, t_end))) / (2 * h);
    INFO("column " << j << ": tangent " << q.col(j).transpose() << ", finite differences " << fd.transpose());
    CHECK((q.col(j) - fd).norm() <= 1e-4 * (1 + fd.norm()));
  }
}

template <class Flight>
analysis::LyapunovSpectrum spectrum(const std::string& name, const Flight& flight, std::size_t particles,
                                    std::size_t collisions, int threads = 2) {
  const auto s = bundled_shape(name);
  const dynamics::Table table(s.region);
  return analysis::lyapunov_spectrum(table, flight, dynamics::microcanonical(table, flight, 1.0, 11), particles,
                                     collisions, threads);
}

analysis::LyapunovSpectrum free_spectrum(const std::string& name, std::size_t particles, std::size_t collisions,
                                         int threads = 2) {
  return spectrum(name, dynamics::FreeFlight{}, particles, collisions, threads);
}

/// A field that bends the flights visibly in the bundled tables (r_c = 1.25 at speed 1; Ω > 0
/// turns clockwise) without leaving room for a cyclotron orbit inside them.
const dynamics::MagneticFlight field{0.8};

/// A field with a force: the static force, or a slow drive (both bending the flights visibly
/// between collisions), with the field either way.
dynamics::MagneticDriveFlight with_static_force(double omega_c) { return {omega_c, geometry::Vec2(0.4, -0.9)}; }
dynamics::MagneticDriveFlight with_drive(double omega_c, double amplitude = 1) {
  return {omega_c, amplitude * geometry::Vec2(1.5, 1), 7.0, 0.3};
}

/// The spectrum's conjugate pairs, λ1 = −λ4 and λ2 = −λ3 per trajectory, and det J = 1: the
/// flow is Hamiltonian (a time-dependent one under a drive).
void check_conjugate(const analysis::LyapunovSpectrum& r) {
  const double top = r.per_time[0].mean;
  CHECK(top > 0.1);
  for (std::size_t i = 0; i < r.trajectories.size(); ++i) {
    const auto& l = r.trajectories[i].log_stretch;
    CHECK(std::abs(l[0] + l[1] + l[2] + l[3]) < 1e-8 * std::abs(l[0]));  // det J = 1
    CHECK(std::abs(r.exponent(i, 0) + r.exponent(i, 3)) < 0.01 * top);
    CHECK(std::abs(r.exponent(i, 1) + r.exponent(i, 2)) < 0.01 * top);
  }
}

/// Conjugate pairs, and λ2 = λ3 = 0 per trajectory: an autonomous flow that keeps its energy.
void check_pairs(const analysis::LyapunovSpectrum& r) {
  check_conjugate(r);
  for (std::size_t i = 0; i < r.trajectories.size(); ++i)
    CHECK(std::abs(r.exponent(i, 1)) < 0.01 * r.per_time[0].mean);  // the flow's direction and the energy
}

/// The Sinai table's maximal exponent from tangent dynamics against two nearby orbits'
/// divergence rate (phase_space_helpers.hpp) from the same initial states, within 3 SE.
template <class Flight>
void check_against_divergence(const Flight& flight, std::size_t particles, std::size_t collisions) {
  const auto sh = bundled_shape("sinai.yaml");
  const dynamics::Table table(sh.region);
  const auto initial = dynamics::microcanonical(table, flight, 1.0, 17);
  const auto r = analysis::lyapunov_spectrum(table, flight, initial, particles, collisions, 2);
  std::vector<double> divergence;
  for (std::size_t i = 0; i < particles; ++i)
    divergence.push_back(divergence_rate(table, flight, initial(i), geometry::Vec2(0.6, 0.8), collisions));
  const auto expected = analysis::sample_moments(divergence);
  INFO("tangent dynamics " << r.per_time[0].mean << " ± " << r.per_time[0].se << ", two orbits " << expected.mean
                           << " ± " << expected.se_mean);
  CHECK(r.per_time[0].se > 0);
  CHECK(std::abs(r.per_time[0].mean - expected.mean) < 3 * std::hypot(r.per_time[0].se, expected.se_mean));
}

}  // namespace

TEST_CASE("the tangent map equals finite differences: free flights on segments, arcs and elliptic arcs") {
  for (const char* name : {"sinai.yaml", "clover.yaml", "elliptic-stadium.yaml", "sinai-ellipse.yaml", "mushroom.yaml"}) {
    INFO(name);
    const auto sh = bundled_shape(name);
    const dynamics::Table table(sh.region);
    const auto initial = dynamics::microcanonical(table, dynamics::FreeFlight{}, 1.0, 5);
    for (std::size_t i = 0; i < 4; ++i) check_against_finite_differences(table, dynamics::FreeFlight{}, initial(i), 4);
  }
}

TEST_CASE("the tangent map equals finite differences under the periodic drive and a static force") {
  const auto scene = bundled_scene("sinai-ellipse-driven.yaml", 4);
  const dynamics::Table table(scene.shape<2>().region);
  // A slow drive, so that the force changes the flights between collisions visibly.
  const dynamics::PeriodicDriveFlight drive{geometry::Vec2(3, 1), 7.0, 0.3};
  const dynamics::ConstantForceFlight gravity{geometry::Vec2(0.4, -2)};
  const auto initial = dynamics::microcanonical(table, dynamics::FreeFlight{}, 1.0, 9);
  for (std::size_t i = 0; i < 4; ++i) {
    check_against_finite_differences(table, drive, drive.start(initial(i)), 4);
    check_against_finite_differences(table, gravity, initial(i), 4);
  }
}

TEST_CASE("the tangent map equals finite differences off quivering walls") {
  // The drive seen from the walls: straight flights, walls that move (their velocity and
  // acceleration enter the collision Jacobian); the drive either way.
  for (const char* name : {"sinai.yaml", "clover.yaml", "sinai-ellipse.yaml"}) {
    INFO(name);
    const auto sh = bundled_shape(name);
    const dynamics::Table table(sh.region);
    const auto initial = dynamics::microcanonical(table, dynamics::FreeFlight{}, 1.0, 9);
    for (const double sign : {1.0, -1.0}) {
      const dynamics::QuiveringWallFlight quiver{sign * geometry::Vec2(3, 1), 7.0, 0.3};
      for (std::size_t i = 0; i < 4; ++i) check_against_finite_differences(table, quiver, quiver.start(initial(i)), 4);
    }
  }
}

TEST_CASE("the tangent map equals finite differences in a magnetic field with a force, both field signs") {
  // (Searched to a horizon; elliptic arcs and all the others by the certified scan.)
  for (const char* name : {"sinai.yaml", "clover.yaml", "stadium.yaml", "sinai-ellipse.yaml"}) {
    INFO(name);
    const auto sh = bundled_shape(name);
    const dynamics::Table table(sh.region);
    const auto initial = dynamics::microcanonical(table, field, 1.0, 5);
    for (const double omega_c : {field.omega_c, -field.omega_c}) {
      INFO("omega_c " << omega_c);
      for (std::size_t i = 0; i < 4; ++i) {
        for (const auto& flight : {with_static_force(omega_c), with_drive(omega_c)})
          check_against_finite_differences(table, flight, flight.start(initial(i)), 4);
      }
    }
  }
}

TEST_CASE("the tangent map equals finite differences in a magnetic field, on every wall kind") {
  // (Elliptic arcs: found by the certified scan; segments and circular arcs: closed forms.)
  for (const char* name : {"sinai.yaml", "clover.yaml", "stadium.yaml", "sinai-ellipse.yaml"}) {
    INFO(name);
    const auto sh = bundled_shape(name);
    const dynamics::Table table(sh.region);
    const auto initial = dynamics::microcanonical(table, field, 1.0, 5);
    for (std::size_t i = 0; i < 4; ++i) check_against_finite_differences(table, field, initial(i), 4);
    const dynamics::MagneticFlight reversed{-field.omega_c};
    for (std::size_t i = 4; i < 8; ++i) check_against_finite_differences(table, reversed, initial(i), 4);
  }
}

TEST_CASE("integrable tables: the maximal exponent vanishes, decreasing with the trajectory's length") {
  const double chaotic = free_spectrum("stadium.yaml", 8, 4000).per_time[0].mean;
  for (const char* name : {"circle.yaml", "square.yaml", "ellipse.yaml"}) {
    INFO(name);
    const auto short_run = free_spectrum(name, 8, 1000), long_run = free_spectrum(name, 8, 16000);
    // Perturbations grow linearly: the estimate falls like log(T)/T.
    CHECK(long_run.per_time[0].mean < 0.5 * short_run.per_time[0].mean);
    CHECK(long_run.per_time[0].mean < 0.01 * chaotic);
  }
}

TEST_CASE("the circle in a magnetic field is integrable: the maximal exponent vanishes") {
  // The canonical angular momentum about the centre is kept by the flights and the bounces.
  const double chaotic = spectrum("stadium.yaml", field, 8, 4000).per_time[0].mean;
  const auto short_run = spectrum("circle.yaml", field, 8, 1000), long_run = spectrum("circle.yaml", field, 8, 16000);
  CHECK(long_run.per_time[0].mean < 0.5 * short_run.per_time[0].mean);
  CHECK(long_run.per_time[0].mean < 0.01 * chaotic);
}

TEST_CASE("cyclotron orbits that meet no wall are trapped, left out of the exponents, not escapes") {
  // In the unit circle with r_c = 1/4, the orbit from x circles about c = x + w0/k and stays
  // inside exactly when |c| + r_c < 1.
  const dynamics::MagneticFlight strong{4.0};
  const auto sh = bundled_shape("circle.yaml");
  const dynamics::Table table(sh.region);
  const auto initial = dynamics::microcanonical(table, strong, 1.0, 3);
  const auto r = analysis::lyapunov_spectrum(table, strong, initial, 40, 200, 2);
  std::size_t inside = 0;
  for (std::size_t i = 0; i < 40; ++i) {
    const auto s = initial(i);
    const geometry::Vec2 center = s.x + geometry::Vec2(s.v.y(), -s.v.x()) / strong.omega_c;
    const bool stays = center.norm() + s.v.norm() / strong.omega_c < 1;
    inside += stays;
    CHECK(r.trajectories[i].trapped == stays);
    CHECK(r.trajectories[i].collisions == (stays ? 0u : 200u));
  }
  CHECK(inside > 0);
  CHECK(r.trapped() == inside);
  CHECK(r.escapes() == 0);
}

TEST_CASE("a trajectory's exponents do not depend on when it starts: each flight's tangent flow over its own duration") {
  // The same orbit started at t = 1e8 + 1/8 instead of 0: each flight runs on its own clock, so
  // the flights, their durations and the stretches are the same bit for bit.  A duration taken
  // as the difference of two absolute hit times would be rounded to ulp(1e8) = 1.5e-8, which
  // moves every stretch.
  const auto sh = bundled_shape("stadium.yaml");
  const dynamics::Table table(sh.region);
  dynamics::State s;
  s.x = geometry::Vec2(0.1, 0.2);
  s.v = geometry::Vec2(std::cos(0.7), std::sin(0.7));
  auto late = s;
  late.t = 1e8 + 0.125;
  auto check = [&](const auto& flight) {
    const auto a = analysis::lyapunov_trajectory(table, flight, s, 2000),
               b = analysis::lyapunov_trajectory(table, flight, late, 2000);
    for (int k = 0; k < 4; ++k) CHECK(b.log_stretch[k] == a.log_stretch[k]);
    CHECK(std::abs(b.time - a.time) <= 1.5e-8);  // (b's end time absolute: rounded to ulp(1e8))
  };
  check(dynamics::FreeFlight{});
  check(field);
}

TEST_CASE("the spectrum comes in conjugate pairs that sum to zero") {
  for (const char* name : {"stadium.yaml", "clover.yaml", "sinai-ellipse.yaml"}) {
    INFO(name);
    check_pairs(free_spectrum(name, 6, 20000));
  }
  // In a magnetic field the flow is Hamiltonian and keeps the energy: pairs and two zeros.
  for (const char* name : {"stadium.yaml", "sinai.yaml"}) {
    INFO(name << " in a magnetic field");
    check_pairs(spectrum(name, field, 6, 20000));
  }
  // A static force in the field keeps ½v² − (F/m)·x and the flow autonomous: two zeros again.
  check_pairs(spectrum("stadium.yaml", with_static_force(field.omega_c), 6, 20000));
  // Under the drive the energy changes, but the flow stays Hamiltonian: pairs again, in the lab,
  // off quivering walls and in a field.
  const auto scene = bundled_scene("clover-driven.yaml", 4);
  const dynamics::Table table(scene.shape<2>().region);
  const geometry::Vec2 accel = scene.force.amplitude / scene.mass;
  const auto drive_spectrum = [&](const auto& flight) {
    return analysis::lyapunov_spectrum(table, flight, dynamics::initial_states(scene, table, flight), 4, 20000, 2);
  };
  check_conjugate(drive_spectrum(dynamics::PeriodicDriveFlight{accel, scene.force.omega, scene.force.phase}));
  check_conjugate(drive_spectrum(dynamics::QuiveringWallFlight{accel, scene.force.omega, scene.force.phase}));
  check_conjugate(
      drive_spectrum(dynamics::MagneticDriveFlight{-field.omega_c, accel, scene.force.omega, scene.force.phase}));
}

TEST_CASE("Sinai table: the maximal exponent equals the wave-front curvature recursion's, within 3 SE") {
  // An independent method on the same trajectories: B, the curvature of the unstable wave front
  // just after a bounce, grows the front by |1 + τB| over a flight τ (speed 1), and becomes
  // B/(1 + τB) there; a bounce adds 2K/cos φ, K the wall's dispersing curvature (−κ).
  const auto sh = bundled_shape("sinai.yaml");
  const dynamics::Table table(sh.region);
  const auto initial = dynamics::microcanonical(table, dynamics::FreeFlight{}, 1.0, 11);
  const std::size_t particles = 24, collisions = 20000;
  std::vector<double> recursion;
  for (std::size_t i = 0; i < particles; ++i) {
    const auto s0 = initial(i);
    double B = 0, sum = 0, t = s0.t, t_end = s0.t;
    dynamics::evolve(table, dynamics::FreeFlight{}, s0, collisions, [&](const auto& hit, const auto&) {
      const double tau = hit.t - t;
      sum += std::log(std::abs(1 + tau * B));
      B = B / (1 + tau * B);
      const double cos_phi = hit.state.v.dot(hit.normal) / hit.state.v.norm();
      B += -2 * table.curvature_at(hit.wall, hit.point) / cos_phi;
      t = t_end = hit.t;
    });
    recursion.push_back(sum / (t_end - s0.t));
  }
  const auto expected = analysis::sample_moments(recursion);
  const auto r = analysis::lyapunov_spectrum(table, dynamics::FreeFlight{}, initial, particles, collisions, 2);
  INFO("tangent dynamics " << r.per_time[0].mean << " ± " << r.per_time[0].se << ", recursion " << expected.mean
                           << " ± " << expected.se_mean);
  CHECK(r.per_time[0].se > 0);
  CHECK(std::abs(r.per_time[0].mean - expected.mean) < 3 * r.per_time[0].se);
}

TEST_CASE("Sinai table in a magnetic field: the maximal exponent equals two orbits' divergence rate, within 3 SE") {
  check_against_divergence(field, 32, 6000);
}

TEST_CASE("Sinai table in a field with a force, and off quivering walls: the maximal exponent equals two orbits'") {
  check_against_divergence(with_static_force(field.omega_c), 32, 6000);
  // (A weak drive, a/ω = 0.04, so that the energy stays of order 1 over the trajectories.)
  check_against_divergence(with_drive(-field.omega_c, 0.15), 64, 3000);
  check_against_divergence(dynamics::QuiveringWallFlight{geometry::Vec2(0.2, -0.15), 7.0, 0.3}, 64, 3000);
}

TEST_CASE("a field with a force: orbits that meet no wall in wall_free_periods are trapped, not escapes") {
  // In the unit circle with r_c = 1/4 a weak drive far from the resonance (ω = 1, |Ω| = 4) moves
  // the cyclotron circle by ~a/(Ω² − ω²) = 0.003: the orbit from x meets the wall exactly when
  // |c| + r_c > 1 (c = x + w0/k), but for orbits within 0.01 of touching it.  A static force
  // makes the centre drift at |F|/(m|Ω|) across the field: every orbit meets the wall.
  const auto sh = bundled_shape("circle.yaml");
  const dynamics::Table table(sh.region);
  const dynamics::MagneticDriveFlight drive{4.0, geometry::Vec2(0.03, 0.04), 1.0, 0.3},
      drift{4.0, geometry::Vec2(0.12, 0.16)};
  const auto initial = dynamics::microcanonical(table, drive, 1.0, 3);
  const auto r = analysis::lyapunov_spectrum(table, drive, initial, 40, 200, 2);
  std::size_t inside = 0, outside = 0;
  for (std::size_t i = 0; i < 40; ++i) {
    const auto s = initial(i);
    const geometry::Vec2 center = s.x + geometry::Vec2(s.v.y(), -s.v.x()) / drive.omega_c;
    const double reach = center.norm() + s.v.norm() / drive.omega_c;
    if (std::abs(reach - 1) < 0.01) continue;
    (reach < 1 ? inside : outside) += 1;
    CHECK(r.trajectories[i].trapped == (reach < 1));
    CHECK(r.trajectories[i].collisions == (reach < 1 ? 0u : 200u));
  }
  CHECK(inside > 0);
  CHECK(outside > 0);
  CHECK(r.escapes() == 0);
  const auto drifting = analysis::lyapunov_spectrum(table, drift, initial, 40, 200, 2);
  CHECK(drifting.trapped() == 0);
  CHECK(drifting.escapes() == 0);
}

TEST_CASE("the exponents are identical for any thread count") {
  const auto one = free_spectrum("clover.yaml", 5, 2000, 1), two = free_spectrum("clover.yaml", 5, 2000, 2);
  for (std::size_t i = 0; i < 5; ++i) CHECK(one.trajectories[i].log_stretch == two.trajectories[i].log_stretch);
}

TEST_CASE("billiard lyapunov --json: its keys, and a scene's flight") {
  auto r = billiard("lyapunov shapes/sinai.yaml --particles 4 --collisions 3000 --json --quiet");
  INFO(r.output);
  REQUIRE(r.status == 0);
  auto j = nlohmann::json::parse(r.output);
  for (const char* key : {"lyapunov", "lyapunov_se", "lyapunov_per_collision", "lyapunov_per_collision_se"})
    CHECK(j[key].is_number());
  CHECK(j["spectrum"].size() == 4);
  CHECK(j["speed"] == 1.0);
  // λ per unit time = λ per collision / mean free time.
  CHECK(j["lyapunov"].get<double>() ==
        Approx(j["lyapunov_per_collision"].get<double>() / j["mean_free_time"].get<double>()).epsilon(0.05));
  r = billiard("lyapunov scenes/clover-driven.yaml --particles 3 --collisions 2000 --json --quiet");
  REQUIRE(r.status == 0);
  j = nlohmann::json::parse(r.output);
  CHECK(j["force"] == "periodic");
  CHECK(j["lyapunov"].get<double>() > 0);
  r = billiard("lyapunov scenes/stadium-magnetic.yaml --particles 3 --collisions 2000 --json --quiet");
  INFO(r.output);
  REQUIRE(r.status == 0);
  j = nlohmann::json::parse(r.output);
  CHECK(j["lyapunov"].get<double>() > 0);
  CHECK(j["spectrum"][0].get<double>() == Approx(-j["spectrum"][3].get<double>()).epsilon(0.01));
  CHECK(j["trapped"] == 0);
  r = billiard("lyapunov scenes/clover-magnetic-driven.yaml --particles 3 --collisions 2000 --json --quiet");
  INFO(r.output);
  REQUIRE(r.status == 0);
  j = nlohmann::json::parse(r.output);
  CHECK(j["force"] == "periodic");
  CHECK(j["magnetic"] == true);
  CHECK(j["lyapunov"].get<double>() > 0);
  CHECK(j["spectrum"][0].get<double>() == Approx(-j["spectrum"][3].get<double>()).epsilon(0.01));
  CHECK(j["spectrum"][1].get<double>() == Approx(-j["spectrum"][2].get<double>()).epsilon(0.01));
  r = billiard("lyapunov scenes/clover-magnetic-driven.yaml --particles 3 --collisions 500 --quiet");
  REQUIRE(r.status == 0);
  CHECK(r.output.find("lambda_4 = ") != std::string::npos);
  // The integrated flight (a position-dependent force, or a potential) is the one refused.
  r = billiard("lyapunov scenes/clover-field.yaml --particles 3 --collisions 10 --quiet");
  CHECK(r.status == 2);
  CHECK(r.output.find("billiard: error: scenes/clover-field.yaml: Lyapunov exponents are computed for") != std::string::npos);
  CHECK(r.output.find("quivering walls") != std::string::npos);
  CHECK(r.output.find("not for a position-dependent force or a potential (this scene: force field)") !=
        std::string::npos);
}
