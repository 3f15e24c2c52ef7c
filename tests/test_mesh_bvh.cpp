// The triangle BVH never culls a triangle a flight can hit: its first hit is that of every
// triangle tried in turn in the mesh's order, bit for bit (of triangles crossed at the same
// time, the first in the mesh, whatever the tree and the walk's order), for straight rays
// (from inside the mesh, from the walls after a bounce, and aimed exactly at vertices and
// edges, where the float boxes are tightest), for helices (boxes grown by the cyclotron radius)
// and for driven flights (grown by the oscillation's amplitude); and the walls keep the mesh's
// own numbering.  The slab test, in floats, enters every child a ray meets in doubles, no
// later, and gives the times that a child-by-child test does, bit for bit, without a SIMD
// target and on every target.  A straight flight's walk passes over a leaf only where it moves
// away from each of its triangles by more than the triangle's margin, and that margin holds:
// a flight so headed never leaves through the triangle, even grazing it.
#include "billiards/dynamics/magnetic_flight.hpp"
#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <cstring>
#include <limits>
#include <string>

using namespace billiards;
using namespace billiards::dynamics;

namespace {

geometry3::Shape3 mesh_shape(const std::string& name) {
  return geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/" + name + ".yaml");
}

/// A table and its triangles' indices in the mesh's order (the inverse of Table3::piece_of).
struct MeshTable {
  const Table3& table;
  std::vector<int> in_mesh_order;
  explicit MeshTable(const Table3& t) : table(t), in_mesh_order(t.triangles().size()) {
    for (int i = 0; i < int(in_mesh_order.size()); ++i)
      in_mesh_order[std::size_t(table.piece_of({wall_kind3::triangle, i}))] = i;
  }
};

/// The earliest exit through any triangle, each asked up to `t_end` in the mesh's order,
/// without the BVH: of several crossed at the same time, the first in the mesh.
template <class Flight>
Hit3 every_triangle(const MeshTable& mesh, const Flight& flight, const typename Flight::State& s, double t_end,
                    int& ties) {
  const auto& triangles = mesh.table.triangles();
  Hit3 best;
  best.t = t_end;
  for (const int i : mesh.in_mesh_order) {
    const double t = flight.exit_time(s, triangles[i], t_end);
    if (t == best.t && best.found()) ++ties;
    if (t < best.t) best.t = t, best.wall = {wall_kind3::triangle, i};
  }
  return best;
}

/// The BVH's hit is the scan's: the same time bit for bit, through the same triangle, the first
/// in the mesh of those crossed at that very time (a tie at a shared edge or vertex).
template <class Flight>
void check_first_hit(const MeshTable& mesh, const Flight& flight, const typename Flight::State& s, double t_end,
                     int& compared, int& ties) {
  const auto hit = mesh.table.collision(flight, s, t_end);
  const Hit3 scan = every_triangle(mesh, flight, s, t_end, ties);
  REQUIRE(hit.found() == scan.found());
  if (!hit.found()) return;
  CHECK(hit.t == scan.t);
  CHECK(hit.wall == scan.wall);
  ++compared;
}

Vec3 random_direction(ParticleRng& rng) {
  const double z = 2 * rng.uniform() - 1, phi = 2 * geometry::pi * rng.uniform();
  const double rho = std::sqrt(1 - z * z);
  return {rho * std::cos(phi), rho * std::sin(phi), z};
}

/// A mesh's region moved by `offset`, with its own point location.
geometry3::Region3 moved(const geometry3::Region3& region, const Vec3& offset) {
  auto mesh = std::get<geometry3::TriangleMesh>(region.outer);
  for (Vec3& v : mesh.vertices) v += offset;
  mesh.locator = std::make_shared<geometry3::MeshLocator>(mesh);
  geometry3::Region3 out = region;
  out.outer = mesh;
  return out;
}

}  // namespace

