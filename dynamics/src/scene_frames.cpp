#include "billiards/dynamics/scene_frames.hpp"

#include "billiards/dynamics/first_error.hpp"
#include "billiards/dynamics/follow.hpp"
#include "billiards/dynamics/scene_run.hpp"

#include <cmath>
#include <stdexcept>

namespace billiards::dynamics {

SceneFrames empty_frames(const Scene& scene, std::size_t particles, std::size_t frames, double time) {
  if (frames < 2) throw std::invalid_argument("an animation needs at least 2 frames");
  if (!(time > 0)) throw std::invalid_argument("an animation needs a positive time");
  SceneFrames f;
  f.particles = particles;
  f.dimension = scene.dimension();
  const SampleClock clock{0, time / double(frames - 1)};
  for (std::size_t k = 0; k < frames; ++k) f.times.push_back(clock.time(k));
  f.positions.assign(frames * particles * std::size_t(f.dimension), std::nan(""));
  f.energies.assign(frames * particles, std::nan(""));
  f.escaped.assign(particles, 0);
  return f;
}

namespace {

/// Particle i's frames: its state at each frame time, until the last or an escape.
template <class Flight>
void follow_particle(const Scene& scene, const TableFor<Flight>& table, const Flight& flight,
                     const typename Flight::State& s, SceneFrames& f, std::size_t i) {
  const std::size_t frames = f.times.size();
  const SampleClock clock{0, f.times[1]};
  const FollowLimits limits{.t_end = clock.time(frames - 1)};
  std::size_t k = 0;
  const auto sample = [&](const auto& state) {
    for (int j = 0; j < f.dimension; ++j) f.positions[(k * f.particles + i) * f.dimension + j] = state.x[j];
    f.energies[k * f.particles + i] = energy_of(flight, state, scene.mass);
    ++k;
  };
  const auto result = follow(table, flight, s, limits, clock, [](const auto&, const auto&) {}, sample);
  f.escaped[i] = result.escaped || k < frames;
}

}  // namespace

void fill_frames(const Scene& scene, SceneFrames& f, std::size_t first, std::size_t last, int threads) {
  with_flight(scene, [&](const auto& flight) {
    using Flight = std::decay_t<decltype(flight)>;
    const auto table = table_of<Flight>(scene);
    const auto initial = initial_states(scene, table, flight);
    FirstError error;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (std::ptrdiff_t i = std::ptrdiff_t(first); i < std::ptrdiff_t(last); ++i)
      error.run(std::size_t(i), [&] { follow_particle(scene, table, flight, initial(std::size_t(i)), f, std::size_t(i)); });
    error.rethrow();
  });
}

}  // namespace billiards::dynamics
