// CGAL validation of 2-D tables (geometry::validate): valid tables pass, including tangent
// joints computed in double and irrational centres; every kind of error names the file, the
// line(s) of the piece(s) involved and the problem.
#include "billiards/geometry.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace billiards;
using namespace billiards::geometry;

namespace {

const std::string file = "table.yaml";

Piece segment(const Vec2& a, const Vec2& b) { return Segment{a, b}; }

/// Arc of the circle (c, r) from polar angle t0 sweeping dt (> 0 counter-clockwise).
Piece arc(const Vec2& c, double r, double t0, double dt) {
  Arc a;
  a.center = c;
  a.radius = r;
  a.start = t0;
  a.sweep = dt;
  a.source = a.point_at(t0);
  a.target = a.point_at(t0 + dt);
  return a;
}

void set_source(Piece& p, const Vec2& q) {
  if (auto* s = std::get_if<Segment>(&p))
    s->a = q;
  else
    std::get<Arc>(p).source = q;
}

/// A loop written at `line`, its pieces on the following lines.  Each joint is the end of the
/// piece before it, bit for bit, as the loader makes it.
Loop loop(int line, std::vector<Piece> pieces) {
  Loop l;
  l.origin = {file, line};
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (pieces.size() > 1) set_source(pieces[(i + 1) % pieces.size()], target_of(pieces[i]));
    l.where.push_back({file, line + 1 + int(i)});
  }
  l.pieces = std::move(pieces);
  return l;
}

Loop polygon(int line, const std::vector<Vec2>& v) {
  std::vector<Piece> pieces;
  for (std::size_t i = 0; i < v.size(); ++i) pieces.push_back(segment(v[i], v[(i + 1) % v.size()]));
  return loop(line, pieces);
}

/// A full circle; a hole (clockwise) unless `inside`.
Loop circle(int line, const Vec2& c, double r, bool inside = false) {
  Arc a = std::get<Arc>(arc(c, r, 0, inside ? 2 * pi : -2 * pi));
  a.target = a.source;
  return loop(line, {a});
}

Region2 region(Loop outer, std::vector<Loop> holes = {}) {
  Region2 r;
  r.origin = {file, 1};
  r.outer = std::move(outer);
  r.holes = std::move(holes);
  return r;
}

