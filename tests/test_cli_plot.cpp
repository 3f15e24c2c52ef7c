// `billiard plot`, `billiard coeffs` and `billiard fp` from the command line.
#include "cli_helpers.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <sstream>

namespace fs = std::filesystem;

/// Width and height from a PNG's IHDR chunk (big-endian, right after the signature).
static std::pair<unsigned, unsigned> png_size(const std::string& bytes) {
  auto be32 = [&](std::size_t i) {
    unsigned v = 0;
    for (std::size_t k = i; k < i + 4; ++k) v = v << 8 | static_cast<unsigned char>(bytes[k]);
    return v;
  };
  return {be32(16), be32(20)};
}

static std::size_t files_in(const fs::path& dir) {
  return std::distance(fs::directory_iterator(dir), fs::directory_iterator());
}

TEST_CASE("plot writes a PNG of the shape and its trajectory, and nothing on error") {
  const auto dir = scratch("plot");
  const auto png = dir / "clover.png";
  const auto r = billiard("plot shapes/clover.yaml --trajectory 50 -o " + png.string());
  REQUIRE(r.status == 0);
  const std::string bytes = read_file(png);
  REQUIRE(bytes.size() > 24);
  CHECK(bytes.substr(0, 8) == "\x89PNG\r\n\x1a\n");
  CHECK(bytes.size() > 20000);  // a drawing, not an empty canvas
  CHECK(bytes.size() < 5000000);
  const auto [width, height] = png_size(bytes);
  CHECK(width > 400);
  CHECK(width < 3000);
  CHECK(height > 400);
  CHECK(height < 3000);
  CHECK(files_in(dir) == 1);  // no temporary file left next to it

  const auto bad = billiard("plot shapes/no-such-shape.yaml -o " + (dir / "bad.png").string());
  CHECK(bad.status != 0);
  CHECK_THAT(bad.output, Catch::Contains("cannot open shape file"));
  CHECK_FALSE(fs::exists(dir / "bad.png"));
}

TEST_CASE("plot writes the format its -o extension names, and refuses other extensions") {
  const auto dir = scratch("plot-formats");
  REQUIRE(billiard("plot shapes/square.yaml -o " + (dir / "square.svg").string()).status == 0);
  CHECK(read_file(dir / "square.svg").find("<svg") != std::string::npos);
  REQUIRE(billiard("plot shapes/square.yaml -o " + (dir / "square.pdf").string()).status == 0);
  CHECK(read_file(dir / "square.pdf").substr(0, 5) == "%PDF-");
  const auto jpg = billiard("plot shapes/square.yaml -o " + (dir / "square.jpg").string());
  CHECK(jpg.status == 2);
  CHECK_THAT(jpg.output, Catch::Contains("format follows its extension: .png, .pdf or .svg"));
  CHECK(files_in(dir) == 2);  // no JPEG, no temporary file
}

TEST_CASE("plot draws 3-D shapes: polyhedra with balls, meshes; bad files write nothing") {
  const auto dir = scratch("plot3");
  for (const char* shape : {"sinai3", "l-prism", "ball"}) {
    const auto png = dir / (std::string(shape) + ".png");
    const auto r = billiard(std::string("plot shapes/3d/") + shape + ".yaml --trajectory 40 -o " + png.string());
    INFO(shape << ": " << r.output);
    REQUIRE(r.status == 0);
    const auto bytes = read_file(png);
    REQUIRE(bytes.substr(1, 3) == "PNG");
    CHECK(png_size(bytes).first > 500);
  }
  const auto bad = dir / "bad.yaml";
  write_file(bad, "dimension: 3\nboundary:\n  sphere: {center: [0, 0, 0], radius: -1}\n");
  const auto r = billiard("plot " + bad.string() + " -o " + (dir / "bad.png").string());
  CHECK(r.status != 0);
  CHECK_THAT(r.output, Catch::Contains("bad.yaml:3"));
  CHECK_FALSE(fs::exists(dir / "bad.png"));
}

TEST_CASE("plot: a failing drawing leaves no PNG, a missing python is named") {
  const auto dir = scratch("plot-failures");
  // A stand-in for plot_shape.py that writes part of its output, then fails.
  const auto scripts = dir / "scripts";
  fs::create_directories(scripts);
  write_file(scripts / "plot_shape.py", "import sys\nopen(sys.argv[2], 'w').write('half')\nsys.exit(3)\n");
  setenv("BILLIARDS_SCRIPTS", scripts.c_str(), 1);
  const auto failed = billiard("plot shapes/sinai.yaml -o " + (dir / "sinai.png").string());
  unsetenv("BILLIARDS_SCRIPTS");
  CHECK(failed.status != 0);
  CHECK_THAT(failed.output, Catch::Contains("drawing failed"));
  CHECK(files_in(dir) == 1);  // only the scripts directory: no PNG, no temporary

  setenv("BILLIARDS_PYTHON", "/nonexistent/python3", 1);
  const auto no_python = billiard("plot shapes/sinai.yaml -o " + (dir / "sinai.png").string());
  unsetenv("BILLIARDS_PYTHON");
  CHECK(no_python.status != 0);
  CHECK_THAT(no_python.output, Catch::Contains("cannot run /nonexistent/python3"));
  CHECK(files_in(dir) == 1);
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
