// Exact measures of every bundled shape against closed forms and independent methods.
#include "billiards/dynamics/random.hpp"
#include "billiards/dynamics/table.hpp"
#include "billiards/geometry.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <tuple>

using namespace billiards;
using geometry::pi;
using geometry::Vec2;

namespace {

geometry::Measures measures(const std::string& name, const Overrides& set = {}) {
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + name + ".yaml", set);
  return geometry::measures_of(shape.region);
}

bool close(double a, double b, double rel = 1e-14) { return std::abs(a - b) <= rel * std::abs(b); }

/// Neumaier's compensated sum, so that summing many small terms adds no rounding drift.
struct Sum {
  double sum = 0, carry = 0;
  void add(double x) {
    const double t = sum + x;
    carry += std::abs(sum) >= std::abs(x) ? (sum - t) + x : (x - t) + sum;
    sum = t;
  }
  double value() const { return sum + carry; }
};

/// Area and perimeter of the polygon through n points per piece (independent of the closed
/// forms: only point_along is shared), extrapolated twice from n, 2n and 4n (error O(n⁻⁶)).
std::pair<double, double> refined(const geometry::Region2& region, int n) {
  auto at = [&](int k) {
    Sum area, length;
    for (const geometry::Loop* loop : region.loops())
      for (const auto& p : loop->pieces)
        for (int i = 0; i < k; ++i) {
          const Vec2 a = geometry::point_along(p, double(i) / k), b = geometry::point_along(p, double(i + 1) / k);
          area.add(0.5 * geometry::cross(a, b));
          length.add((b - a).norm());
        }
    return std::pair{area.value(), length.value()};
  };
  auto richardson = [](double f1, double f2, double f4) {
    const double g1 = (4 * f2 - f1) / 3, g2 = (4 * f4 - f2) / 3;
    return (16 * g2 - g1) / 15;
  };
  const auto [a1, l1] = at(n);
  const auto [a2, l2] = at(2 * n);
  const auto [a4, l4] = at(4 * n);
  return {richardson(a1, a2, a4), richardson(l1, l2, l4)};
}

}  // namespace

TEST_CASE("closed forms of the bundled shapes") {
  auto m = measures("circle");
  CHECK(close(m.volume, pi));
  CHECK(close(m.surface, 2 * pi));
  CHECK(close(geometry::mean_free_path(m), pi / 2));
  m = measures("annulus");
  CHECK(close(m.volume, pi * (1 - 0.16)));
  CHECK(close(m.surface, 2 * pi * 1.4));
  m = measures("square");
  CHECK(m.volume == 1);
  CHECK(m.surface == 4);
  CHECK(close(m.boundary_tensor(0, 0), 2));
  CHECK(std::abs(m.boundary_tensor(0, 1)) < 1e-15);
  m = measures("sinai");
  CHECK(close(m.volume, 1 - pi / 16));
  CHECK(close(m.surface, 4 + pi / 2));
  m = measures("stadium");  // a = r = 1
  CHECK(close(m.volume, 4 + pi));
  CHECK(close(m.surface, 4 + 2 * pi));
  CHECK(close(m.boundary_tensor(0, 0), pi));  // only the caps have normals along x
  CHECK(close(m.boundary_tensor(1, 1), 4 + pi));
  m = measures("mushroom");  // R = 1, w = 1/4, h = 1
  CHECK(close(m.volume, pi / 2 + 0.5));
  CHECK(close(m.surface, pi + 2 * 0.75 + 2 * 1 + 0.5));
  m = measures("l-room");
  CHECK(m.volume == 3);
  CHECK(m.surface == 8);
}

TEST_CASE("the paper's clover: lambda = 2.610") {
  const auto m = measures("clover");
  CHECK(std::abs(geometry::mean_free_path(m) - 2.610) < 5e-4);
  // W/S = F²/2 for any direction (the paper, Appendix B): the boundary tensor is isotropic.
  CHECK(close(m.boundary_tensor(0, 0), m.surface / 2, 1e-13));
  CHECK(close(m.boundary_tensor(1, 1), m.surface / 2, 1e-13));
  CHECK(std::abs(m.boundary_tensor(0, 1)) < 1e-13 * m.surface);
  // Scaling both radii by s scales V by s² and S by s.
  const auto big = measures("clover", {{"R1", "3"}, {"R2", "6"}});
  CHECK(close(big.volume, 9 * m.volume, 1e-13));
  CHECK(close(big.surface, 3 * m.surface, 1e-13));
}

TEST_CASE("Green's theorem agrees with an extrapolated polygonal refinement to 1e-14") {
  for (const char* name : {"clover", "stadium", "sinai", "mushroom", "annulus", "triangle", "wavy-1200"}) {
    INFO(name);
    const auto shape = geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml");
    const auto m = geometry::measures_of(shape.region);
    const auto [area, length] = refined(shape.region, shape.region.piece_count() > 100 ? 1 : 1000);
    CHECK(std::abs(m.volume / area - 1) < 1e-14);
    CHECK(std::abs(m.surface / length - 1) < 1e-14);
  }
}

