// The boundary map (analysis/boundary_map.hpp) and `billiard bmap`: Birkhoff coordinates
// against the circle's closed form, against the point each s names on the boundary, and the
// first hits of a microcanonical ensemble against the invariant measure ds dp; the sections;
// identical results for any thread count.
#include "cli_helpers.hpp"
#include "phase_space_helpers.hpp"

#include "billiards/analysis/boundary_map.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

using namespace billiards;
using analysis::BoundaryCoordinates;

namespace {

auto free_initial(const dynamics::Table& table, std::uint64_t seed = 7) {
  return dynamics::microcanonical(table, dynamics::FreeFlight{}, 1.0, seed);
}

/// Column j of row i.
double at(const analysis::SectionRows& r, std::size_t i, std::size_t j) { return r.rows[i * r.columns + j]; }

}  // namespace

TEST_CASE("circle: p is conserved and s advances by R (pi - 2 asin p) per bounce") {
  const auto circle = bundled_shape("circle.yaml");
  const dynamics::Table table(circle.region);
  const BoundaryCoordinates coordinates(circle.region);
  const double R = 1, S = 2 * geometry::pi * R;
  CHECK(coordinates.perimeter() == Approx(S).epsilon(1e-14));
  const auto r = analysis::boundary_map(table, coordinates, dynamics::FreeFlight{}, free_initial(table), 8, 200, 2);
  REQUIRE(r.row_count() == 8 * 200);
  for (std::size_t i = 1; i < r.row_count(); ++i) {
    if (at(r, i, 0) != at(r, i - 1, 0)) continue;  // (a new particle)
    const double p = at(r, i - 1, 3);
    CHECK(at(r, i, 3) == Approx(p).margin(1e-9));
    const double step = std::fmod(at(r, i, 2) - at(r, i - 1, 2) + S, S);
    const double expected = std::fmod(R * (geometry::pi - 2 * std::asin(p)) + S, S);
    CHECK(std::min(std::abs(step - expected), S - std::abs(step - expected)) < 1e-8);
  }
}

TEST_CASE("s names the hit point on every wall kind (point_along at the same arc length)") {
  for (const char* name : {"clover.yaml", "sinai-ellipse.yaml", "elliptic-stadium.yaml", "annulus.yaml", "mushroom.yaml"}) {
    INFO(name);
    const auto s = bundled_shape(name);
    const dynamics::Table table(s.region);
    const BoundaryCoordinates coordinates(s.region);
    std::vector<const geometry::Piece*> pieces;
    for (const auto* loop : s.region.loops())
      for (const auto& piece : loop->pieces) pieces.push_back(&piece);
    const auto& starts = coordinates.piece_starts();
    const auto initial = free_initial(table);
    for (std::size_t i = 0; i < 20; ++i) {
      dynamics::evolve(table, dynamics::FreeFlight{}, initial(i), 50, [&](const auto& hit, const auto&) {
        const int piece = table.piece_of(hit.wall);
        const double arc = coordinates.s_of(table, hit);
        REQUIRE(arc >= starts[piece]);
        REQUIRE(arc <= starts[piece + 1]);
        const double u = (arc - starts[piece]) / (starts[piece + 1] - starts[piece]);
        CHECK((geometry::point_along(*pieces[piece], u) - hit.point).norm() < 1e-8);
      });
    }
  }
}

/// Kolmogorov–Smirnov distance between the empirical CDF of x weighted by w and `cdf`.
double weighted_ks(std::vector<std::pair<double, double>> xw, const std::function<double(double)>& cdf) {
  std::sort(xw.begin(), xw.end());
  double total = 0, below = 0, d = 0;
  for (const auto& [x, w] : xw) total += w;
  for (const auto& [x, w] : xw) {
    d = std::max(d, std::abs(below / total - cdf(x)));
    below += w;
    d = std::max(d, std::abs(below / total - cdf(x)));
  }
  return d;
}

TEST_CASE("first hits of a microcanonical ensemble, weighted by 1/chord, are uniform in (s, p): ds dp") {
  // A uniform start in phase space reaches the boundary at (s, p) with density ∝ ℓ(s, p) ds dp,
  // ℓ the chord that ends there (the starts that lead to it fill that chord): weighted by 1/ℓ,
  // the first hits follow the invariant measure ds dp, whatever the dynamics.  One
  // Kolmogorov–Smirnov test for s and one for p, at the weights' effective sample size.
  for (const char* name : {"clover.yaml", "sinai-ellipse.yaml", "elliptic-stadium.yaml", "sinai.yaml"}) {
    INFO(name);
    const auto s = bundled_shape(name);
    const dynamics::Table table(s.region);
    const BoundaryCoordinates coordinates(s.region);
    const std::size_t n = 20000;
    const auto initial = free_initial(table, 3);
    const auto r = analysis::boundary_map(table, coordinates, dynamics::FreeFlight{}, initial, n, 1, 2);
    REQUIRE(r.row_count() == n);
    std::vector<std::pair<double, double>> arcs, ps;
    double sum_w = 0, sum_w2 = 0;
    for (std::size_t i = 0; i < n; ++i) {
      auto back = initial(i);
      back.v = -back.v;
      const double chord = at(r, i, 4) + dynamics::collision(table, dynamics::FreeFlight{}, back).t;
      const double w = 1 / chord;
      arcs.emplace_back(at(r, i, 2), w);
      ps.emplace_back(at(r, i, 3), w);
      sum_w += w, sum_w2 += w * w;
    }
    const double S = coordinates.perimeter();
    CHECK(S == Approx(geometry::measures_of(s.region).surface).epsilon(1e-9));
    const auto effective = std::size_t(sum_w * sum_w / sum_w2);
    const double ds = weighted_ks(arcs, [&](double x) { return std::clamp(x / S, 0.0, 1.0); });
    const double dp = weighted_ks(ps, [](double x) { return std::clamp((x + 1) / 2, 0.0, 1.0); });
    CHECK(analysis::ks_p_value(ds, effective) > 1e-4);
    CHECK(analysis::ks_p_value(dp, effective) > 1e-4);
  }
}

