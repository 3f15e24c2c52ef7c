// `billiard plot` and `billiard coeffs` from the command line.
#include "cli_helpers.hpp"

#include <catch2/catch.hpp>

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
