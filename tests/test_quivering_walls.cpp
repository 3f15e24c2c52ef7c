// The paper's equivalence (section 6) between the uniform drive F cos(ωt + φ) and walls that
// translate by F cos(ωt + φ)/(mω²) around a free particle: QuiveringWallFlight against the lab
// picture (PeriodicDriveFlight), collision by collision and in ensemble statistics, and the
// scene option `picture: quivering-walls` in `billiard run`.
#include "billiards/analysis.hpp"
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/geometry.hpp"

#include "cli_helpers.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>

using namespace billiards;
using dynamics::PeriodicDriveFlight;
using dynamics::QuiveringWallFlight;
using geometry::pi;
using geometry::Vec2;

namespace {

const geometry::Shape& clover() {
  static const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
  return shape;
}

const Vec2 force = 10 / std::sqrt(2.0) * Vec2(1, 1);  // the paper's F = 10 along (1,1)/√2, m = 1

}  // namespace

TEST_CASE("one trajectory: the same walls at the same times; the velocities differ by wall velocity") {
  const dynamics::Table table(clover().region);
  for (const double omega : {40 * pi, 320 * pi})
    for (const double phase : {0.0, 0.7}) {
      const PeriodicDriveFlight lab{force, omega, phase};
      const QuiveringWallFlight moving{force, omega, phase};
      for (std::uint64_t particle = 0; particle < 4; ++particle) {
        dynamics::ParticleRng rng(7, particle);
        const dynamics::State s = dynamics::sample_microcanonical(table, 1.0, rng);
        auto x = lab.start(s);
        // The same particle seen from the frame y = x + d(t): ẏ = ẋ + ḋ, ḋ = −F sin(φ)/(mω).
        dynamics::State s_moving = s;
        s_moving.v = s.v - force / omega * std::sin(phase);
        auto y = moving.start(s_moving);
        // Six collisions: the two pictures round differently and chaos amplifies it (measured
        // at 40π: 1e-15 at the 3rd collision, 1e-11 at the 6th, 1e-8 at the 8th, O(1) at the 16th).
        for (int k = 0; k < 6; ++k) {
          INFO("omega = " << omega << ", phase = " << phase << ", particle " << particle << ", collision " << k);
          const auto hx = dynamics::collision(table, lab, x);
          const auto hy = dynamics::collision(table, moving, y);
          REQUIRE(hx.found());
          REQUIRE(hy.wall == hx.wall);
          CHECK(std::abs(hy.t - hx.t) <= 1e-10 * (1 + hx.t));
          CHECK((hy.point - hx.point).norm() <= 1e-10);
          dynamics::bounce(lab, x, hx);
          dynamics::bounce(moving, y, hy);
          // After the bounce too: the reflection off the moving wall is the lab's reflection.
          const Vec2 wall_velocity = -force / omega * std::sin(double(x.phase));
          CHECK((moving.wall_velocity(y) - wall_velocity).norm() <= 1e-9);
          CHECK((y.v - (x.v + wall_velocity)).norm() <= 1e-9);
        }
      }
    }
}

