// Lyapunov exponents of 3-D tables (analysis/lyapunov.hpp with D = 3) against what is known
// without that code: the tangent map against finite differences (free flights, helices in a
// magnetic field, alone and under a static force or the drive), a vanishing maximal exponent in
// the cube and the ball, the conjugate pairing of the six exponents, and the 3-D Sinai table's
// maximal exponent, free, in a field and in a field with a force, from the divergence of two
// nearby orbits, renormalised (phase_space_helpers.hpp).
#include "cli_helpers.hpp"
#include "phase_space_helpers.hpp"

#include "billiards/analysis/lyapunov.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace billiards;
using Phase = Eigen::Matrix<double, 6, 1>;

namespace {

geometry3::Shape3 shape3(const std::string& name) {
  return geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/" + name);
}

Phase phase_point(const dynamics::State3& s) {
  Phase p;
  p << s.x, s.v;
  return p;
}

template <class Flight>
analysis::BasicLyapunovSpectrum<3> spectrum(const dynamics::Table3& table, const Flight& flight, std::size_t particles,
                                            std::size_t collisions, int threads = 2) {
  return analysis::lyapunov_spectrum(table, flight, dynamics::microcanonical(table, flight, 1.0, 11), particles,
                                     collisions, threads);
}

analysis::BasicLyapunovSpectrum<3> free_spectrum(const dynamics::Table3& table, std::size_t particles,
                                                 std::size_t collisions, int threads = 2) {
  return spectrum(table, dynamics::FreeFlight3{}, particles, collisions, threads);
}

/// A field strong enough to bend the flights visibly within the unit cube: r_c = 1/|Ω| ≈ 1.1 at
/// speed 1, across a direction in general position.
const dynamics::MagneticFlight3 helix{Eigen::Vector3d(0.3, 0.6, 0.6)};

/// The tangent map over 5 bounces in the 3-D Sinai table (to half way to the next) against
/// central differences of perturbed trajectories, column by column.
template <class Flight>
void check_against_finite_differences(const Flight& flight) {
  const auto sh = shape3("sinai3.yaml");
  const dynamics::Table3 table(sh.region);
  const auto initial = dynamics::microcanonical(table, flight, 1.0, 5);
  std::size_t sphere_hits = 0;
  for (std::size_t i = 0; i < 8; ++i) {
    const auto s = initial(i);
    auto q = analysis::BasicTangentBasis<3>::Identity().eval();
    std::size_t made = 0;
    const auto end = analysis::carry_tangent(table, flight, s, 5, q, made, [&](auto&, const auto& hit) {
      sphere_hits += hit.wall.kind == dynamics::wall_kind3::sphere;
    });
    REQUIRE(made == 5);
    const auto next = dynamics::collision(table, flight, end, end.t + 100);  // (a horizon flight needs one)
    REQUIRE(next.found());
    const double t_end = 0.5 * (end.t + next.t);
    analysis::tangent_flight_step(flight, q, t_end - end.t);
    const double h = 1e-7;
    for (int j = 0; j < 6; ++j) {
      auto plus = s, minus = s;
      (j < 3 ? plus.x[j] : plus.v[j - 3]) += h;
      (j < 3 ? minus.x[j] : minus.v[j - 3]) -= h;
      // (advance_to restores each orbit's own speed, so the velocity columns see the speed change too)
      const Phase fd = (phase_point(advance_to(table, flight, plus, t_end)) -
                        phase_point(advance_to(table, flight, minus, t_end))) / (2 * h);
      INFO("particle " << i << ", column " << j << ": tangent " << q.col(j).transpose() << ", finite differences "
                       << fd.transpose());
      CHECK((q.col(j) - fd).norm() <= 1e-4 * (1 + fd.norm()));
    }
  }
  CHECK(sphere_hits >= 3);  // (the ball's curvature entered the maps checked)
}

/// A field with a force: the static force, or a slow drive, with the field either way.
dynamics::MagneticDriveFlight3 with_static_force(const Eigen::Vector3d& omega_c) {
  return {omega_c, Eigen::Vector3d(0.2, -0.5, 0.3)};
}
dynamics::MagneticDriveFlight3 with_drive(const Eigen::Vector3d& omega_c, double amplitude = 1) {
  return {omega_c, amplitude * Eigen::Vector3d(1.0, 0.6, -0.8), 7.0, 0.3};
}

/// Six exponents in conjugate pairs, the volume kept: a Hamiltonian flow (a time-dependent one
/// under a drive).
void check_conjugate(const analysis::BasicLyapunovSpectrum<3>& r) {
  const double top = r.per_time[0].mean;
  CHECK(top > 0.5);
  CHECK(r.per_time[1].mean > 0.1 * top);  // a second positive exponent: two unstable directions
  for (std::size_t i = 0; i < r.trajectories.size(); ++i) {
    const auto& l = r.trajectories[i].log_stretch;
    CHECK(std::abs(l[0] + l[1] + l[2] + l[3] + l[4] + l[5]) < 1e-8 * std::abs(l[0]));  // det J = 1
    for (int k = 0; k < 3; ++k) CHECK(std::abs(r.exponent(i, k) + r.exponent(i, 5 - k)) < 0.01 * top);
  }
}

/// Conjugate pairs, the middle two zero: an autonomous flow that keeps its energy.
void check_pairs(const analysis::BasicLyapunovSpectrum<3>& r) {
  check_conjugate(r);
  for (std::size_t i = 0; i < r.trajectories.size(); ++i)
    CHECK(std::abs(r.exponent(i, 2)) < 0.01 * r.per_time[0].mean);  // the flow's direction and the energy
}

/// The maximal exponent from tangent dynamics against two nearby orbits' divergence rate
/// (phase_space_helpers.hpp) on the same trajectories, within 3 SE.
template <class Flight>
void check_against_divergence(const Flight& flight, std::size_t particles, std::size_t collisions) {
  const auto sh = shape3("sinai3.yaml");
  const dynamics::Table3 table(sh.region);
  const auto initial = dynamics::microcanonical(table, flight, 1.0, 17);
  const auto r = analysis::lyapunov_spectrum(table, flight, initial, particles, collisions, 2);
  std::vector<double> divergence;
  for (std::size_t i = 0; i < particles; ++i)
    divergence.push_back(
        divergence_rate(table, flight, initial(i), Eigen::Vector3d(0.6, 0, 0.8), collisions));
  const auto expected = analysis::sample_moments(divergence);
  INFO("tangent dynamics " << r.per_time[0].mean << " ± " << r.per_time[0].se << ", two orbits " << expected.mean
                           << " ± " << expected.se_mean);
  CHECK(r.per_time[0].se > 0);
  CHECK(std::abs(r.per_time[0].mean - expected.mean) < 3 * std::hypot(r.per_time[0].se, expected.se_mean));
}

}  // namespace