TEST_CASE("the BVH finds the first hit of every triangle tried in turn: rays, rays through vertices and edges") {
  // The bumpy mesh also far from the origin, where a float's step is a tenth of its triangles
  // (the BVH's boxes are in the frame of their root's center).
  const Vec3 origin = Vec3::Zero(), far = Vec3(3e3, -1e4, 7e3);
  for (const auto& [name, offset] :
       {std::pair{"l-prism", origin}, std::pair{"bumpy-100k", origin}, std::pair{"bumpy-100k", far}}) {
    INFO(name << " moved by " << offset.transpose());
    const auto shape = mesh_shape(name);
    const auto region = moved(shape.region, offset);
    const Table3 table(region);
    const MeshTable mesh(table);
    const auto& triangles = table.triangles();
    const FreeFlight3 flight;
    ParticleRng rng(7, 0);
    int compared = 0, ties = 0;
    // Along trajectories: from inside, then from each wall after a bounce.
    for (int particle = 0; particle < 10; ++particle) {
      State3 s = sample_microcanonical(table, 1.0, rng);
      for (int k = 0; k < 100; ++k) {
        check_first_hit(mesh, flight, s, never, compared, ties);
        bounce(flight, s, table.collision(flight, s));
      }
    }
    // From inside through a vertex, the midpoint of an edge or a random point of an edge.
    for (int k = 0; k < 1500; ++k) {
      State3 s = sample_microcanonical(table, 1.0, rng);
      const auto& p = triangles[std::size_t(rng.uniform() * double(triangles.size()))].p;
      const int a = k % 3, b = (a + 1) % 3;
      const double along = k % 5 == 0 ? 0.0 : k % 5 == 1 ? 0.5 : rng.uniform();
      s.v = p[a] + along * (p[b] - p[a]) - s.x;
      check_first_hit(mesh, flight, s, never, compared, ties);
    }
    CHECK(compared == 2500);
    if (offset == origin) CHECK(ties > 100);  // (rays through vertices and edges cross several at once)
  }
}

TEST_CASE("the BVH grown by a tube finds the first hit of every triangle: helices and driven flights") {
  for (const char* name : {"l-prism", "bumpy-100k"}) {
    INFO(name);
    const auto shape = mesh_shape(name);
    const Table3 table(shape.region);
    const MeshTable mesh(table);
    const bool big = table.triangles().size() > 1000;
    ParticleRng rng(8, 0);
    int compared = 0, ties = 0;
    // Helices: a cyclotron radius about a tenth and a fiftieth of the mesh (the tube's pad).
    for (const double rc : {big ? 0.1 : 0.5, big ? 0.02 : 0.1}) {
      const MagneticFlight3 flight{random_direction(rng) / rc};
      State3 s = sample_microcanonical(table, 1.0, rng);
      for (int k = 0; k < (big ? 6 : 40); ++k) {
        check_first_hit(mesh, flight, s, s.t + 20, compared, ties);
        bounce(flight, s, table.collision(flight, s, s.t + 20));
      }
    }
    // The drive at low and high frequency: δ = |F|/(mω²) from 0.25 to 1e-5.
    for (const double omega : {2 * geometry::pi, 320 * geometry::pi}) {
      const PeriodicDriveFlight3 flight{10 * random_direction(rng), omega, 2 * geometry::pi * rng.uniform()};
      auto s = flight.start(sample_microcanonical(table, 1.0, rng));
      for (int k = 0; k < (big ? 6 : 40); ++k) {
        check_first_hit(mesh, flight, s, never, compared, ties);
        bounce(flight, s, table.collision(flight, s));
      }
    }
    CHECK(compared == (big ? 24 : 160));
  }
}