TEST_CASE("the triangle's area by Heron's formula") {
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/triangle.yaml");
  const auto m = geometry::measures_of(shape.region);
  std::vector<double> sides;
  for (const auto& p : shape.region.outer.pieces) sides.push_back(geometry::length_of(p));
  const double s = (sides[0] + sides[1] + sides[2]) / 2;
  CHECK(close(m.volume, std::sqrt(s * (s - sides[0]) * (s - sides[1]) * (s - sides[2])), 1e-13));
}

TEST_CASE("the containment test's classified cells answer as the crossing count does") {
  // contains(p) answers from a fine cell no wall comes near; contains(p, tolerance) always counts
  // crossings.  They must agree everywhere: at random points of the box and just beside walls
  // (points pushed off each wall by ±tolerance/2 and ±3 tolerances); and a segment that
  // certainly_contains certifies must be inside at every point.
  for (const char* name : {"clover", "mushroom", "sinai", "annulus", "l-room", "wavy-1200"}) {
    INFO(name);
    const auto shape = geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml");
    const dynamics::Table table(shape.region);
    dynamics::ParticleRng rng(5, 0);
    const Vec2 lo = table.lo(), size = table.hi() - table.lo();
    int disagreements = 0, classified = 0, fine = 0;
    auto check = [&](const Vec2& p) {
      disagreements += table.contains(p) != table.contains(p, table.tolerance());
    };
    for (int i = 0; i < 200000; ++i) {
      const Vec2 p = lo + Vec2(rng.uniform() * size.x(), rng.uniform() * size.y());
      check(p);
      classified += table.classes().of(p) != dynamics::Table::Classes::mixed;
      fine += table.fine_classes().of(p) != dynamics::Table::Classes::mixed;
    }
    const auto ids = table.wall_ids();
    for (int i = 0; i < 20000; ++i) {
      const Vec2 p = lo + Vec2(rng.uniform() * size.x(), rng.uniform() * size.y());
      const auto w = ids[std::size_t(rng.uniform() * ids.size())];
      // The nearest point of wall w's line or circle, then off it along the normal.
      Vec2 foot, n;
      if (w.kind == dynamics::wall_kind::arc) std::tie(foot, n) = table.arcs()[w.index].radial_contact(p);
      else std::tie(foot, n) = table.segments()[w.index].contact(p, Vec2::Zero());
      for (const double k : {-3.0, -0.5, 0.5, 3.0}) check(foot + k * table.tolerance() * n);
    }
    // A segment certified inside (both ends in one inside cell, or in neighbouring cells of an
    // inside block) is inside all along: δ-sized segments, as a drive's oscillation segment
    // at high ω, and segments up to 1.5 cells long, which cross into neighbouring cells.
    const double cell = std::max(size.x() / table.classes().nx, size.y() / table.classes().ny);
    int certified = 0, across = 0, wrong = 0;
    for (int i = 0; i < 40000; ++i) {
      const Vec2 p = lo + Vec2(rng.uniform() * size.x(), rng.uniform() * size.y());
      const double longest = i % 2 ? 0.002 * size.norm() : 1.5 * cell;
      const double angle = 2 * geometry::pi * rng.uniform(), length = longest * rng.uniform();
      const Vec2 q = p + length * Vec2(std::cos(angle), std::sin(angle));
      if (!table.certainly_contains(p, q)) continue;
      ++certified;
      across += table.classes().cell_of(p) != table.classes().cell_of(q);
      for (int k = 0; k <= 64; ++k) wrong += !table.contains(p + (q - p) * (k / 64.0), table.tolerance());
    }
    CHECK(disagreements == 0);
    CHECK(wrong == 0);
    CHECK(certified > 10000);  // (most short segments in the region are certified at once)
    CHECK(across > 1000);      // (and many of them end in another cell)
    UNSCOPED_INFO(name << ": " << certified << " of 40000 short segments certified inside, " << across << " across cells");
    UNSCOPED_INFO(name << ": " << classified / 2000.0 << "% of the box in classified cells");
    CHECK(classified > 100000);  // (the lookup answers for most points)
    UNSCOPED_INFO(name << ": " << fine / 2000.0 << "% of the box in classified fine cells");
    CHECK(fine >= classified);  // (refined where no grid lists the walls: more, never fewer)
  }
}

TEST_CASE("Monte Carlo area with the winding-number test matches V within 4 sigma") {
  for (const char* name : {"clover", "mushroom", "sinai", "wavy-1200"}) {
    INFO(name);
    const auto shape = geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml");
    const dynamics::Table table(shape.region);
    const auto m = geometry::measures_of(shape.region);
    dynamics::ParticleRng rng(3, 0);
    const Vec2 lo = table.lo(), size = table.hi() - table.lo();
    const int n = 400000;
    int inside = 0;
    for (int i = 0; i < n; ++i)
      inside += table.contains(lo + Vec2(rng.uniform() * size.x(), rng.uniform() * size.y()));
    const double box = size.x() * size.y(), p = double(inside) / n;
    CHECK(std::abs(p * box - m.volume) < 4 * box * std::sqrt(p * (1 - p) / n));
  }
}