std::string error_of(const Region2& r) {
  try {
    validate(r);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

Loop square(int line, double side = 4) { return polygon(line, {{0, 0}, {side, 0}, {side, side}, {0, side}}); }

/// Stadium: half circles of radius r at x = ±a joined by segments, centred at c, turned by phi.
Loop stadium(int line, double a, double r, const Vec2& c = {0, 0}, double phi = 0) {
  const Eigen::Rotation2Dd rot(phi);
  const auto at = [&](double x, double y) { return Vec2(c + rot * Vec2(x, y)); };
  return loop(line, {segment(at(-a, -r), at(a, -r)), arc(at(a, 0), r, phi - pi / 2, pi), segment(at(a, r), at(-a, r)),
                     arc(at(-a, 0), r, phi + pi / 2, pi)});
}

/// Arc of the circle (c, r) from point p to point q, counter-clockwise or not; p and q are its
/// ends bit for bit.
Piece arc_between(const Vec2& c, double r, const Vec2& p, const Vec2& q, bool ccw) {
  const double t0 = std::atan2(p.y() - c.y(), p.x() - c.x());
  double dt = std::atan2(q.y() - c.y(), q.x() - c.x()) - t0;
  if (ccw && dt <= 0) dt += 2 * pi;
  if (!ccw && dt >= 0) dt -= 2 * pi;
  Arc a = std::get<Arc>(arc(c, r, t0, dt));
  a.source = p;
  a.target = q;
  return a;
}

/// Jarzynski's clover: three focusing lobes of radius r1 (centres at 2 r1/√3, irrational) and
/// three dispersing arcs of radius r2 tangent to them, all joints tangencies computed in double.
Loop clover(int line, double r1, double r2) {
  const double a = 2 * r1 / std::sqrt(3.0);
  const double b = (a + std::sqrt(4 * (r1 + r2) * (r1 + r2) - 3 * a * a)) / 2;
  std::vector<Vec2> centre;
  for (int k = 0; k < 3; ++k) {
    centre.push_back(a * Vec2(std::cos(-pi / 6 + 2 * pi / 3 * k), std::sin(-pi / 6 + 2 * pi / 3 * k)));
    centre.push_back(b * Vec2(std::cos(pi / 6 + 2 * pi / 3 * k), std::sin(pi / 6 + 2 * pi / 3 * k)));
  }
  std::vector<double> radius{r1, r2, r1, r2, r1, r2};
  std::vector<Vec2> joint(6);  // joint[i]: between circle i and circle i + 1
  for (int i = 0; i < 6; ++i) {
    const Vec2 &p = centre[i], &q = centre[(i + 1) % 6];
    joint[i] = p + radius[i] * (q - p).normalized();
  }
  std::vector<Piece> pieces;
  for (int i = 0; i < 6; ++i)
    pieces.push_back(arc_between(centre[i], radius[i], joint[(i + 5) % 6], joint[i], i % 2 == 0));
  return loop(line, pieces);
}

/// The cusped triangle between three mutually tangent disks of radius r: three dispersing
/// arcs meeting at zero-angle cusps.
Loop cusped_triangle(int line, double r) {
  std::vector<Vec2> c;
  for (int k = 0; k < 3; ++k)
    c.push_back(2 * r / std::sqrt(3.0) * Vec2(std::cos(pi / 2 + 2 * pi / 3 * k), std::sin(pi / 2 + 2 * pi / 3 * k)));
  const auto touch = [&](int i, int j) { return Vec2((c[i] + c[j]) / 2); };
  return loop(line, {arc_between(c[0], r, touch(2, 0), touch(0, 1), false),
                     arc_between(c[1], r, touch(0, 1), touch(1, 2), false),
                     arc_between(c[2], r, touch(1, 2), touch(2, 0), false)});
}

/// A four-centre oval: small arcs of radius r centred at (±d, 0), large arcs centred at
/// (0, ∓e), internally tangent to them.  Radii nearly equal when d, e ≪ r.
Loop oval(int line, double r, double d, double e) {
  const double big = r + std::hypot(d, e);
  const Vec2 right(d, 0), left(-d, 0), top(0, -e), bottom(0, e);  // centres; "top" arc centred below
  const auto joint = [&](const Vec2& large, const Vec2& small) {
    return Vec2(large + big * (small - large).normalized());
  };
  return loop(line, {arc_between(right, r, joint(bottom, right), joint(top, right), true),
                     arc_between(top, big, joint(top, right), joint(top, left), true),
                     arc_between(left, r, joint(top, left), joint(bottom, left), true),
                     arc_between(bottom, big, joint(bottom, left), joint(bottom, right), true)});
}

/// The same loop run the other way.
Loop reversed(Loop l) {
  std::reverse(l.pieces.begin(), l.pieces.end());
  std::reverse(l.where.begin(), l.where.end());
  for (Piece& p : l.pieces) {
    if (auto* s = std::get_if<Segment>(&p)) {
      std::swap(s->a, s->b);
    } else {
      auto& a = std::get<Arc>(p);
      std::swap(a.source, a.target);
      a.start += a.sweep;
      a.sweep = -a.sweep;
    }
  }
  return l;
}

Region2 translated(Region2 r, const Vec2& d) {
  const auto move = [&](Loop& l) {
    for (Piece& p : l.pieces) {
      if (auto* s = std::get_if<Segment>(&p)) {
        s->a += d;
        s->b += d;
      } else {
        auto& a = std::get<Arc>(p);
        a.center += d;
        a.source += d;
        a.target += d;
      }
    }
  };
  move(r.outer);
  for (Loop& h : r.holes) move(h);
  return r;
}

}  // namespace

TEST_CASE("valid tables pass validation") {
  CHECK_NOTHROW(validate(region(square(1))));
  CHECK_NOTHROW(validate(region(circle(1, {0, 0}, 1, true))));
  // The unit circle as two half circles: tangent joints, on the same circle.
  CHECK_NOTHROW(validate(region(loop(1, {arc({0, 0}, 1, 0, pi), arc({0, 0}, 1, pi, pi)}))));
  // And as three arcs, one of them a full turn minus the others.
  CHECK_NOTHROW(validate(
      region(loop(1, {arc({0, 0}, 1, 0.1, 0.2), arc({0, 0}, 1, 0.3, 0.4), arc({0, 0}, 1, 0.7, 2 * pi - 0.6)}))));
  CHECK_NOTHROW(validate(region(stadium(1, 1, 1))));
  CHECK_NOTHROW(validate(region(clover(1, 1, 2))));
  CHECK_NOTHROW(validate(region(cusped_triangle(1, 1))));
  // Sinai: a square with a disk hole.
  CHECK_NOTHROW(validate(region(square(1, 1), {circle(3, {0.5, 0.5}, 0.25)})));
  // Holes of several kinds: a stadium, a polygon, a circle.
  CHECK_NOTHROW(validate(region(square(1, 10), {reversed(stadium(10, 0.5, 0.25, {5, 5}, 0.3)),
                                                polygon(20, {{1, 1}, {1, 3}, {3, 1}}), circle(30, {8, 2}, 1)})));
}

TEST_CASE("tangent joints stay valid at any scale, offset and proportion") {
  for (double s : {1e-6, 1e-3, 1.0, 1e3, 1e6}) {
    CHECK_NOTHROW(validate(region(clover(1, s, 2 * s))));
    CHECK_NOTHROW(validate(region(stadium(1, s, s))));
    CHECK_NOTHROW(validate(translated(region(clover(1, s, 2 * s)), {1e3 * s, -7e2 * s})));
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 100; ++i) {
    const double r1 = std::exp(4 * u(rng) - 2), r2 = r1 * std::exp(6 * u(rng) - 3);
    INFO("clover r1 = " << r1 << ", r2 = " << r2);
    CHECK_NOTHROW(validate(region(clover(1, r1, r2))));
    const double a = std::exp(6 * u(rng) - 3), r = std::exp(6 * u(rng) - 3);
    INFO("stadium a = " << a << ", r = " << r);
    CHECK_NOTHROW(validate(region(stadium(1, a, r, {u(rng), u(rng)}, 2 * pi * u(rng)))));
    CHECK_NOTHROW(validate(region(cusped_triangle(1, r))));
    const double d = r * std::exp(-7 * u(rng)), e = r * std::exp(-7 * u(rng));
    INFO("oval r = " << r << ", d = " << d << ", e = " << e);
    CHECK_NOTHROW(validate(region(oval(1, r, d, e))));
  }
}

TEST_CASE("the bundled shape files are valid") {
  for (const char* name :
       {"annulus", "circle", "clover", "l-room", "mushroom", "sinai", "square", "stadium", "triangle", "wavy-1200"})
    CHECK_NOTHROW(load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml"));
}

TEST_CASE("crossing and touching pieces are named with their lines") {
  // A bow-tie: the segments at lines 3 and 5 cross.
  CHECK_THAT(
      error_of(region(polygon(2, {{0, 0}, {1, 1}, {1, 0}, {0, 1}}))),
      Catch::Equals("table.yaml:5: the segment at line 3 and the segment at line 5 cross or touch at (0.5, 0.5)"));
  // The right half of the unit disk, closed by a tangent segment, a segment that cuts back
  // through the arc at (0.8, 0.6) and one back to the start.
  CHECK_THAT(error_of(region(loop(2, {arc({0, 0}, 1, -pi / 2, pi), segment({0, 1}, {1, 1}), segment({1, 1}, {0.5, 0}),
                                      segment({0.5, 0}, {0, -1})}))),
             Catch::Equals("table.yaml:5: the arc at line 3 and the segment at line 5 cross or touch at (0.8, 0.6)"));
  // A figure eight: the loop passes twice through its corner (0, 0).
  CHECK_THAT(error_of(region(polygon(2, {{0, 0}, {1, -1}, {1, 1}, {0, 0}, {-1, 1}, {-1, -1}}))),
             Catch::Contains("cross or touch at (0, 0)"));
  // A corner on another piece.
  CHECK_THAT(error_of(region(polygon(2, {{0, 0}, {4, 0}, {4, 4}, {2, 0}, {0, 4}}))),
             Catch::Contains("the segment at line 3 and the segment at line 5 cross or touch at (2, 0)"));
  // A spike: the segment at line 4 runs back over the segment at line 3.
  CHECK_THAT(
      error_of(region(polygon(2, {{0, 0}, {2, 0}, {1, 0}, {1, 1}}))),
      Catch::Contains("table.yaml:4: the segment at line 3 and the segment at line 4 overlap from (1, 0) to (2, 0)"));
}

TEST_CASE("a crossing beside a joint is not mistaken for the joint") {
  // A quarter of the unit circle ending at J = (1, 0), then a segment from J through the point
  // Q of the arc 1e-6 before J: it crosses the arc at Q, 1e-6 from the joint.
  const double t = -1e-6;
  const Vec2 q(std::cos(t), std::sin(t)), far = 2 * q - Vec2(1, 0);
  const auto error = error_of(region(loop(2, {arc({0, 0}, 1, -pi / 2, pi / 2), segment({1, 0}, far),
                                              segment(far, {1.5, -1.5}), segment({1.5, -1.5}, {0, -1})})));
  CHECK_THAT(error, Catch::StartsWith(
                        "table.yaml:4: the arc at line 3 and the segment at line 4 cross or touch at (1, -1.0000"));
}

TEST_CASE("holes must lie strictly inside the outer boundary and apart") {
  CHECK_THAT(error_of(region(square(1), {circle(6, {9, 9}, 1)})),
             Catch::Equals("table.yaml:6: the hole is not inside the outer boundary"));
  CHECK_THAT(
      error_of(region(square(1), {circle(6, {4, 2}, 1)})),
      Catch::Contains("table.yaml:7: the hole at line 6 is not strictly inside the outer boundary: the segment at "
                      "line 3 and the circle at line 7 cross or touch at (4, 1)"));
  // Tangent to the bottom wall at (2, 0).
  CHECK_THAT(error_of(region(square(1), {circle(6, {2, 1}, 1)})),
             Catch::Contains("the segment at line 2 and the circle at line 7 cross or touch at (2, 0)"));
  // A corner of a triangular hole on a corner of the outer boundary.
  CHECK_THAT(
      error_of(region(polygon(1, {{0, 0}, {4, 0}, {4, 2}, {4, 4}, {0, 4}}), {polygon(7, {{4, 2}, {3, 1}, {3, 3}})})),
      Catch::Contains("the hole at line 7 is not strictly inside the outer boundary"));
  // Two disks that overlap, two that touch at (2, 2).
  CHECK_THAT(
      error_of(region(square(1), {circle(6, {1.5, 2}, 1), circle(8, {2.5, 2}, 1)})),
      Catch::Contains("table.yaml:9: the holes at lines 6 and 8 overlap or touch: the circle at line 7 and the circle "
                      "at line 9 cross or touch at (2, "));
  CHECK_THAT(
      error_of(region(square(1), {circle(6, {1.5, 2}, 0.5), circle(8, {2.5, 2}, 0.5)})),
      Catch::Contains("the holes at lines 6 and 8 overlap or touch: the circle at line 7 and the circle at line 9 "
                      "cross or touch at (2, 2)"));
  CHECK_THAT(error_of(region(square(1), {circle(6, {2, 2}, 1.5), circle(8, {2, 2}, 0.5)})),
             Catch::Equals("table.yaml:8: the hole lies inside the hole at line 6"));
}

TEST_CASE("orientation: outer boundary counter-clockwise, holes clockwise") {
  CHECK_THAT(error_of(region(polygon(2, {{0, 0}, {0, 1}, {1, 1}, {1, 0}}))),
             Catch::Equals("table.yaml:2: the outer boundary runs clockwise: list its pieces counter-clockwise (region "
                           "on the left)"));
  CHECK_THAT(error_of(region(circle(2, {0, 0}, 1, false))),
             Catch::StartsWith("table.yaml:2: the outer boundary runs clockwise"));
  CHECK_THAT(error_of(region(reversed(clover(2, 1, 2)))),
             Catch::StartsWith("table.yaml:2: the outer boundary runs clockwise"));
  CHECK_THAT(error_of(region(square(1, 10), {stadium(6, 0.5, 0.25, {5, 5}, 0.3)})),
             Catch::StartsWith("table.yaml:6: the hole runs counter-clockwise"));
  CHECK_THAT(
      error_of(region(square(1), {polygon(6, {{1, 1}, {2, 1}, {2, 2}})})),
      Catch::Equals("table.yaml:6: the hole runs counter-clockwise: list its pieces clockwise (region on the left)"));
  CHECK_THAT(error_of(region(square(1), {circle(6, {2, 2}, 1, true)})),
             Catch::StartsWith("table.yaml:6: the hole runs counter-clockwise"));
}

TEST_CASE("loops must be closed chains of pieces of positive length") {
  CHECK_THAT(error_of(region(polygon(2, {{0, 0}, {1, 0}, {1, 0}, {0, 1}}))),
             Catch::Equals("table.yaml:4: zero-length segment: it must have a positive length"));
  Loop zero_arc =
      loop(2, {segment({0, 0}, {1, 0}), arc({1, 0}, 1, pi, 0), segment({0, 0}, {0, 1}), segment({0, 1}, {0, 0})});
  CHECK_THAT(error_of(region(zero_arc)),
             Catch::Equals("table.yaml:4: zero-length arc: it must have a positive length"));
  Loop open = square(2);
  std::get<Segment>(open.pieces[1]).b = {4, 4.5};
  CHECK_THAT(
      error_of(region(open)),
      Catch::Equals("table.yaml:4: the loop is not closed: this segment ends at (4, 4.5) but the segment at line 5 "
                    "begins at (4, 4)"));
  // A joint off by 1e-300 is still a gap: joints must be shared bit for bit.
  Loop nearly = square(2);
  std::get<Segment>(nearly.pieces[3]).b.x() = 1e-300;
  CHECK_THAT(error_of(region(nearly)), Catch::StartsWith("table.yaml:6: the loop is not closed"));
  CHECK_THAT(error_of(region(loop(2, {arc({0, 0}, 1, 0, 2 * pi), segment({1, 0}, {2, 0}), segment({2, 0}, {1, 0})}))),
             Catch::Equals("table.yaml:3: a full circle must be a loop by itself"));
  CHECK_THAT(error_of(region(Loop{{}, {}, {file, 2}})),
             Catch::Equals("table.yaml:2: the outer boundary has no pieces"));
}

TEST_CASE("arcs must be consistent and finite") {
  Loop bad = loop(2, {arc({0, 0}, 1, 0, pi), arc({0, 0}, 1, pi, pi)});
  std::get<Arc>(bad.pieces[0]).radius = 1.001;
  CHECK_THAT(
      error_of(region(bad)),
      Catch::Equals("table.yaml:3: the arc's ends are not the points of its circle at its start and end angles"));
  std::get<Arc>(bad.pieces[0]).radius = -1;
  CHECK_THAT(error_of(region(bad)), Catch::Equals("table.yaml:3: the arc's radius must be positive"));
  std::get<Arc>(bad.pieces[0]).radius = NAN;
  CHECK_THAT(error_of(region(bad)),
             Catch::Equals("table.yaml:3: the arc has a coordinate that is not a finite number"));
  Loop big = circle(2, {0, 0}, 1, true);
  std::get<Arc>(big.pieces[0]).sweep = 7;
  CHECK_THAT(error_of(region(big)), Catch::Equals("table.yaml:3: the arc sweeps more than a full turn"));
}

TEST_CASE("validation errors through shape files name the file and line") {
  const auto error = [](const std::string& yaml) {
    try {
      parse_shape(yaml, "bad.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // A hole whose corner sits on a corner of the outer boundary.
  CHECK_THAT(error("boundary:\n  pieces:\n    - point: [0, 0]\n    - point: [4, 0]\n    - point: [4, 2]\n"
                   "    - point: [4, 4]\n    - point: [0, 4]\nholes:\n  - pieces:\n    - point: [4, 2]\n"
                   "    - point: [3, 1]\n    - point: [3, 3]\n"),
             Catch::Contains("the hole at line 9 is not strictly inside the outer boundary: the segment at line 4 and "
                             "the segment at line 10 cross or touch at (4, 2)"));
  // A figure eight.
  CHECK_THAT(error("boundary:\n  polygon:\n    - [0, 0]\n    - [1, -1]\n    - [1, 1]\n    - [0, 0]\n    - [-1, 1]\n"
                   "    - [-1, -1]\n"),
             Catch::Contains("cross or touch at (0, 0)"));
}
