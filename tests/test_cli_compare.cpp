// `billiard compare`: the simulation set against the Fokker–Planck prediction (analytic, or with a
// potential numerical); `billiard fp` with a potential.
#include "cli_helpers.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <vector>

namespace fs = std::filesystem;

namespace {

const nlohmann::json& at_time(const nlohmann::json& comparison, double t) {
  for (const auto& f : comparison["times"])
    if (f["t"].get<double>() == t) return f;
  FAIL("no comparison at t = " << t);
  throw;
}

}  // namespace

TEST_CASE("compare at high omega: the distribution is the Fokker-Planck one once particles have collided") {
  const auto dir = scratch("compare") / "out";
  const auto r = billiard("compare scenes/clover-driven.yaml --omega 320*pi --particles 20000 --time 20 "
                          "--record 1,20 --quiet --no-csv --out " + dir.string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  for (const char* f : {"comparison.json", "comparison.csv", "comparison.png", "summary.json", "energies.npy"})
    CHECK(fs::exists(dir / f));
  CHECK_FALSE(fs::exists(dir / "energies.csv"));  // --no-csv
  CHECK(read_file(dir / "comparison.png").substr(1, 3) == "PNG");
  const auto c = read_json(dir / "comparison.json");

  // t = 20, about 8 collisions per particle: the diffusion limit holds.
  const auto& late = at_time(c, 20);
  CHECK(late["ks_p_value"].get<double>() > 1e-3);
  CHECK(late["l1_distance"].get<double>() < 1.5 * late["l1_expected_from_noise"].get<double>());
  CHECK(std::abs(late["mean_dE_fp_deviation_se"].get<double>()) < 3);
  CHECK(std::abs(late["var_dE_fp_deviation_se"].get<double>()) < 3);

  // t = 1: most particles have not hit a wall yet, so E(t) = E0 for them — a spike the
  // diffusion cannot have, which both distances must see although the variance is right.
  const auto& early = at_time(c, 1);
  CHECK(early["ks_p_value"].get<double>() < 1e-6);
  CHECK(early["l1_distance"].get<double>() > 5 * early["l1_expected_from_noise"].get<double>());

  // The measured moments are those of the energies written beside them.
  const auto E = read_npy(dir / "energies.npy");
  const std::size_t m = 3, n = E.size() / m;
  REQUIRE(n == 20000);
  double sum = 0, sum2 = 0;
  for (std::size_t i = 0; i < n; ++i) sum += E[i * m + 2] - E[i * m];
  const double mean = sum / double(n);
  for (std::size_t i = 0; i < n; ++i) sum2 += std::pow(E[i * m + 2] - E[i * m] - mean, 2);
  CHECK(late["mean_dE"].get<double>() == Approx(mean).epsilon(1e-9));
  CHECK(late["var_dE"].get<double>() == Approx(sum2 / double(n - 1)).epsilon(1e-9));
  CHECK(late["n"].get<std::size_t>() == n);
}

TEST_CASE("compare --no-plot: the same numbers and files but the figure, which plot_compare.py draws afterwards") {
  const auto dir = scratch("compare-no-plot");
  const std::string run = "compare scenes/clover-driven.yaml --omega 320*pi --particles 2000 --time 5 --record 1 "
                          "--quiet --no-csv --threads 2 --out ";
  const auto with = billiard(run + (dir / "with").string());
  const auto without = billiard(run + (dir / "without").string() + " --no-plot");
  INFO(with.output << without.output);
  REQUIRE(with.status == 0);
  REQUIRE(without.status == 0);
  CHECK_FALSE(fs::exists(dir / "without" / "comparison.png"));
  for (const char* f : {"comparison.csv", "fokker-planck.csv", "energies.npy"})
    CHECK(read_file(dir / "without" / f) == read_file(dir / "with" / f));
  CHECK(read_json(dir / "without" / "comparison.json")["times"] == read_json(dir / "with" / "comparison.json")["times"]);
  const auto plot = run_command("/usr/bin/python3 " BILLIARDS_SOURCE_DIR "/scripts/plot_compare.py " +
                                (dir / "without").string());
  INFO(plot.output);
  CHECK(plot.status == 0);
  CHECK(read_file(dir / "without" / "comparison.png").substr(1, 3) == "PNG");
}

TEST_CASE("compare refuses a scene without a prediction and writes nothing") {
  const auto dir = scratch("compare-free") / "out";
  const auto r = billiard("compare scenes/clover-free.yaml --particles 100 --quiet --out " + dir.string());
  CHECK(r.status != 0);
  CHECK_THAT(r.output, Catch::Contains("clover-free.yaml") && Catch::Contains("compare needs a scene with a Fokker-Planck prediction"));
  CHECK_FALSE(fs::exists(dir));
}

TEST_CASE("numeric options take expressions, and a bad one is an error") {
  const auto a = billiard("coeffs scenes/clover-driven.yaml --json --omega 320*pi");
  const auto b = billiard("coeffs scenes/clover-driven.yaml --json --omega 1005.3096491487338");
  REQUIRE(a.status == 0);
  CHECK(a.output == b.output);
  const auto bad = billiard("coeffs scenes/clover-driven.yaml --omega 320*");
  CHECK(bad.status != 0);
  CHECK_THAT(bad.output, Catch::Contains("--omega") && Catch::Contains("bad expression '320*'"));
}

namespace {

/// The clover tilted by U = 0.4 y (E0 = 1/2, part of the top lobe forbidden), driven by F = 10
/// along (1, 1)/√2 at `omega`; with `force: none` when `driven` is false.
fs::path tilted_clover(const fs::path& dir, const std::string& omega, bool driven = true) {
  const auto path = dir / "tilt.yaml";
  write_file(path, "shape: " BILLIARDS_SOURCE_DIR "/shapes/clover.yaml\nparameters: {g: 0.4, F: 10, omega: " + omega +
                       "}\ninitial:\n  microcanonical: {energy: 1/2}\n" +
                       (driven ? "force:\n  periodic: {amplitude: [F/sqrt(2), F/sqrt(2)], omega: omega}\n" : "") +
                       "potential: {expression: g*y}\nintegrator: {tolerance: 1e-8}\n"
                       "run: {particles: 3000, time: 10, seed: 5}\n");
  return path;
}

}  // namespace

TEST_CASE("compare with a potential: the simulation against the numerical Fokker-Planck solution") {
  // At 40 pi the distribution spreads enough by t = 10 (about 4 collisions per particle) that
  // the FP variance exceeds g2 t by 3%; the numerical eta must match moments and shape.
  const auto dir = scratch("compare-potential");
  const auto scene = tilted_clover(dir, "40*pi");
  const auto out = dir / "out";
  const auto r = billiard("compare " + scene.string() + " --record 5,10 --cells 600 --quiet --no-csv --threads 2 --out " +
                          out.string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Catch::Contains("numerical (U != 0"));
  for (const char* f : {"comparison.json", "comparison.csv", "comparison.png", "fokker-planck.csv"})
    CHECK(fs::exists(out / f));
  const auto c = read_json(out / "comparison.json");
  CHECK(c["prediction"]["closed_form"] == false);
  const auto& late = at_time(c, 10);
  CHECK(std::abs(late["mean_dE_fp_deviation_se"].get<double>()) < 3);
  CHECK(std::abs(late["var_dE_fp_deviation_se"].get<double>()) < 3);
  CHECK(late["ks_p_value"].get<double>() > 1e-3);
  CHECK(late["l1_distance"].get<double>() < 1.5 * late["l1_expected_from_noise"].get<double>());
  CHECK(late["fp_var_dE"].get<double>() > 1.01 * late["g2_t"].get<double>());  // beyond the short-time law
  // t = 5 (two collisions): a spike at E0 of particles that have not met a wall, which the
  // diffusion cannot have, as without a potential.
  CHECK(at_time(c, 5)["ks_p_value"].get<double>() < 1e-4);
}

TEST_CASE("fp with a potential: numerical columns only, each eta integrating to 1; no drive is refused") {
  const auto dir = scratch("fp-potential");
  const auto scene = tilted_clover(dir, "320*pi");
  const auto csv_path = dir / "fp.csv";
  const auto r = billiard("fp " + scene.string() + " --times 8,1000 --cells 400 -o " + csv_path.string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Catch::Contains("numerical only"));
  std::istringstream csv(read_file(csv_path));
  std::string line;
  std::getline(csv, line);
  CHECK(line == "E,eta_numerical(t=8),eta_numerical(t=1000)");
  // ∫η dE by the trapezoidal rule over the cell centres (η vanishes at both ends of the grid).
  double mass[2] = {0, 0}, E_prev = 0, eta_prev[2] = {0, 0};
  bool first = true;
  while (std::getline(csv, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream f(line);
    double E, eta[2];
    f >> E >> eta[0] >> eta[1];
    for (int k = 0; k < 2 && !first; ++k) mass[k] += 0.5 * (eta[k] + eta_prev[k]) * (E - E_prev);
    first = false;
    E_prev = E, eta_prev[0] = eta[0], eta_prev[1] = eta[1];
  }
  CHECK(mass[0] == Approx(1).epsilon(1e-3));
  CHECK(mass[1] == Approx(1).epsilon(1e-3));

  // A potential without a drive has no prediction: both commands refuse, naming the scene.
  const auto undriven = tilted_clover(scratch("fp-potential-undriven"), "320*pi", false);
  const auto fp = billiard("fp " + undriven.string() + " --times 8 -o " + (dir / "none.csv").string());
  CHECK(fp.status != 0);
  CHECK_THAT(fp.output, Catch::Contains("tilt.yaml") && Catch::Contains("fp needs a periodic force"));
  CHECK_FALSE(fs::exists(dir / "none.csv"));
  const auto cmp = billiard("compare " + undriven.string() + " --quiet --out " + (dir / "none").string());
  CHECK(cmp.status != 0);
  CHECK_THAT(cmp.output, Catch::Contains("compare needs a scene with a Fokker-Planck prediction"));
  CHECK_FALSE(fs::exists(dir / "none"));

  // A bowl U = |x|² in the unit circle: at E0 = 1/2 < U on the wall no particle reaches the wall.
  const auto bowl = dir / "bowl.yaml";
  write_file(bowl, "shape: " BILLIARDS_SOURCE_DIR "/shapes/circle.yaml\ninitial:\n  microcanonical: {energy: 1/2}\n"
                   "force:\n  periodic: {amplitude: [1, 0], omega: 100}\npotential: {expression: x^2 + y^2}\n"
                   "run: {particles: 10, time: 1}\n");
  const auto trapped = billiard("fp " + bowl.string() + " --times 1 -o " + (dir / "bowl.csv").string());
  CHECK(trapped.status != 0);
  CHECK_THAT(trapped.output, Catch::Contains("bowl.yaml") && Catch::Contains("the energy does not diffuse"));
  CHECK_FALSE(fs::exists(dir / "bowl.csv"));
}
