// What the phase-space tests (boundary map, Lyapunov exponents) share: bundled shapes and
// scenes by name.
#pragma once

#include "billiards/dynamics/scene.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <string>

inline billiards::geometry::Shape bundled_shape(const std::string& name) {
  return billiards::geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + name);
}

/// A bundled scene with `particles` particles.
inline billiards::dynamics::Scene bundled_scene(const std::string& name, std::size_t particles) {
  billiards::dynamics::SceneOverrides o;
  o.particles = particles;
  return billiards::dynamics::load_scene(BILLIARDS_SOURCE_DIR "/scenes/" + name, o);
}
