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
             Catch::Contains("bad.yaml:1: only dimension 2"));
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