TEST_CASE("3-D: the tangent map equals finite differences on planes and spheres") {
  check_against_finite_differences(dynamics::FreeFlight3{});
}

TEST_CASE("3-D: the tangent map of helices in a magnetic field equals finite differences") {
  check_against_finite_differences(helix);
}

TEST_CASE("3-D: the tangent map of a field with a force (static, the drive) equals finite differences, both signs") {
  for (const Eigen::Vector3d& omega_c : {helix.omega_c, Eigen::Vector3d(-helix.omega_c)}) {
    INFO("omega_c " << omega_c.transpose());
    check_against_finite_differences(with_static_force(omega_c));
    check_against_finite_differences(with_drive(omega_c));
  }
}

TEST_CASE("3-D integrable tables (cube, ball): the maximal exponent vanishes, decreasing with the length") {
  const auto sinai = shape3("sinai3.yaml");
  const double chaotic = free_spectrum(dynamics::Table3(sinai.region), 6, 4000).per_time[0].mean;
  for (const char* name : {"cube.yaml", "ball.yaml"}) {
    INFO(name);
    const auto sh = shape3(name);
    const dynamics::Table3 table(sh.region);
    const auto short_run = free_spectrum(table, 6, 1000), long_run = free_spectrum(table, 6, 16000);
    CHECK(long_run.per_time[0].mean < 0.5 * short_run.per_time[0].mean);  // log(T)/T
    CHECK(long_run.per_time[0].mean < 0.01 * chaotic);
  }
}

