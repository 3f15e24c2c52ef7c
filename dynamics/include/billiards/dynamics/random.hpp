// One random stream per particle: particle i of a run with seed s draws from a generator
// seeded by SplitMix64(s, i), so its initial condition depends on (s, i) only and never on
// the thread that happens to run it.
#pragma once

#include "billiards/dynamics/state.hpp"

#include <cstdint>
#include <functional>
#include <random>

namespace billiards::dynamics {

template <class Real>
class BasicTable;
using Table = BasicTable<double>;

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// The generator of particle `index` in a run seeded with `seed`.
class ParticleRng {
 public:
  ParticleRng(std::uint64_t seed, std::uint64_t index)
      : engine_(splitmix64(splitmix64(seed) ^ splitmix64(~index))) {}
  /// Uniform in [0, 1) with 53 random bits (portable, unlike std::uniform_real_distribution).
  double uniform() { return double(engine_() >> 11) * 0x1.0p-53; }

 private:
  std::mt19937_64 engine_;
};

/// Microcanonical sample for a standard billiard: position uniform in the region (rejection
/// from the bounding box), velocity isotropic with the given speed.
State sample_microcanonical(const Table& table, double speed, ParticleRng& rng);

/// Microcanonical sample at energy E in a potential U: position uniform over the allowed part
/// {U(x) < E} of the region (the 2-D microcanonical density is uniform there), velocity
/// isotropic with |v| = √(2(E − U(x))/m).
State sample_microcanonical(const Table& table, double energy, double mass,
                            const std::function<double(const Vec2&)>& potential, ParticleRng& rng);

}  // namespace billiards::dynamics
