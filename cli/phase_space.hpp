// What the phase-space commands (bmap, lyapunov, chaos) share: a table given as a shape file
// (free flights at speed 1) or a scene file (its force, energy and seed), its particles, and
// the flight the scene needs.
#pragma once

#include "options.hpp"

#include "billiards/analysis/lyapunov.hpp"
#include "billiards/dynamics/scene.hpp"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace billiards::cli {

struct PhaseSpaceArgs {
  std::string source;  // SHAPE or SCENE
  std::size_t particles = 0, collisions = 0;
  std::optional<std::uint64_t> seed;
  int threads = 0;
  bool quiet = false;
  std::vector<std::string> set;
};

/// A scene file names its shape (`shape:`); anything else is read as a shape file, whose reader
/// reports what is wrong with it.
bool is_scene_file(const std::string& path);

/// SHAPE|SCENE, --particles, --collisions, --seed, --threads, --quiet, --set.
void add_phase_space_options(CLI::App* cmd, PhaseSpaceArgs& args, std::size_t particles, std::size_t collisions);

/// The scene of a scene file, or a shape file as a free scene (energy ½, mass 1: speed 1);
/// with the command line's particles and seed; 2-D or 3-D.
dynamics::Scene load_phase_space_scene(const PhaseSpaceArgs& args);
/// Refuses a magnetic field with a force: such a flight's collision search needs a time horizon
/// (an orbit may circle forever), and `command` follows particles collision by collision.
void refuse_forced_magnetic(const dynamics::Scene& scene, const std::string& command);

/// The short chaos check that `coeffs` and `compare` state beside their prediction (chaos.cpp):
/// `billiard chaos --json`'s keys for 8 orbits x 20000 collisions, and "reason".
nlohmann::json ergodicity_check(const geometry::Region2& region);
/// One line: the verdict, or a plain warning that the prediction's assumption fails.
void print_ergodicity(const nlohmann::json& check);

}  // namespace billiards::cli
