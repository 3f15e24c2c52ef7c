// Tables of more walls than the bundled shapes have, built where a test needs them
// (test_lanes.cpp, test_lockstep.cpp, test_forced_flight.cpp).
#pragma once

#include "billiards/dynamics/table.hpp"
#include "billiards/geometry.hpp"

#include <cmath>
#include <string>

/// A regular n-gon inscribed in the unit circle, as a shape file's polygon.
inline std::string polygon_yaml(int n, double r_odd = 1) {
  std::string text = "boundary:\n  polygon: [";
  for (int k = 0; k < n; ++k) {
    const double r = k % 2 ? r_odd : 1, a = 2 * billiards::geometry::pi * k / n;
    text += (k ? ", [" : "[") + std::to_string(r * std::cos(a)) + ", " + std::to_string(r * std::sin(a)) + "]";
  }
  return text + "]\n";
}

/// A 20-gon with three circular holes: 20 segments and 3 arcs.
inline billiards::dynamics::Table twenty_gon() {
  const std::string text = polygon_yaml(20) + R"(holes:
  - circle: {center: [0.3, 0], radius: 0.15}
  - circle: {center: [-0.3, 0.3], radius: 0.1}
  - circle: {center: [-0.2, -0.4], radius: 0.2}
)";
  return billiards::dynamics::Table(billiards::geometry::parse_shape("name: twenty-gon\n" + text, "twenty-gon").region);
}

/// A gear: the polygon of 2·teeth vertices on radii 1 and 3/4 in turn, around a disk of radius
/// 0.3 if `hole` (2·teeth segments, and an arc).
inline billiards::dynamics::Table gear(int teeth, bool hole) {
  std::string text = "name: gear\n" + polygon_yaml(2 * teeth, 0.75);
  if (hole) text += "holes:\n  - circle: {center: [0, 0], radius: 0.3}\n";
  return billiards::dynamics::Table(billiards::geometry::parse_shape(text, "gear").region);
}

/// A circle cut into n arcs.
inline billiards::dynamics::Table circle_of_arcs(int n) {
  using billiards::geometry::pi;
  billiards::geometry::Region2 circle;
  for (int k = 0; k < n; ++k) {
    billiards::geometry::Arc arc{billiards::geometry::Vec2(0, 0), 1, 2 * pi * k / n, 2 * pi / n, {}, {}};
    arc.source = arc.point_at(arc.start);
    arc.target = arc.point_at(arc.start + arc.sweep);
    circle.outer.pieces.push_back(arc);
    circle.outer.where.emplace_back();
  }
  return billiards::dynamics::Table(circle);
}
