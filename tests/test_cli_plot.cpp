// `billiard plot` and `billiard coeffs` from the command line.
#include "cli_helpers.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <sstream>

namespace fs = std::filesystem;

TEST_CASE("plot writes a PNG of the shape and its trajectory, and nothing on error") {
  const auto dir = scratch("plot");
  const auto png = dir / "clover.png";
  const auto r = billiard("plot shapes/clover.yaml --trajectory 50 -o " + png.string());
  REQUIRE(r.status == 0);
  const std::string bytes = read_file(png);
  CHECK(bytes.substr(0, 8) == "\x89PNG\r\n\x1a\n");
  CHECK(bytes.size() > 20000);
  const auto bad = billiard("plot shapes/no-such-shape.yaml -o " + (dir / "bad.png").string());
  CHECK(bad.status != 0);
  CHECK_THAT(bad.output, Catch::Contains("cannot open shape file"));
  CHECK_FALSE(fs::exists(dir / "bad.png"));
}

TEST_CASE("coeffs --json gives the paper's clover numbers") {
  const auto r = billiard("coeffs scenes/clover-driven.yaml --json");
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Catch::Contains("\"mean_free_path\": 2.6095956"));
  // C = 0.5419 F²/ω² with F = 10, ω = 40π: 0.0034318.
  CHECK_THAT(r.output, Catch::Contains("\"C\": 0.0034318"));
  const auto free = billiard("coeffs scenes/clover-free.yaml");
  CHECK(free.status != 0);
  CHECK_THAT(free.output, Catch::Contains("coeffs needs a periodic force"));
}

TEST_CASE("fp writes the numerical and analytic Fokker-Planck solutions, which agree in L1") {
  const auto dir = scratch("fp");
  const auto csv = dir / "fp.csv";
  REQUIRE(billiard("fp scenes/clover-driven.yaml --times 10,100,1000 -o " + csv.string()).status == 0);
  std::istringstream in(read_file(csv));
  std::string line;
  std::getline(in, line);
  CHECK(line == "E,eta_numerical(t=10),eta_analytic(t=10),eta_numerical(t=100),eta_analytic(t=100),"
                "eta_numerical(t=1000),eta_analytic(t=1000)");
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    std::vector<double> row(7);
    for (double& x : row) fields >> x;
    rows.push_back(row);
  }
  REQUIRE(rows.size() == 4000);
  for (int k = 0; k < 3; ++k) {
    double l1 = 0;  // over the cell centres written in the file
    for (std::size_t i = 1; i < rows.size(); ++i)
      l1 += std::abs(rows[i][1 + 2 * k] - rows[i][2 + 2 * k]) * (rows[i][0] - rows[i - 1][0]);
    INFO("time column " << k);
    CHECK(l1 < 1e-3);
  }
  CHECK(billiard("fp scenes/clover-free.yaml --times 1 -o " + (dir / "free.csv").string()).status != 0);
  CHECK_FALSE(fs::exists(dir / "free.csv"));
}
