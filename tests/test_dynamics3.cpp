// Free 3-D dynamics: the collision rate of every bundled shape equals v/λ with λ = 4V/S
// (Santaló; exact in expectation for the microcanonical ensemble, whatever the dynamics),
// no escapes, exact corner reflections, watertight triangle edges, grazing balls.
#include "cli_helpers.hpp"

#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace billiards;
using namespace billiards::dynamics;
using geometry3::Region3;

namespace {

const std::string shapes3 = BILLIARDS_SOURCE_DIR "/shapes/3d/";

/// The unit cube as 12 triangles, counter-clockwise seen from outside.
const std::string cube_off =
    "OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
    "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";

/// Is x outside the region by more than rounding?  After a corner hit a particle may sit a
/// few ulps beyond a wall (and fly zero time), as in 2-D; the distance decides, computed
/// independently of the collision code (closed forms; CGAL's AABB tree for meshes).
bool is_outside(const Region3& region, const Vec3& x) {
  constexpr double rounding = 1e-13;
  for (const auto& b : region.holes)
    if (b.radius - (x - b.center).norm() > rounding) return true;
  if (const auto* p = std::get_if<geometry3::ConvexPolyhedron>(&region.outer)) {
    for (const auto& plane : p->planes)
      if (plane.beyond(x) > rounding) return true;
    return false;
  }
  if (const auto* b = std::get_if<geometry3::Ball>(&region.outer)) return (x - b->center).norm() - b->radius > rounding;
  const auto& mesh = std::get<geometry3::TriangleMesh>(region.outer);
  return !mesh.locator->inside(x) && mesh.locator->distance(x) > rounding;
}

struct RunStats {
  double mean = 0, se = 0;  // collisions per particle
  long collisions = 0, escapes = 0, outside = 0;
  double max_speed_error = 0;
};

/// N microcanonical particles at speed 1 flying for time T.  A flight that finds no wall is an
/// escape; the midpoint of every 8th flight is checked with is_outside.
RunStats run(const Table3& table, int particles, double T) {
  RunStats r;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < particles; ++i) {
    dynamics::ParticleRng rng(11, i);
    State3 s = sample_microcanonical(table, 1.0, rng);
    long n = 0;
    while (true) {
      const Hit3 hit = collision(table, FreeFlight3{}, s);
      if (!hit.found()) {
        ++r.escapes;
        break;
      }
      if (n % 8 == 0 && is_outside(table.region(), s.x + 0.5 * (hit.t - s.t) * s.v)) ++r.outside;
      if (hit.t > T) break;
      bounce(FreeFlight3{}, s, hit);
      restore_speed(s.v, 1.0);
      ++n;
    }
    r.max_speed_error = std::max(r.max_speed_error, std::abs(s.v.norm() - 1));
    r.collisions += n;
    sum += n;
    sum2 += double(n) * n;
  }
  r.mean = sum / particles;
  r.se = std::sqrt((sum2 / particles - r.mean * r.mean) / (particles - 1));
  return r;
}

/// Runs ~`target` collisions in `name` and compares the rate with v/λ.
void check_rate(const geometry3::Shape3& shape, const std::string& name, long target) {
  const Table3 table(shape.region);
  const double lambda = geometry::mean_free_path(measures_of(shape.region));
  const int particles = 4000;
  const double T = double(target) / particles * lambda;
  const RunStats r = run(table, particles, T);
  const double expected = T / lambda;
  INFO(name << ": " << r.collisions << " collisions, " << r.mean << " ± " << r.se << " per particle, expected "
            << expected);
  CHECK(r.escapes == 0);
  CHECK(r.outside == 0);
  CHECK(r.collisions >= target * 9 / 10);
  CHECK(std::abs(r.mean - expected) < 4 * r.se);
  CHECK(r.max_speed_error < 1e-14);
}

}  // namespace

TEST_CASE("free collision rate is v / lambda with lambda = 4V/S, and nothing escapes") {
  for (const char* name : {"cube", "ball", "sinai3", "octahedron", "l-prism", "bumpy-100k"})
    check_rate(geometry3::load_shape3(shapes3 + name + ".yaml"), name, 1000000);
}

