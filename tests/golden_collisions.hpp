// Collision sequences along trajectories in every bundled table, free and forced, written as
// rows (case, particle, collision, wall, t, x, y, z).  tests/golden/collisions.csv holds the
// rows as recorded before the wall-and-flight core was rebuilt (record_golden writes them);
// test_golden_collisions runs the same trajectories with the code as it is and compares.
#pragma once

#include "billiards/dynamics/scene_run.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace golden {

struct Row {
  std::string label;
  int particle = 0, k = 0;
  long wall = -1;  // 2-D: the wall's line in the shape file; 3-D: Table3::piece_of
  double t = 0, x = 0, y = 0, z = 0;
};

struct Case {
  std::string label;  // shape file and flight, e.g. "clover.yaml periodic 10pi"
  std::string scene;  // scene text (shape path relative to the source tree)
  int particles, collisions;
};

inline std::vector<Case> cases() {
  const std::vector<std::string> shapes2 = {"annulus", "circle", "clover", "l-room", "mushroom",
                                            "sinai", "square", "stadium", "triangle", "wavy-1200"};
  const std::vector<std::string> shapes3 = {"3d/ball", "3d/cube", "3d/l-prism", "3d/octahedron", "3d/sinai3",
                                            "3d/bumpy-100k"};
  struct Force {
    std::string name, yaml2, yaml3;
  };
  const std::vector<Force> forces = {
      {"free", "", ""},
      {"periodic 10pi", "force: {periodic: {amplitude: [3, 2], omega: 10*pi, phase: 0.3}}",
       "force: {periodic: {amplitude: [3, 2, 1], omega: 10*pi, phase: 0.3}}"},
      {"periodic 320pi", "force: {periodic: {amplitude: [30, -20], omega: 320*pi, phase: 0}}",
       "force: {periodic: {amplitude: [30, -20, 10], omega: 320*pi, phase: 0}}"},
      {"constant", "force: {constant: {amplitude: [0.3, -1]}}", ""},
      {"quivering 40pi",
       "force: {periodic: {amplitude: [5, 5], omega: 40*pi, phase: 0, picture: quivering-walls}}", ""},
  };
  std::vector<Case> out;
  for (int dim : {2, 3})
    for (const auto& shape : dim == 2 ? shapes2 : shapes3)
      for (const auto& f : forces) {
        const std::string& force = dim == 2 ? f.yaml2 : f.yaml3;
        if (f.name != "free" && force.empty()) continue;
        const std::string scene = "shape: " + std::string(BILLIARDS_SOURCE_DIR) + "/shapes/" + shape +
                                  ".yaml\ninitial: {microcanonical: {energy: 1/2}}\n" + force +
                                  "\nrun: {particles: 4, time: 1, seed: 7}\n";
        out.push_back({shape + " " + f.name, scene, shape == "3d/bumpy-100k" ? 2 : 4, 25});
      }
  out.push_back({"clover-field", "file:" + std::string(BILLIARDS_SOURCE_DIR) + "/scenes/clover-field.yaml", 3, 15});
  return out;
}

/// The case's scene.
inline billiards::dynamics::Scene scene_of(const Case& c) {
  using namespace billiards::dynamics;
  if (c.scene.rfind("file:", 0) == 0) return load_scene(c.scene.substr(5));
  return parse_scene(c.scene, c.label, ".");
}

struct Run {
  std::vector<Row> rows;
  double size = 0;  // the table's size: the largest extent of its bounding box
};

/// The case's rows.  `perturbed` displaces every initial position and turns every initial
/// velocity by the flight's own accuracy: 1e-15 (of the table's size; radians) for the closed
/// forms, the integrator's tolerance for integrated flights, whose adaptive steps turn any
/// rounding difference into one of that size.
inline Run run(const Case& c, bool perturbed = false) {
  using namespace billiards::dynamics;
  const Scene scene = scene_of(c);
  Run out;
  auto& rows = out.rows;
  with_flight(scene, [&](const auto& flight) {
    using Flight = std::decay_t<decltype(flight)>;
    const auto table = table_of<Flight>(scene);
    const auto initial = initial_states(scene, table, flight);
    const double size = out.size = (table.hi() - table.lo()).maxCoeff();
    const double horizon = is_straight<Flight> ? never : 1e3;
    const double shift = !perturbed ? 0 : std::is_same_v<Flight, FieldFlight> ? scene.integrator_tolerance : 1e-15;
    for (int i = 0; i < c.particles; ++i) {
      auto s = initial(std::size_t(i));
      if (perturbed) {
        s.x.array() += shift * size / std::sqrt(double(s.x.size()));
        const double v0 = s.v[0], v1 = s.v[1];
        s.v[0] -= shift * v1;
        s.v[1] += shift * v0;
        s = flight.start(s);
      }
      const auto v2 = s.v.squaredNorm();
      for (int k = 0; k < c.collisions; ++k) {
        const auto hit = collision(table, flight, s, horizon);
        if (!hit.found()) break;
        bounce(flight, s, hit);
        if constexpr (Flight::conserves_energy) restore_speed(s.v, v2);
        Row r{c.label, i, k, -1, hit.t, hit.point[0], hit.point[1], 0};
        if constexpr (is_3d<Flight>) {
          r.wall = table.piece_of(hit.wall);
          r.z = hit.point[2];
        } else {
          r.wall = table.source_of(hit.wall).line;
        }
        rows.push_back(r);
      }
    }
  });
  return out;
}

}  // namespace golden
