// `billiard compare`: the simulation set against the Fokker–Planck prediction.
#include "cli_helpers.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <vector>

namespace fs = std::filesystem;

namespace {

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(read_file(p)); }

/// energies.npy as rows of doubles (its header is padded to 128 bytes).
std::vector<double> read_npy(const fs::path& p) {
  const std::string bytes = read_file(p);
  std::vector<double> x((bytes.size() - 128) / sizeof(double));
  std::memcpy(x.data(), bytes.data() + 128, x.size() * sizeof(double));
  return x;
}

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