TEST_CASE("a helix with no horizon (billiard trajectory without --time) finds its first hit in a mesh") {
  // A helix wide beside the mesh crosses a triangle's plane again every turn, outside the
  // triangle's span: the search asks each triangle only as far as it walks, not to t = ∞ (a scan
  // that never ended, thrown as "did not converge").  The first hit is every triangle's first
  // before s.t + 20, which each helix here reaches sooner.
  const auto shape = mesh_shape("bumpy-100k");
  const Table3 table(shape.region);
  const MeshTable mesh(table);
  ParticleRng rng(9, 0);
  int compared = 0, ties = 0;
  for (const double rc : {10.0, 0.1}) {
    const MagneticFlight3 flight{random_direction(rng) / rc};
    State3 s = sample_microcanonical(table, 1.0, rng);
    for (int k = 0; k < 6; ++k) {
      const auto hit = table.collision(flight, s, never);
      const Hit3 scan = every_triangle(mesh, flight, s, s.t + 20, ties);
      REQUIRE(scan.found());
      REQUIRE(hit.found());
      CHECK(hit.t == scan.t);
      CHECK(hit.wall == scan.wall);
      ++compared;
      bounce(flight, s, hit);
    }
  }
  CHECK(compared == 12);
}

TEST_CASE("a mesh's triangles are numbered in the mesh's order (Table3::piece_of), whatever the BVH's order") {
  const auto shape = mesh_shape("bumpy-100k");
  const Table3 table(shape.region);
  const auto& mesh = std::get<geometry3::TriangleMesh>(shape.region.outer);
  REQUIRE(table.triangles().size() == mesh.triangles.size());
  for (int i = 0; i < int(table.triangles().size()); ++i) {
    const auto& face = mesh.triangles[std::size_t(table.piece_of({wall_kind3::triangle, i}))];
    for (int k = 0; k < 3; ++k) REQUIRE(table.triangles()[i].p[k] == mesh.vertices[face[k]]);
  }
}

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// A node of random boxes around the unit cube, some of them empty as the build leaves unused
/// children (lo = +∞, hi = −∞), some flat, and random cones of normals (some none: all zero).
Bvh::Node random_node(ParticleRng& rng) {
  Bvh::Node n{};
  for (int i = 0; i < Bvh::width; ++i) {
    const bool empty = rng.uniform() < 0.2, flat = rng.uniform() < 0.1;
    for (int k = 0; k < 3; ++k) {
      const double lo = 2 * rng.uniform() - 0.5, hi = flat && k == 0 ? lo : lo + rng.uniform();
      n.bound[0][k][i] = empty ? std::numeric_limits<float>::infinity() : float(lo);
      n.bound[1][k][i] = empty ? -std::numeric_limits<float>::infinity() : float(hi);
    }
    if (rng.uniform() < 0.2) continue;
    for (int k = 0; k < 4; ++k) n.cone[k][i] = std::int8_t(k < 3 ? 254 * rng.uniform() - 127 : -127 * rng.uniform());
  }
  return n;
}

/// The times [in, out] within [0, tau_max] that origin + τ dir spends in child i's box grown by
/// `pad`, in doubles (in > out: none); a zero component, the slab spans all or nothing.
std::pair<double, double> slab_in_doubles(const Bvh::Node& node, int i, const Vec3& origin, const Vec3& dir,
                                          double pad, double tau_max) {
  double in = 0, out = tau_max;
  for (int k = 0; k < 3; ++k) {
    const double lo = node.bound[0][k][i] - pad, hi = node.bound[1][k][i] + pad;
    if (!(lo <= hi)) return {1, 0};
    if (dir[k] == 0) {
      if (origin[k] < lo || origin[k] > hi) return {1, 0};
      continue;
    }
    const double a = (lo - origin[k]) / dir[k], b = (hi - origin[k]) / dir[k];
    in = std::max(in, std::min(a, b));
    out = std::min(out, std::max(a, b));
  }
  return {in, out};
}

}  // namespace