TEST_CASE("the boundary map and the sections are identical for any thread count") {
  const auto s = bundled_shape("clover.yaml");
  const dynamics::Table table(s.region);
  const BoundaryCoordinates coordinates(s.region);
  const auto one = analysis::boundary_map(table, coordinates, dynamics::FreeFlight{}, free_initial(table), 9, 300, 1);
  const auto two = analysis::boundary_map(table, coordinates, dynamics::FreeFlight{}, free_initial(table), 9, 300, 2);
  CHECK(one.rows == two.rows);
  const analysis::SectionLine line{{0, 1}, 0};
  CHECK(analysis::line_section(table, dynamics::FreeFlight{}, line, free_initial(table), 9, 300, 1).rows ==
        analysis::line_section(table, dynamics::FreeFlight{}, line, free_initial(table), 9, 300, 2).rows);
}

TEST_CASE("line section of the square: |p| = |vx| is conserved, crossings upward at y = 1/2") {
  const auto s = bundled_shape("square.yaml");
  const dynamics::Table table(s.region);
  const analysis::SectionLine line{{0, 1}, 0.5};  // y = 1/2, crossed upward: d = (−1, 0)
  const auto initial = free_initial(table);
  const auto r = analysis::line_section(table, dynamics::FreeFlight{}, line, initial, 5, 400, 2);
  REQUIRE(r.row_count() > 5 * 50);
  for (std::size_t i = 0; i < r.row_count(); ++i) {
    const auto start = initial(std::size_t(at(r, i, 0)));
    CHECK(std::abs(at(r, i, 3)) == Approx(std::abs(start.v.x()) / start.v.norm()).margin(1e-9));
    CHECK(-at(r, i, 2) >= -1e-12);  // u = −x along d = (−1, 0)
    CHECK(-at(r, i, 2) <= 1 + 1e-12);
  }
}

TEST_CASE("stroboscopic section: states at the drive phase asked for, with their kinetic energy") {
  const auto scene = bundled_scene("clover-driven.yaml", 4);
  const dynamics::PeriodicDriveFlight flight{scene.force.amplitude / scene.mass, scene.force.omega, scene.force.phase};
  const dynamics::Table table(scene.shape<2>().region);
  const double phase = 1.0;
  const auto r = analysis::stroboscopic_section(table, flight, phase, dynamics::initial_states(scene, table, flight),
                                                4, 300, 2, scene.mass);
  REQUIRE(r.row_count() > 4);
  for (std::size_t i = 0; i < r.row_count(); ++i) {
    const double t = at(r, i, 6);
    CHECK(std::cos(flight.omega * t + flight.phase0) == Approx(std::cos(phase)).margin(1e-9));
    CHECK(t == Approx((phase - flight.phase0 + 2 * geometry::pi * at(r, i, 1)) / flight.omega).margin(1e-12));
    CHECK(at(r, i, 7) == Approx(0.5 * scene.mass * (std::pow(at(r, i, 4), 2) + std::pow(at(r, i, 5), 2))));
    CHECK(table.contains(geometry::Vec2(at(r, i, 2), at(r, i, 3))));
  }
}

TEST_CASE("billiard bmap writes the map, its CSV and its picture; bad sections are refused") {
  const auto dir = scratch_root() / "bmap";
  auto r = billiard("bmap shapes/stadium.yaml --particles 3 --collisions 500 --quiet --out " + dir.string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  for (const char* file : {"bmap.npy", "bmap.csv", "bmap.json", "bmap.png"}) CHECK(std::filesystem::exists(dir / file));
  const auto meta = nlohmann::json::parse(read_file(dir / "bmap.json"));
  CHECK(meta["rows"] == 1500);
  const std::string csv = read_file(dir / "bmap.csv");
  CHECK(csv.rfind("particle,collision,s,p,t,energy\n", 0) == 0);

  r = billiard("bmap shapes/stadium.yaml --section \"x*y = 0\" --out " + (dir / "bad").string());
  CHECK(r.status == 2);
  CHECK(r.output.find("billiard: error: --section 'x*y = 0': the equation is not linear") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "bad"));
  // A magnetic field with a force: refused before any work (its search needs a time horizon).
  r = billiard("bmap scenes/clover-magnetic-driven.yaml --particles 2 --collisions 10 --out " + (dir / "bad").string());
  CHECK(r.status == 2);
  CHECK(r.output.find("billiard: error: scenes/clover-magnetic-driven.yaml: billiard bmap follows particles") !=
        std::string::npos);
  r = billiard("bmap shapes/stadium.yaml --strobe 0 --out " + (dir / "bad").string());
  CHECK(r.status == 2);
  CHECK(r.output.find("needs a periodic drive") != std::string::npos);
  r = billiard("bmap scenes/clover-driven.yaml --particles 2 --collisions 200 --strobe pi/2 --quiet --out " +
               (dir / "strobe").string());
  CHECK(r.status == 0);
  CHECK(std::filesystem::exists(dir / "strobe" / "strobe.png"));
}