TEST_CASE("3-D Sinai table: six exponents in conjugate pairs, two of them zero; in a magnetic field too") {
  const auto sh = shape3("sinai3.yaml");
  const dynamics::Table3 table(sh.region);
  check_pairs(free_spectrum(table, 6, 20000));
  check_pairs(spectrum(table, helix, 6, 20000));
  // A static force in the field keeps ½v² − (F/m)·x: two zeros again; under the drive, pairs.
  check_pairs(spectrum(table, with_static_force(helix.omega_c), 6, 20000));
  check_conjugate(spectrum(table, with_drive(-helix.omega_c), 6, 20000));
}

TEST_CASE("3-D Sinai table: the maximal exponent equals two nearby orbits' divergence rate, within 3 SE") {
  check_against_divergence(dynamics::FreeFlight3{}, 48, 6000);
}

TEST_CASE("3-D Sinai table in a magnetic field: the maximal exponent equals two orbits' divergence rate") {
  check_against_divergence(helix, 32, 6000);
}

TEST_CASE("3-D Sinai table in a field with a force: the maximal exponent equals two orbits' divergence rate") {
  check_against_divergence(with_static_force(helix.omega_c), 32, 6000);
  check_against_divergence(with_drive(-helix.omega_c, 0.15), 32, 3000);
}

TEST_CASE("billiard lyapunov on a 3-D shape: six exponents, the same for 1 and 2 threads") {
  const std::string cmd = "lyapunov shapes/3d/sinai3.yaml --particles 4 --collisions 3000 --json --quiet --threads ";
  const auto one = billiard(cmd + "1"), two = billiard(cmd + "2");
  INFO(one.output);
  REQUIRE(one.status == 0);
  REQUIRE(two.status == 0);
  CHECK(one.output == two.output);
  const auto j = nlohmann::json::parse(one.output);
  CHECK(j["dimension"] == 3);
  REQUIRE(j["spectrum"].size() == 6);
  CHECK(j["spectrum"][0].get<double>() > 0);
  CHECK(j["spectrum"][0].get<double>() == Approx(-j["spectrum"][5].get<double>()).epsilon(0.01));
  const auto driven = billiard("lyapunov scenes/sinai3-driven.yaml --particles 3 --collisions 1000 --json --quiet");
  INFO(driven.output);
  REQUIRE(driven.status == 0);
  CHECK(nlohmann::json::parse(driven.output)["spectrum"].size() == 6);
  const auto magnetic = billiard("lyapunov scenes/sinai3-magnetic.yaml --particles 3 --collisions 1000 --json --quiet");
  INFO(magnetic.output);
  REQUIRE(magnetic.status == 0);
  const auto m = nlohmann::json::parse(magnetic.output);
  REQUIRE(m["spectrum"].size() == 6);
  CHECK(m["spectrum"][0].get<double>() == Approx(-m["spectrum"][5].get<double>()).epsilon(0.01));
  const auto forced =
      billiard("lyapunov scenes/sinai3-magnetic-driven.yaml --particles 3 --collisions 1000 --json --quiet");
  INFO(forced.output);
  REQUIRE(forced.status == 0);
  const auto f = nlohmann::json::parse(forced.output);
  REQUIRE(f["spectrum"].size() == 6);
  CHECK(f["magnetic"] == true);
  CHECK(f["force"] == "periodic");
  for (int k = 0; k < 3; ++k)
    CHECK(f["spectrum"][k].get<double>() == Approx(-f["spectrum"][5 - k].get<double>()).epsilon(0.01));
}