TEST_CASE("the clover at omega = 320 pi: both pictures give the same energy statistics, and g1 dt, g2 dt") {
  const auto& shape = clover();
  const dynamics::Table table(shape.region);
  const double omega = 320 * pi, E0 = 0.5, dt = 20;
  // θ = ωt: a whole number of periods at t = 19 and 20 (sin θ = 0, the two energies agree),
  // a quarter period later at 19 + 1/640 (sin θ = 1, they differ by m ẋ·ḋ + ½m|ḋ|²).
  const double quarter = 19 + 1.0 / 640;
  dynamics::RunOptions opt;
  opt.record_times = {0, 19, quarter, dt};
  const std::size_t n = 20000, m = opt.record_times.size();
  const PeriodicDriveFlight lab{force, omega, 0};
  const QuiveringWallFlight moving{force, omega, 0};
  const auto a = dynamics::run_ensemble(table, lab, dynamics::microcanonical(table, lab, 1.0, 2021), opt, n, 2);
  const auto b = dynamics::run_ensemble(table, moving, dynamics::microcanonical(table, moving, 1.0, 2021), opt, n, 2);
  REQUIRE(a.escapes() == 0);
  REQUIRE(b.escapes() == 0);

  // Particle by particle: the transform is exact, so the energies at t = 20 agree up to
  // rounding amplified by chaos (measured: 83% within 1e-9, 98.2% within 1e-6, 99.6% within
  // 1e-3; the rest have gone separate ways, e.g. in the clover's cusps).
  const auto da = a.energy_changes(3, m), db = b.energy_changes(3, m);
  std::size_t close = 0;
  for (std::size_t i = 0; i < n; ++i) close += std::abs(da[i] - db[i]) <= 1e-6;
  CHECK(close >= 0.97 * n);

  // The ensemble statistics agree with each other and with g1 Δt, g2 Δt (analysis layer).
  analysis::Drive drive{Eigen::Vector2d(force.x(), force.y()), omega, 1};
  const auto c = analysis::coefficients(geometry::measures_of(shape.region), drive, E0);
  const auto ma = analysis::sample_moments(da), mb = analysis::sample_moments(db);
  CHECK(std::abs(ma.mean - mb.mean) <= ma.se_mean);
  CHECK(std::abs(ma.variance - mb.variance) <= ma.se_variance);
  for (const auto& s : {ma, mb}) {
    CHECK(std::abs(s.mean - c.g1 * dt) <= 3 * s.se_mean);
    CHECK(std::abs(s.variance - c.g2 * dt) <= 3 * s.se_variance);
  }

  // A quarter period off: E_moving − E_lab = m ẋ·ḋ + ½m|ḋ|² with |ḋ| = F/(mω) and ẋ isotropic
  // of speed ≈ 1, so the mean is ½|ḋ|² and the spread |ḋ|/√2.  (At t = 19, sin θ = 0: equal.)
  const auto ea = a.energies_at(2, m), eb = b.energies_at(2, m);
  std::vector<double> diff(n);
  for (std::size_t i = 0; i < n; ++i) diff[i] = eb[i] - ea[i];
  const auto md = analysis::sample_moments(diff);
  const double wall_speed = force.norm() / omega;
  CHECK(std::abs(md.mean - 0.5 * wall_speed * wall_speed) <= 4 * md.se_mean);
  CHECK(std::sqrt(md.variance) == Approx(wall_speed / std::sqrt(2.0)).epsilon(0.05));
  const auto e19a = a.energies_at(1, m), e19b = b.energies_at(1, m);
  std::size_t equal19 = 0;
  for (std::size_t i = 0; i < n; ++i) equal19 += std::abs(e19a[i] - e19b[i]) <= 1e-6;
  CHECK(equal19 >= 0.97 * n);
}

TEST_CASE("billiard run: picture: quivering-walls gives the lab picture's statistics; bad values are errors") {
  const auto dir = scratch("quivering-walls");
  auto scene = [&](const std::string& picture) {
    return "shape: " BILLIARDS_SOURCE_DIR "/shapes/clover.yaml\n"
           "initial:\n  microcanonical: {energy: 1/2}\n"
           "force:\n  periodic: {amplitude: [10/sqrt(2), 10/sqrt(2)], omega: 320*pi" +
           picture + "}\nrun: {particles: 2000, time: 20, seed: 3}\n";
  };
  write_file(dir / "lab.yaml", scene(""));
  write_file(dir / "moving.yaml", scene(", picture: quivering-walls"));
  write_file(dir / "bad.yaml", scene(", picture: sideways"));
  const std::string common = " --quiet --no-csv --threads 2 --out ";
  const auto lab = billiard("run " + (dir / "lab.yaml").string() + common + (dir / "lab").string());
  const auto moving = billiard("run " + (dir / "moving.yaml").string() + common + (dir / "moving").string());
  REQUIRE(lab.status == 0);
  REQUIRE(moving.status == 0);
  const auto ja = nlohmann::json::parse(read_file(dir / "lab" / "summary.json"));
  const auto jb = nlohmann::json::parse(read_file(dir / "moving" / "summary.json"));
  // The pictures differ by rounding, which chaos amplifies: by t = 20 the k ≈ 2–4% of particles
  // with the most collisions (≥ 9) have diverged, and contribute independent draws, so the two
  // estimates differ by about √(2k/n) ≈ 0.2–0.3 SE (measured: 0.02 and 0.13 SE for two builds
  // whose scans differ in rounding only).  A wrong bounce or energy shows as several SE.
  CHECK(std::abs(ja["mean_dE"].get<double>() - jb["mean_dE"].get<double>()) <= 0.5 * ja["se_mean_dE"].get<double>());
  CHECK(std::abs(ja["var_dE"].get<double>() - jb["var_dE"].get<double>()) <= 0.5 * ja["se_var_dE"].get<double>());
  const auto bad = billiard("run " + (dir / "bad.yaml").string() + common + (dir / "bad").string());
  CHECK(bad.status != 0);
  CHECK(bad.output.find("bad.yaml:5: 'picture' is one of: lab, quivering-walls") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "bad"));
}
