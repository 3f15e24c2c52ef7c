// A scene's particles at uniform times 0, Δt, ..., T: the frames of an animation.  Each particle
// is followed (follow.hpp) and sampled by its flight's own `advance`, so the frames show driven
// and field flights on their true curved paths.  The same scene and seed give the same frames
// as `billiard animate` and billiardkit.animate, for any number of threads.
#pragma once

#include "billiards/dynamics/scene.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace billiards::dynamics {

struct SceneFrames {
  std::size_t particles = 0;
  int dimension = 2;
  std::vector<double> times;      // K frame times, times[k] = k T/(K − 1)
  std::vector<double> positions;  // K × particles × dimension, NaN once a particle has escaped
  std::vector<double> energies;   // K × particles (½mv², plus U(x) in a potential), NaN likewise
  std::vector<std::uint8_t> escaped;  // per particle
  double position(std::size_t k, std::size_t i, int j) const { return positions[(k * particles + i) * dimension + j]; }
};

/// Room for the first `particles` particles of the scene at `frames` ≥ 2 uniform times from 0 to
/// `time`, every entry NaN until fill_frames computes it.
SceneFrames empty_frames(const Scene& scene, std::size_t particles, std::size_t frames, double time);

/// Computes particles [first, last) of `frames` (their initial states are those of `billiard
/// run` with the scene's seed), on `threads` OpenMP threads.
void fill_frames(const Scene& scene, SceneFrames& frames, std::size_t first, std::size_t last, int threads);

}  // namespace billiards::dynamics
