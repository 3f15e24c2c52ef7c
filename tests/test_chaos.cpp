// The chaos check (analysis/chaos.hpp, `billiard chaos`) on tables whose nature is known:
// integrable (circle, square, ellipse), mixed (the mushroom: regular orbits and a chaotic sea
// that never enters the islands) and chaotic, ergodic (stadium, Sinai, clover); and the
// verdict `coeffs` prints beside its prediction.
#include "cli_helpers.hpp"

#include "billiards/analysis/chaos.hpp"
#include "billiards/geometry/shape_file.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <string>

using namespace billiards;

namespace {
analysis::ChaosVerdict check(const std::string& name) {
  analysis::ChaosOptions o;
  o.orbits = 8;
  o.collisions = 20000;
  o.threads = 2;
  return analysis::chaos_of(geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + name).region, o);
}
}  // namespace

TEST_CASE("integrable tables are neither chaotic nor uniform on the boundary map") {
  for (const char* name : {"circle.yaml", "square.yaml", "ellipse.yaml"}) {
    INFO(name);
    const auto v = check(name);
    CHECK(!v.chaotic);
    CHECK(!v.uniform);
    CHECK(!v.ergodic());
  }
}

TEST_CASE("the mushroom is mixed: chaotic orbits that do not cover the map, and regular ones") {
  const auto v = check("mushroom.yaml");
  CHECK(!v.ergodic());
  std::size_t chaotic = 0, regular = 0;
  for (const auto& e : v.orbits) {
    if (e.lyapunov_per_collision > 0.1) {
      ++chaotic;
      CHECK(e.distance > 0.2);  // the islands are never entered
    } else {
      ++regular;
      CHECK(e.lyapunov_per_collision < 0.01);
    }
  }
  CHECK(chaotic > 0);
  CHECK(regular > 0);
}

TEST_CASE("the stadium, the Sinai table and the clover are chaotic and ergodic") {
  for (const char* name : {"stadium.yaml", "sinai.yaml", "clover.yaml"}) {
    INFO(name);
    const auto v = check(name);
    CHECK(v.ergodic());
    CHECK(v.lyapunov.mean > 10 * v.lyapunov.se);
    CHECK(v.pooled_distance < 3 * v.noise_distance);  // 8 orbits pooled: close to independent points
  }
}

TEST_CASE("billiard chaos --json, and coeffs warns when the table is not chaotic") {
  auto r = billiard("chaos shapes/circle.yaml --particles 4 --collisions 5000 --json --quiet");
  INFO(r.output);
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.output);
  CHECK(j["ergodic"] == false);
  CHECK(j["per_orbit"].size() == 4);
  for (const char* key : {"lyapunov", "lyapunov_se", "pooled_distance", "noise_distance", "chaotic", "uniform"})
    CHECK(j.contains(key));

  const auto dir = scratch_root() / "chaos";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "circle-driven.yaml") << "shape: " BILLIARDS_SOURCE_DIR "/shapes/circle.yaml\n"
                                               "initial:\n  microcanonical: {energy: 1/2}\n"
                                               "force:\n  periodic: {amplitude: [2, 0], omega: 40*pi}\n"
                                               "run: {particles: 100, time: 1}\n";
  r = billiard("coeffs " + (dir / "circle-driven.yaml").string());
  CHECK(r.status == 0);
  CHECK(r.output.find("warning: the undriven table is NOT chaotic and ergodic") != std::string::npos);
  r = billiard("coeffs scenes/clover-driven.yaml --json");
  REQUIRE(r.status == 0);
  CHECK(nlohmann::json::parse(r.output)["chaos_check"]["ergodic"] == true);
}

TEST_CASE("3-D: the cube and the ball are neither chaotic nor uniform in (wall, cos^2 theta); the 3-D Sinai table is") {
  analysis::ChaosOptions o;
  o.orbits = 6;
  o.collisions = 20000;
  o.threads = 2;
  const auto region = [](const char* name) {
    return geometry3::load_shape3(std::string(BILLIARDS_SOURCE_DIR "/shapes/3d/") + name).region;
  };
  for (const char* name : {"cube.yaml", "ball.yaml"}) {
    INFO(name);
    const auto v = analysis::chaos_of(region(name), o);
    CHECK(!v.chaotic);
    CHECK(!v.uniform);
  }
  const auto v = analysis::chaos_of(region("sinai3.yaml"), o);
  CHECK(v.position_cells == 7);  // six faces and the ball
  CHECK(v.ergodic());
  CHECK(v.pooled_distance < 3 * v.noise_distance);
  // The same verdict from the command, for 1 and 2 threads alike.
  const std::string cmd = "chaos shapes/3d/sinai3.yaml --particles 3 --collisions 20000 --json --quiet --threads ";
  const auto one = billiard(cmd + "1"), two = billiard(cmd + "2");
  INFO(one.output);
  REQUIRE(one.status == 0);
  CHECK(one.output == two.output);
  CHECK(nlohmann::json::parse(one.output)["ergodic"] == true);
}