TEST_CASE("a triangulated cube with a ball inside: rate v / lambda, nothing escapes") {
  const auto dir = scratch("dynamics3-ball");
  std::ofstream(dir / "cube.off") << cube_off;
  const auto shape = geometry3::parse_shape3(
      "dimension: 3\nboundary:\n  mesh: cube.off\nholes:\n  - ball: {center: [0.4, 0.5, 0.6], radius: 0.3}\n",
      (dir / "s.yaml").string());
  check_rate(shape, "cube mesh + ball", 300000);
}

TEST_CASE("a flight into a corner of the cube comes back: v -> -v") {
  for (const char* name : {"cube", "l-prism"}) {
    const auto shape = geometry3::load_shape3(shapes3 + name + ".yaml");
    const Table3 table(shape.region);
    // From (0.25, 0.25, 0.25) along (1, 1, 1)-ish to the corner (0, 0, 0): three walls meet.
    State3 s;
    s.x = Vec3(0.25, 0.5, 0.75);
    s.v = -s.x / s.x.norm();
    const Vec3 v0 = s.v;
    int bounces = 0;
    while (bounces < 3) {
      const Hit3 hit = collision(table, FreeFlight3{}, s);
      REQUIRE(hit.found());
      CHECK(hit.point.norm() < 1e-15);
      bounce(FreeFlight3{}, s, hit);
      restore_speed(s.v, 1.0);
      ++bounces;
    }
    CHECK((s.v + v0).norm() < 1e-15);
    const Hit3 next = collision(table, FreeFlight3{}, s);  // now flying straight back out of the corner
    REQUIRE(next.found());
    CHECK(next.t > 0.5);
  }
}

TEST_CASE("triangle meshes are watertight: rays through edges and vertices always hit") {
  // The cube as 12 triangles; rays from inside aimed exactly at the diagonals that split its
  // faces, at its edges and at its vertices.
  const auto dir = scratch("dynamics3-watertight");
  std::ofstream(dir / "cube.off") << cube_off;
  const auto shape = geometry3::parse_shape3("dimension: 3\nboundary:\n  mesh: cube.off\n", (dir / "s.yaml").string());
  const Table3 table(shape.region);
  dynamics::ParticleRng rng(3, 0);
  int shots = 0;
  for (int i = 0; i < 20000; ++i) {
    State3 s;
    s.x = Vec3(rng.uniform(), rng.uniform(), rng.uniform());
    const double u = rng.uniform();
    // Targets on face diagonals (x = y on z = 0), on edges (y = 0, z = 0) and at a vertex.
    const Vec3 target = i % 3 == 0 ? Vec3(u, u, 0) : i % 3 == 1 ? Vec3(u, 0, 0) : Vec3(1, 1, 1);
    s.v = target - s.x;
    const Hit3 hit = collision(table, FreeFlight3{}, s);
    REQUIRE(hit.found());
    CHECK((hit.point - target).norm() < 1e-14);
    ++shots;
  }
  CHECK(shots == 20000);
  // Lattice directions from dyadic points: every bounce lands exactly on an edge, a face
  // diagonal or a vertex of the triangulated cube, 10⁴ times each.
  for (const Vec3& d : {Vec3(1, 1, 1), Vec3(1, 1, 0), Vec3(1, -1, 0), Vec3(2, 1, 0), Vec3(1, 2, 2), Vec3(0, 0, 1)}) {
    State3 s;
    s.x = Vec3(0.5, 0.25, 0.75);
    s.v = d / d.norm();
    int outside = 0;
    for (int k = 0; k < 10000; ++k) {
      const Hit3 hit = collision(table, FreeFlight3{}, s);
      REQUIRE(hit.found());
      outside += is_outside(shape.region, s.x + 0.5 * (hit.t - s.t) * s.v);
      bounce(FreeFlight3{}, s, hit);
      restore_speed(s.v, 1.0);
    }
    CHECK(outside == 0);
  }
}