TEST_CASE("the slab test in floats enters every child a ray meets, no later, the same bit for bit on every target") {
  ParticleRng rng(10, 0);
  int compared = 0, met = 0, grazing = 0, away_count = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Bvh::Node node = random_node(rng);
    double extent = 0;
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < 3; ++k)
        for (int i = 0; i < Bvh::width; ++i)
          if (std::isfinite(node.bound[side][k][i]))
            extent = std::max(extent, double(std::abs(node.bound[side][k][i])));
    const Vec3 origin(2 * rng.uniform() - 0.5, 2 * rng.uniform() - 0.5, 2 * rng.uniform() - 0.5);
    // Every other ray is aimed at a corner of a child's box or a point of one of its edges,
    // where the box is met at a single point; a few are slow, to a speed of 1e-35.
    Vec3 dir = random_direction(rng);
    const int aimed = int(rng.uniform() * Bvh::width);
    if (trial % 2 && std::isfinite(node.bound[0][0][aimed])) {
      Vec3 corner;
      for (int k = 0; k < 3; ++k) corner[k] = node.bound[rng.uniform() < 0.5][k][aimed];
      const int along = trial % 4 == 1 ? int(3 * rng.uniform()) : -1;
      if (along >= 0) {
        const double lo = node.bound[0][along][aimed], hi = node.bound[1][along][aimed];
        corner[along] = lo + rng.uniform() * (hi - lo);
      }
      dir = corner - origin;
    }
    if (trial % 7 == 0) dir[trial % 3] = 0;  // (a slab the ray never crosses)
    if (trial % 11 == 0) dir *= 1e-35;
    const double pad = trial % 2 ? 0.0 : 0.01 * rng.uniform();
    const double tau_max = trial % 3 ? std::numeric_limits<double>::infinity() : 3 * rng.uniform() / dir.norm();
    const auto heading = trial % 5 < 3 ? Bvh::Heading::straight : Bvh::Heading::any;
    const detail::BvhRay ray(origin, dir, pad, extent, heading);
    const float tau_bound = ray.time_bound(tau_max);
    // The slab test one child and one axis at a time, as the lanes must compute it.
    unsigned mask = 0;
    float expected[Bvh::width];
    for (int i = 0; i < Bvh::width; ++i) {
      float in = 0, out = tau_bound;
      for (int k = 0; k < 3; ++k) {
        const int near = dir[k] < 0;  // (the side the ray enters the slab through)
        const float a = node.bound[near][k][i], b = node.bound[1 - near][k][i];
        const float ta = (a - ray.enter[k]) * ray.inv[k], tb = (b - ray.leave[k]) * ray.inv[k];
        in = in < ta ? ta : in;
        out = tb < out ? tb : out;
      }
      // Passed over where the heading moves away from the cone, none without one.
      const float facing = (float(node.cone[0][i]) * ray.heading[0] + float(node.cone[1][i]) * ray.heading[1]) +
                           float(node.cone[2][i]) * ray.heading[2];
      const bool away = facing < float(node.cone[3][i]);
      away_count += away;
      if (heading == Bvh::Heading::any) REQUIRE(!away);
      mask |= unsigned(in <= out && !away) << i;
      expected[i] = in;
      // A child the ray meets in doubles is entered, no later than there.
      const auto [in_d, out_d] = slab_in_doubles(node, i, origin, dir, pad, tau_max);
      if (in_d <= out_d && !away) {
        ++met, grazing += out_d - in_d < 1e-9 * (in_d + 1);
        INFO("trial " << trial << ", child " << i);
        REQUIRE(mask >> i & 1);
        REQUIRE(double(in) <= in_d * ray.time_scale);
      }
    }
    const auto check = [&](auto slab_test) {
      float t_in[Bvh::width];
      REQUIRE(slab_test(&node.bound[0][0][0], &node.cone[0][0], ray, tau_bound, t_in) == mask);
      for (int i = 0; i < Bvh::width; ++i) REQUIRE(same_bits(t_in[i], expected[i]));
      ++compared;
    };
    check(detail::slab_test<detail::QuadLanes>);
    for (const auto& target : simd::runnable_targets()) {
      INFO(target.name << ", trial " << trial);
      REQUIRE(bvh_lanes::kernel_of(target.bit));
      check(bvh_lanes::kernel_of(target.bit));
    }
  }
  CHECK(compared == 20000 * (1 + int(simd::runnable_targets().size())));
  CHECK(grazing > 1000);
  CHECK(met > 8000);
  CHECK(away_count > 10000);
}

