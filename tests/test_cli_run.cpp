// `billiard run`: reproducibility, checkpoints, and errors on bad scenes.
#include "cli_helpers.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace fs = std::filesystem;

TEST_CASE("same seed: 1 thread and 2 threads give byte-identical energies") {
  const auto dir = scratch("threads");
  const std::string common = "run scenes/clover-free.yaml --particles 3000 --time 50 --quiet --out ";
  REQUIRE(billiard(common + (dir / "one").string() + " --threads 1").status == 0);
  REQUIRE(billiard(common + (dir / "two").string() + " --threads 2").status == 0);
  const auto a = read_file(dir / "one" / "energies.npy"), b = read_file(dir / "two" / "energies.npy");
  CHECK(a.size() == 128 + 3000 * 11 * 8);
  CHECK(a == b);
  CHECK(read_file(dir / "one" / "energies.csv") == read_file(dir / "two" / "energies.csv"));
}

TEST_CASE("driven scene: 1 thread and 2 threads give byte-identical energies") {
  const auto dir = scratch("threads-driven");
  const std::string common = "run scenes/clover-driven.yaml --particles 2000 --time 5 --quiet --out ";
  REQUIRE(billiard(common + (dir / "one").string() + " --threads 1").status == 0);
  REQUIRE(billiard(common + (dir / "two").string() + " --threads 2").status == 0);
  const auto a = read_file(dir / "one" / "energies.npy");
  CHECK(a.size() == 128 + 2000 * 6 * 8);
  CHECK(a == read_file(dir / "two" / "energies.npy"));
}

TEST_CASE("--npy float32 halves energies.npy, each energy the double's rounding; --npy none leaves it out") {
  const auto dir = scratch("npy-types");
  const std::string common = "run scenes/clover-driven.yaml --particles 1500 --time 5 --quiet --no-csv --out ";
  REQUIRE(billiard(common + (dir / "f8").string()).status == 0);
  REQUIRE(billiard(common + (dir / "f4").string() + " --npy float32").status == 0);
  REQUIRE(billiard(common + (dir / "none").string() + " --npy none").status == 0);
  const std::size_t n = 1500 * 6;
  const auto f8 = read_npy(dir / "f8" / "energies.npy");
  const auto f4 = read_file(dir / "f4" / "energies.npy");
  REQUIRE(f8.size() == n);
  REQUIRE(f4.size() == 128 + n * sizeof(float));
  CHECK(f4.find("'descr': '<f4'") != std::string::npos);
  CHECK(f4.find("'shape': (1500, 6)") != std::string::npos);
  std::vector<float> E(n);
  std::memcpy(E.data(), f4.data() + 128, n * sizeof(float));
  for (std::size_t i = 0; i < n; ++i) {
    INFO("entry " << i << ": " << f8[i]);
    REQUIRE(E[i] == static_cast<float>(f8[i]));                                       // round to nearest
    REQUIRE(std::abs(double(E[i]) - f8[i]) <= std::ldexp(std::abs(f8[i]), -24));  // half an ulp of 24 bits
  }
  CHECK_FALSE(fs::exists(dir / "none" / "energies.npy"));
  CHECK(fs::exists(dir / "none" / "summary.json"));
  // The statistics come from the doubles whatever is written.
  const auto a = read_json(dir / "f8" / "summary.json"), b = read_json(dir / "none" / "summary.json");
  CHECK(a["var_dE"] == b["var_dE"]);
  CHECK(a["per_time"] == b["per_time"]);
  const auto bad = billiard(common + (dir / "bad").string() + " --npy float16");
  CHECK(bad.status != 0);
  CHECK_FALSE(fs::exists(dir / "bad"));
}

TEST_CASE("a run resumed from its checkpoint equals an uninterrupted run") {
  const auto dir = scratch("resume");
  const std::string common = "run scenes/clover-free.yaml --particles 5000 --time 20 --quiet --threads 2 --out ";
  REQUIRE(billiard(common + (dir / "whole").string()).status == 0);
  // Interrupted twice (1 chunk, then 2 more), then finished.
  REQUIRE(billiard(common + (dir / "part").string() + " --max-chunks 1").status == 0);
  CHECK_FALSE(fs::exists(dir / "part"));  // no output until the run is complete
  CHECK(fs::exists(dir / "part.partial"));
  REQUIRE(billiard(common + (dir / "part").string() + " --max-chunks 2").status == 0);
  REQUIRE(billiard(common + (dir / "part").string()).status == 0);
  CHECK_FALSE(fs::exists(dir / "part.partial"));
  CHECK(read_file(dir / "whole" / "energies.npy") == read_file(dir / "part" / "energies.npy"));
}

namespace {

/// Writes a scene next to the bundled shapes and runs it; returns the result.
CommandResult run_scene(const std::string& name, const std::string& yaml, const fs::path& out) {
  const fs::path scene = fs::path(BILLIARDS_SOURCE_DIR) / "scenes" / (".test-" + name + ".yaml");
  write_file(scene, yaml);
  const auto r = billiard("run " + scene.string() + " --quiet --out " + out.string());
  fs::remove(scene);
  return r;
}

const std::string good_scene = R"(shape: ../shapes/clover.yaml
initial:
  microcanonical: {energy: 1/2}
run:
  particles: 10
  time: 1
)";

}  // namespace