TEST_CASE("a ray tangent to a ball touches it without colliding; one ulp closer collides") {
  const auto shape = geometry3::load_shape3(shapes3 + "sinai3.yaml");
  const Table3 table(shape.region);
  State3 s;
  s.x = Vec3(-0.45, 0.25, 0.1);  // the line y = 0.25, z = 0.1 misses; z = 0 is tangent at R = 0.25
  s.v = Vec3(1, 0, 0);
  CHECK(sphere_discriminant_sign_filtered(s.x, Vec3::Zero(), s.v, 0.25) < 0);
  s.x.z() = 0;
  CHECK(sphere_discriminant_sign_filtered(s.x, Vec3::Zero(), s.v, 0.25) == 0);  // decided by GMP
  Hit3 hit = collision(table, FreeFlight3{}, s);
  REQUIRE(hit.found());
  CHECK(std::abs(hit.point.x() - 0.5) < 1e-15);  // flies past the ball to the far wall
  s.x.y() = std::nextafter(0.25, 0.0);
  CHECK(sphere_discriminant_sign_filtered(s.x, Vec3::Zero(), s.v, 0.25) > 0);
  hit = collision(table, FreeFlight3{}, s);
  REQUIRE(hit.found());
  CHECK(std::abs(hit.point.norm() - 0.25) < 1e-15);
  CHECK(hit.normal.y() < -0.99);  // the ball's outward normal (into the ball) at the graze
}

// The 3-D primitives' queries, at the hits of free trajectories in every bundled table, against
// the independent point-in-region test and the normals' own rate of turning: the hit point is
// on the wall (|gap| at rounding) and in its box; the gap is < 0 a little inside along the
// normal (where the region is) and > 0 a little outside; |curvature| is how fast the normal
// turns along the wall, |n(p) − n(q)| / |p − q| for a nearby point q on the wall, and its sign
// is + for the sphere the region is inside, − for a ball scatterer, 0 for flat walls.
TEST_CASE("3-D walls: gap, normal, box and curvature at hit points agree with the region") {
  for (const char* name : {"ball", "cube", "l-prism", "octahedron", "sinai3"}) {
    INFO(name);
    const auto shape = geometry3::load_shape3(shapes3 + name + ".yaml");
    const Table3 table(shape.region);
    const double h = 1e-6 * (table.hi() - table.lo()).maxCoeff();
    dynamics::ParticleRng rng(5, 0);
    State3 s = sample_microcanonical(table, 1.0, rng);
    int checked = 0;
    for (int k = 0; k < 200; ++k) {
      const auto hit = collision(table, FreeFlight3{}, s);
      REQUIRE(hit.found());
      table.visit(hit.wall, [&](const auto& w) {
        CHECK(std::abs(w.gap(hit.point)) < 1e-12);
        CHECK((w.normal_at(hit.point) - hit.normal).norm() < 1e-15);
        const auto [lo, hi] = w.box();
        CHECK(((hit.point - lo).minCoeff() >= 0 && (hi - hit.point).minCoeff() >= 0));
        const Vec3 in = hit.point - h * hit.normal, out = hit.point + h * hit.normal;
        CHECK(w.gap(in) < 0);
        CHECK(w.gap(out) > 0);
        CHECK(table.contains(in));
        CHECK(!table.contains(out));
        // A point q on the wall near the hit: the hit point moved along the wall and back onto it.
        const Vec3 t = hit.normal.unitOrthogonal();
        Vec3 q = hit.point + h * t;
        q -= w.gap(q) * w.normal_at(q);
        const double turning = (w.normal_at(q) - w.normal_at(hit.point)).norm() / (q - hit.point).norm();
        CHECK(std::abs(std::abs(w.curvature_at(hit.point)) - turning) < 1e-6 * (1 + turning));
        const bool ball_hole = hit.wall.kind == wall_kind3::sphere && !table.spheres()[hit.wall.index].focusing;
        const double kappa = w.curvature_at(hit.point);
        CHECK((hit.wall.kind != wall_kind3::sphere ? kappa == 0 : ball_hole ? kappa < 0 : kappa > 0));
        ++checked;
      });
      bounce(FreeFlight3{}, s, hit);
      restore_speed(s.v, 1.0);
    }
    CHECK(checked == 200);
  }
}
