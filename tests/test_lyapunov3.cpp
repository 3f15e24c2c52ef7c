// Lyapunov exponents of 3-D tables (analysis/lyapunov.hpp with D = 3) against what is known
// without that code: the tangent map against finite differences, a vanishing maximal exponent
// in the cube and the ball, the conjugate pairing of the six exponents, and the 3-D Sinai
// table's maximal exponent from the divergence of two nearby orbits, renormalised, written here.
#include "cli_helpers.hpp"

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

/// The free flight from s to time t_end, through the bounces before it.
dynamics::State3 advance_to(const dynamics::Table3& table, dynamics::State3 s, double t_end) {
  const dynamics::FreeFlight3 flight;
  const double v2 = s.v.squaredNorm();
  for (;;) {
    const auto hit = dynamics::collision(table, flight, s, t_end);
    if (!hit.found()) return flight.advance(s, t_end);
    dynamics::bounce(flight, s, hit);
    dynamics::restore_speed(s.v, v2);
  }
}

analysis::BasicLyapunovSpectrum<3> free_spectrum(const dynamics::Table3& table, std::size_t particles,
                                                 std::size_t collisions, int threads = 2) {
  return analysis::lyapunov_spectrum(table, dynamics::FreeFlight3{},
                                     dynamics::microcanonical(table, dynamics::FreeFlight3{}, 1.0, 11), particles,
                                     collisions, threads);
}

}  // namespace

TEST_CASE("3-D: the tangent map equals finite differences on planes and spheres") {
  const auto sh = shape3("sinai3.yaml");
  const dynamics::Table3 table(sh.region);
  const dynamics::FreeFlight3 flight;
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
    const double t_end = 0.5 * (end.t + dynamics::collision(table, flight, end).t);
    analysis::tangent_flight_step<3>(q, t_end - end.t);
    const double h = 1e-7;
    for (int j = 0; j < 6; ++j) {
      auto plus = s, minus = s;
      (j < 3 ? plus.x[j] : plus.v[j - 3]) += h;
      (j < 3 ? minus.x[j] : minus.v[j - 3]) -= h;
      // (advance_to restores each orbit's own speed, so the velocity columns see the speed change too)
      const Phase fd = (phase_point(advance_to(table, plus, t_end)) - phase_point(advance_to(table, minus, t_end))) / (2 * h);
      INFO("particle " << i << ", column " << j << ": tangent " << q.col(j).transpose() << ", finite differences "
                       << fd.transpose());
      CHECK((q.col(j) - fd).norm() <= 1e-4 * (1 + fd.norm()));
    }
  }
  CHECK(sphere_hits >= 3);  // (the ball's curvature entered the maps checked)
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

TEST_CASE("3-D Sinai table: six exponents in conjugate pairs, two of them zero") {
  const auto sh = shape3("sinai3.yaml");
  const auto r = free_spectrum(dynamics::Table3(sh.region), 6, 20000);
  const double top = r.per_time[0].mean;
  CHECK(top > 0.5);
  CHECK(r.per_time[1].mean > 0.1 * top);  // a second positive exponent: two unstable directions
  for (std::size_t i = 0; i < r.trajectories.size(); ++i) {
    const auto& l = r.trajectories[i].log_stretch;
    CHECK(std::abs(l[0] + l[1] + l[2] + l[3] + l[4] + l[5]) < 1e-8 * std::abs(l[0]));  // det J = 1
    for (int k = 0; k < 3; ++k) CHECK(std::abs(r.exponent(i, k) + r.exponent(i, 5 - k)) < 0.01 * top);
    CHECK(std::abs(r.exponent(i, 2)) < 0.01 * top);  // the flow's direction and the energy
  }
}

TEST_CASE("3-D Sinai table: the maximal exponent equals two nearby orbits' divergence rate, within 3 SE") {
  // Two orbits δ0 apart in phase space, compared after every interval Δ and the second put back
  // at distance δ0 along their separation (Benettin et al. 1976), with the first's speed.
  const auto sh = shape3("sinai3.yaml");
  const dynamics::Table3 table(sh.region);
  const auto initial = dynamics::microcanonical(table, dynamics::FreeFlight3{}, 1.0, 17);
  const std::size_t particles = 48, collisions = 6000;
  const double delta0 = 1e-9, interval = 1.0;
  const auto r = analysis::lyapunov_spectrum(table, dynamics::FreeFlight3{}, initial, particles, collisions, 2);
  std::vector<double> divergence;
  for (std::size_t i = 0; i < particles; ++i) {
    auto a = initial(i);
    auto b = a;
    b.x += delta0 * Eigen::Vector3d(0.6, 0, 0.8);
    double sum = 0;
    const double t_end = r.trajectories[i].time;
    const int steps = int(t_end / interval);
    for (int k = 1; k <= steps; ++k) {
      a = advance_to(table, a, k * interval);
      b = advance_to(table, b, k * interval);
      const Phase d = phase_point(b) - phase_point(a);
      sum += std::log(d.norm() / delta0);
      const Phase renormalised = phase_point(a) + d * (delta0 / d.norm());
      b.x = renormalised.head<3>();
      b.v = renormalised.tail<3>().normalized() * a.v.norm();
    }
    divergence.push_back(sum / (steps * interval));
  }
  const auto expected = analysis::sample_moments(divergence);
  INFO("tangent dynamics " << r.per_time[0].mean << " ± " << r.per_time[0].se << ", two orbits " << expected.mean
                           << " ± " << expected.se_mean);
  CHECK(r.per_time[0].se > 0);
  CHECK(std::abs(r.per_time[0].mean - expected.mean) <
        3 * std::hypot(r.per_time[0].se, expected.se_mean));
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
}
