// Shape-file errors found by the loader: each names the file and the line.
#include "billiards/geometry.hpp"

#include <catch2/catch.hpp>

using namespace billiards;

namespace {

std::string error_of(const std::string& yaml, const Overrides& set = {}) {
  try {
    geometry::parse_shape(yaml, "bad.yaml", set);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("loader errors name file, line and problem") {
  CHECK_THAT(error_of("boundary:\n  polygon: [[0,0],[1,0],[1,1]]\ncolour: red\n"),
             Catch::Contains("bad.yaml:3: unknown key 'colour'"));
  CHECK_THAT(error_of("boundary:\n  circle: {center: [0, 0], radius: 2*}\n"),
             Catch::Contains("bad.yaml:2: bad expression '2*'"));
  CHECK_THAT(error_of("boundary:\n  circle: {center: [0, 0], radius: -1}\n"),
             Catch::Contains("bad.yaml:2: radius must be positive"));
  CHECK_THAT(error_of("boundary:\n  polygon: [[0,0],[1,0],[1,0],[0,1]]\n"),
             Catch::Contains("zero-length segment"));
  CHECK_THAT(error_of("boundary:\n  pieces:\n    - arc: {center: [0, 0], radius: 1, side: inside}\n"
                      "    - arc: {center: [5, 0], radius: 1, side: inside}\n"),
             Catch::Contains("bad.yaml:4: the arcs at lines 3 and 4 do not meet"));
  CHECK_THAT(error_of("boundary:\n  pieces:\n    - point: [0, 0]\n    - point: [1, 0]\n"
                      "    - arc: {center: [0, 0], radius: 1, side: inside}\n    - point: [0, 2]\n"),
             Catch::Contains("bad.yaml:6: point is not on the circle of the arc at line 5"));
  CHECK_THAT(error_of("boundary:\n  pieces:\n    - arc: {center: [0, 0], radius: 1, side: inside}\n"
                      "    - arc: {center: [1, 0], radius: 1, side: outside}\n"),
             Catch::Contains("cross at two points: put '- point: {near: [x, y]}'"));
  CHECK_THAT(error_of("boundary:\n  pieces:\n    - arc: {center: [0, 0], radius: 1, side: middle}\n"),
             Catch::Contains("bad.yaml:3: side must be 'inside'"));
  CHECK_THAT(error_of("parameters:\n  R: 1\nboundary:\n  circle: {center: [0, 0], radius: R}\n", {{"Q", "2"}}),
             Catch::Contains("--set names 'Q', which is not a parameter"));
  CHECK_THAT(error_of("parameters:\n  R: 1\n  R: 2\nboundary:\n  circle: {center: [0, 0], radius: R}\n"),
             Catch::Contains("bad.yaml"));
  CHECK_THAT(error_of("boundary: [1, 2\n"), Catch::Contains("bad.yaml:2: not valid YAML"));
  CHECK_THAT(error_of("holes:\n  - circle: {center: [0, 0], radius: 1}\n"),
             Catch::Contains("bad.yaml:1: a shape file needs 'boundary'"));
  CHECK_THAT(error_of("dimension: 4\nboundary:\n  circle: {center: [0, 0], radius: 1}\n"),
             Catch::Contains("bad.yaml:1: 'dimension' is 2 (the default) or 3"));
  // A mapping where the name should be (a fuzz finding: its conversion threw).
  CHECK_THAT(error_of("name:\n  a: 1\nboundary:\n  circle: {center: [0, 0], radius: 1}\n"),
             Catch::Contains("bad.yaml:2: 'name' is a single word or phrase"));
  // A tagged mapping where the dimension should be (a fuzz finding: its conversion threw).
  CHECK_THAT(error_of("dimension: !=parameters:\n  R: 1\nboundary:\n  circle: {center: [0, 0], radius: 1}\n"),
             Catch::Contains("bad.yaml:1: 'dimension' is 2 (the default) or 3"));
}

TEST_CASE("a 'near' point picks one of two circle intersections") {
  // The lens between two unit circles centred at (±0.5, 0): region inside both.
  const auto shape = geometry::parse_shape(
      "boundary:\n  pieces:\n    - arc: {center: [-0.5, 0], radius: 1, side: inside}\n"
      "    - point: {near: [0, 1]}\n    - arc: {center: [0.5, 0], radius: 1, side: inside}\n"
      "    - point: {near: [0, -1]}\n",
      "lens.yaml");
  const auto m = geometry::measures_of(shape.region);
  // Lens of two unit circles at distance d = 1: 2 acos(d/2) − (d/2) sqrt(4 − d²).
  CHECK(std::abs(m.volume - (2 * std::acos(0.5) - 0.5 * std::sqrt(3.0))) < 1e-14);
  CHECK(std::abs(m.surface - 2 * (2 * std::acos(0.5))) < 1e-14);
}

TEST_CASE("CGAL validation errors name the pieces and lines involved") {
  const std::string square = "boundary:\n  polygon: [[0,0],[4,0],[4,4],[0,4]]\n";
  // A bow-tie: the segments from lines 2 and 4 cross.
  CHECK_THAT(error_of("boundary:\n  pieces:\n    - point: [0, 0]\n    - point: [1, 1]\n    - point: [1, 0]\n"
                      "    - point: [0, 1]\n"),
             Catch::Contains("cross or touch at (0.5, 0.5)"));
  // A half disk on the right of x = 1, and a segment from its top cutting back through it.
  CHECK_THAT(error_of("boundary:\n  pieces:\n    - point: [0, -1]\n    - point: [1, -1]\n"
                      "    - arc: {center: [1, 0], radius: 1, side: inside}\n    - point: [1, 1]\n"
                      "    - point: [2.5, 0]\n"),
             Catch::Contains("the arc at line 5 and the segment at line 6 cross or touch"));
  CHECK_THAT(error_of(square + "holes:\n  - circle: {center: [9, 9], radius: 1}\n"),
             Catch::Contains("bad.yaml:4: the hole is not inside the outer boundary"));
  CHECK_THAT(error_of(square + "holes:\n  - circle: {center: [4, 2], radius: 1}\n"),
             Catch::Contains("a hole must lie strictly inside"));
  CHECK_THAT(error_of(square + "holes:\n  - circle: {center: [1.5, 2], radius: 1}\n  - circle: {center: [2.5, 2], radius: 1}\n"),
             Catch::Contains("a hole must lie strictly inside"));
  CHECK_THAT(error_of(square + "holes:\n  - circle: {center: [2, 2], radius: 1.5}\n  - circle: {center: [2, 2], radius: 0.5}\n"),
             Catch::Contains("the hole lies inside the hole at line 4"));
  // Tangent to the outer wall: a touch is not allowed either.
  CHECK_THAT(error_of(square + "holes:\n  - circle: {center: [2, 1], radius: 1}\n"),
             Catch::Contains("a hole must lie strictly inside"));
  CHECK_THAT(error_of("boundary:\n  pieces:\n    - point: [0, 0]\n    - point: [0, 1]\n    - point: [1, 1]\n"
                      "    - point: [1, 0]\n"),
             Catch::Contains("bad.yaml:2: the outer boundary runs clockwise"));
  CHECK_THAT(error_of(square + "holes:\n  - pieces:\n    - point: [1, 1]\n    - point: [2, 1]\n    - point: [2, 2]\n"),
             Catch::Contains("bad.yaml:4: the hole runs counter-clockwise"));
}

TEST_CASE("valid tables with tangent joints and holes pass validation") {
  for (const char* name : {"clover", "stadium", "sinai", "mushroom", "annulus", "wavy-1200"})
    CHECK_NOTHROW(geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml"));
  // Scaled by 1e-6 and 1e6, the clover is still valid.
  for (const char* s : {"1e-6", "1e6"})
    CHECK_NOTHROW(geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml",
                                       {{"R1", s}, {"R2", std::string("2*") + s}}));
}