TEST_CASE("bad scenes are reported with file and line, exit non-zero, and write nothing") {
  const auto dir = scratch("bad-scenes");
  const auto out = dir / "out";
  REQUIRE(run_scene("good", good_scene, out).status == 0);
  fs::remove_all(out);
  struct Case {
    std::string name, yaml, message;
  };
  const std::string tail = "initial:\n  microcanonical: {energy: 1/2}\nrun: {particles: 10, time: 1}\n";
  const std::vector<Case> cases = {
      {"unknown-key", good_scene + "colour: red\n", ".test-unknown-key.yaml:7: unknown key 'colour'"},
      {"bad-expression", "shape: ../shapes/clover.yaml\ninitial:\n  microcanonical: {energy: 1/}\nrun: {particles: 10, time: 1}\n",
       ".test-bad-expression.yaml:3: bad expression '1/'"},
      {"negative-energy", "shape: ../shapes/clover.yaml\ninitial:\n  microcanonical: {energy: -1}\nrun: {particles: 10, time: 1}\n",
       ".test-negative-energy.yaml:3: energy must be positive"},
      {"no-shape", "shape: ../shapes/nothing.yaml\n" + tail, "nothing.yaml: cannot open shape file"},
      {"zero-particles", "shape: ../shapes/clover.yaml\ninitial:\n  microcanonical: {energy: 1}\nrun: {particles: 0, time: 1}\n",
       ".test-zero-particles.yaml:4: run.particles must be a whole number"},
      {"bad-omega", good_scene + "force:\n  periodic: {amplitude: [1, 0], omega: 0}\n",
       ".test-bad-omega.yaml:8: omega must be positive"},
      {"not-yaml", "shape: [unclosed\n", ".test-not-yaml.yaml:2: not valid YAML"},
      {"bad-shape-override", "shape: ../shapes/clover.yaml\nset: {R9: 1}\n" + tail,
       "--set names 'R9', which is not a parameter of this shape"},
  };
  for (const auto& c : cases) {
    INFO(c.name);
    const auto r = run_scene(c.name, c.yaml, out);
    CHECK(r.status != 0);
    CHECK_THAT(r.output, Catch::Contains(c.message));
    CHECK_FALSE(fs::exists(out));
  }
}

TEST_CASE("particles outside the region in an initial-condition file are rejected by line") {
  const auto dir = scratch("csv");
  write_file(dir / "init.csv", "x,y,vx,vy\n0,0,1,0\n5,5,1,0\n");
  const auto r = run_scene("csv", "shape: ../shapes/clover.yaml\ninitial:\n  csv: " + (dir / "init.csv").string() +
                                      "\nrun: {time: 1}\n", dir / "out");
  CHECK(r.status != 0);
  CHECK_THAT(r.output, Catch::Contains("init.csv:3: particle is outside the region"));
  CHECK_FALSE(fs::exists(dir / "out"));
}

TEST_CASE("--sweep runs one ensemble per value and tabulates them; Var(dE) grows as F^2") {
  const auto dir = scratch("sweep");
  const auto r = billiard("run scenes/clover-driven.yaml --omega 320*pi --particles 4000 --time 20 --quiet --no-csv "
                          "--sweep F=5,10 --out " + dir.string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  const auto sweep = nlohmann::json::parse(read_file(dir / "sweep.json"));
  REQUIRE(sweep["points"].size() == 2);
  const auto& low = sweep["points"][0]["summary"];
  const auto& high = sweep["points"][1]["summary"];
  CHECK(fs::exists(dir / "F=5" / "energies.npy"));
  CHECK(fs::exists(dir / "F=10" / "summary.json"));
  CHECK(low["shape_parameters"].is_object());
  // g2 ∝ F² (C = 0.5419 F²/ω²): doubling F quadruples Var(dE), within the sampling error.
  const double ratio = high["var_dE"].get<double>() / low["var_dE"].get<double>();
  const double se = ratio * std::hypot(high["se_var_dE"].get<double>() / high["var_dE"].get<double>(),
                                       low["se_var_dE"].get<double>() / low["var_dE"].get<double>());
  CHECK(std::abs(ratio - 4) < 4 * se);
  CHECK(high["prediction"]["C"].get<double>() == Approx(4 * low["prediction"]["C"].get<double>()));
  // The table has a header and one row per value.
  const auto csv = read_file(dir / "sweep.csv");
  CHECK(csv.rfind("F,particles,mean_dE", 0) == 0);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 3);
}

TEST_CASE("geometric sweeps reach their end despite rounding; bad sweeps are errors") {
  const auto dir = scratch("sweep-range");
  const auto r = billiard("run scenes/clover-free.yaml --particles 1000 --time 2 --quiet --no-csv "
                          "--sweep omega=10*pi..40*pi:x2 --out " + dir.string());
  CHECK(r.status != 0);  // the free scene has no drive to sweep
  CHECK_THAT(r.output, Catch::Contains("--omega needs a periodic force"));
  const auto ok = billiard("run scenes/clover-driven.yaml --particles 1000 --time 2 --quiet --no-csv "
                           "--sweep omega=10*pi..40*pi:x2 --out " + dir.string());
  REQUIRE(ok.status == 0);
  CHECK(nlohmann::json::parse(read_file(dir / "sweep.json"))["points"].size() == 3);
  for (const std::string bad : {"omega", "omega=1..2", "omega=2..1:x0.5", "omega=1..2:+0", "omega=1,2*"}) {
    const auto e = billiard("run scenes/clover-driven.yaml --particles 10 --quiet --sweep " + bad + " --out " +
                            (dir / "bad").string());
    INFO(bad << ": " << e.output);
    CHECK(e.status == 2);
    CHECK_THAT(e.output, Catch::Contains("--sweep"));
  }
}