namespace {

/// A unit heading that makes the angle arccos(c) with the unit normal n (c = n·h), about it at
/// the angle phi.
Vec3 heading_at(const Vec3& n, double c, double phi) {
  const Vec3 u = n.unitOrthogonal(), w = n.cross(u);
  return (c * n + std::sqrt(1 - c * c) * (std::cos(phi) * u + std::sin(phi) * w)).normalized();
}

}  // namespace

TEST_CASE("a straight flight moving away from a triangle by more than its margin never leaves through it") {
  // Triangles from a sliver to an equilateral one, from a hundredth to a millionth of the reach
  // R in size, and starts anywhere within R of their vertices: grazing at n·h = −δ (1 + 10⁻⁹),
  // and from on the triangle's plane to rounding (the test's dt = 0 branch).
  ParticleRng rng(13, 0);
  constexpr double R = 4;
  int grazing = 0, thin = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    const double size = R * std::pow(10.0, -2 - 4 * rng.uniform()), aspect = std::pow(10.0, -6 * rng.uniform());
    const Vec3 a = Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * R;
    const Vec3 e1 = size * random_direction(rng), e2 = aspect * size * random_direction(rng) + 0.3 * e1;
    const TriangleWall w(a, a + e1, a + e2, slack_ulps * R);
    const double delta = w.facing_away_margin(R);
    if (delta >= 1) {
      ++thin;
      continue;
    }
    // The start: a point of the triangle's plane, on the triangle or up to R / 2 beside it,
    // moved off the plane by at most the slack (on it to rounding) or into the region by up to
    // R / 4.
    const Vec3 u = w.normal.unitOrthogonal(), v = w.normal.cross(u);
    const double beside = trial % 4 < 2 ? 0.0 : R / 2;
    Vec3 x = a + rng.uniform() * e1 + beside * ((rng.uniform() - 0.5) * u + (rng.uniform() - 0.5) * v);
    x -= w.normal * (trial % 2 ? (2 * rng.uniform() - 1) * w.slack : rng.uniform() * R / 4);
    const double c = -delta * (1 + 1e-9) - (trial % 3 == 0 ? rng.uniform() : 0.0);
    const Vec3 h = heading_at(w.normal, std::max(-1.0, c), 2 * geometry::pi * rng.uniform());
    if (!(w.normal.dot(h) < -delta)) continue;  // (the heading's rounding)
    grazing += c > -2 * delta;
    State3 s;
    s.x = x, s.v = h * std::pow(10.0, 4 * rng.uniform() - 2);
    INFO("trial " << trial);
    REQUIRE(straight_exit_time(s, Ray(s.x, s.v), w, never) == never);
  }
  CHECK(grazing > 80000);
  CHECK(thin > 100);
}

TEST_CASE("a straight flight's walk passes over a leaf only where it moves away from each of its triangles") {
  // The BVH over the bumpy mesh's triangles, with their margins and with margins up to 0.3 (a
  // cone widened by arcsin δ): every leaf a walk with Heading::any visits and the straight
  // walk passes over has each triangle facing away by more than its margin, n·h < −δ; the
  // straight walk from a wall passes over some of the leaves (around its start; to infinity,
  // the walk asks every leaf it enters).
  const auto shape = mesh_shape("bumpy-100k");
  const Table3 table(shape.region);
  const auto& mesh = std::get<geometry3::TriangleMesh>(shape.region.outer);
  ParticleRng rng(14, 0);
  for (const bool wide : {false, true}) {
    std::vector<Bvh::Box> boxes;
    std::vector<Bvh::Facing> facings;
    for (const auto& t : mesh.triangles) {
      const TriangleWall w(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]], slack_ulps);
      const auto [lo, hi] = w.box();
      boxes.push_back({lo, hi});
      facings.push_back({w.normal, wide ? 0.3 * rng.uniform() : w.facing_away_margin(4)});
    }
    const Bvh bvh(boxes, facings, 0, bvh_lanes::kernel_of(simd::chosen_target()));
    long visited = 0, passed_over = 0;
    const FreeFlight3 flight;
    for (int k = 0; k < 300; ++k) {
      // From a wall just hit: headings as the bounce leaves it, and grazing its plane, just
      // facing away from it.
      State3 s = sample_microcanonical(table, 1.0, rng);
      const auto hit = table.collision(flight, s);
      REQUIRE(hit.found());
      bounce(flight, s, hit);
      const Bvh::Facing& f = facings[std::size_t(table.piece_of(hit.wall))];
      const Vec3 h = k % 2 ? Vec3(s.v.normalized())
                           : heading_at(f.normal, -f.margin * (1 + 1e-6), 2 * geometry::pi * rng.uniform());
      // The leaves (first, count) each walk asks.
      std::vector<std::pair<int, int>> any, straight;
      const auto walk = [&](std::vector<std::pair<int, int>>& leaves, Bvh::Heading heading) {
        bvh.walk(
            s.x, h, 0, never, [&](int first, int count) { return leaves.emplace_back(first, count), never; },
            [](int, int) {}, heading);
        std::sort(leaves.begin(), leaves.end());
      };
      walk(any, Bvh::Heading::any);
      walk(straight, Bvh::Heading::straight);
      REQUIRE(std::includes(any.begin(), any.end(), straight.begin(), straight.end()));
      visited += long(any.size()), passed_over += long(any.size() - straight.size());
      std::vector<std::pair<int, int>> over;
      std::set_difference(any.begin(), any.end(), straight.begin(), straight.end(), std::back_inserter(over));
      for (const auto& [first, count] : over)
        for (int i = first; i < first + count; ++i) {
          const Bvh::Facing& g = facings[std::size_t(bvh.order()[i])];
          INFO("k " << k << ", leaf " << first << ", triangle " << i);
          REQUIRE(g.normal.dot(h) < -g.margin);
        }
    }
    INFO("wide " << wide << ": " << passed_over << " of " << visited << " leaves passed over");
    CHECK(passed_over > visited / 10);
  }
}

TEST_CASE("free, driven and magnetic flights in a mesh hit the same walls at the same times on every target") {
  const auto shape = mesh_shape("bumpy-100k");
  const Table3 scalar(shape.region, simd::scalar);
  ParticleRng rng(11, 0);
  const FreeFlight3 free;
  const PeriodicDriveFlight3 driven{10 * random_direction(rng), 320 * geometry::pi, 0.3};
  const MagneticFlight3 magnetic{random_direction(rng) / 0.1};
  for (const auto& target : simd::runnable_targets()) {
    INFO(target.name);
    const Table3 table(shape.region, target.bit);
    ParticleRng start(12, 0);
    int compared = 0;
    const auto follow = [&](const auto& flight, auto s, int bounces) {
      for (int k = 0; k < bounces; ++k, ++compared) {
        const auto hit = table.collision(flight, s, s.t + 20), expected = scalar.collision(flight, s, s.t + 20);
        REQUIRE(hit.found());
        REQUIRE(hit.wall == expected.wall);
        REQUIRE(same_bits(hit.t, expected.t));
        bounce(flight, s, hit);
      }
    };
    for (int particle = 0; particle < 20; ++particle) follow(free, sample_microcanonical(table, 1.0, start), 100);
    follow(driven, driven.start(sample_microcanonical(table, 1.0, start)), 20);
    follow(magnetic, sample_microcanonical(table, 1.0, start), 10);
    CHECK(compared == 2030);
  }
}
