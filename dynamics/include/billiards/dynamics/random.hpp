// One random stream per particle: particle i of a run with seed s draws from a generator
// seeded by SplitMix64(s, i), so its initial condition depends on (s, i) only and never on
// the thread that happens to run it.
#pragma once

#include "billiards/dynamics/state.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <random>

namespace billiards::dynamics {

using Table = BasicTable<double>;

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// std::mt19937_64 seeded with one integer, its first outputs computed on demand.  A particle
/// draws a handful of numbers (its position and direction), while the standard engine fills
/// 312 words of state at seeding and regenerates all 312 at the first draw — ~7 700
/// instructions, a fifth of a particle's cost in a run like the paper's Fig. 4.  Output k < 156
/// depends only on the seeded words k, k + 1 and k + 156, so those are computed as far as
/// needed; from output 156 on, the standard engine takes over, seeded and advanced to the same
/// place.  The sequence is the standard engine's, word for word (tested).
class LazyMt19937_64 {
 public:
  using result_type = std::uint64_t;
  explicit LazyMt19937_64(result_type seed) : seed_(seed) { words_[0] = seed; }
  result_type operator()() {
    if (engine_) return (*engine_)();
    if (drawn_ == m) {
      engine_.emplace(seed_);
      engine_->discard(m);
      return (*engine_)();
    }
    const std::size_t k = drawn_++;
    seed_words(k + m);
    constexpr result_type upper = ~result_type(0) << 31, lower = ~upper;
    const result_type y = (words_[k] & upper) | (words_[k + 1] & lower);
    result_type z = words_[k + m] ^ (y >> 1) ^ (y & 1 ? 0xb5026f5aa96619e9ULL : 0);
    z ^= (z >> 29) & 0x5555555555555555ULL;
    z ^= (z << 17) & 0x71d67fffeda60000ULL;
    z ^= (z << 37) & 0xfff7eee000000000ULL;
    return z ^ (z >> 43);
  }

 private:
  static constexpr std::size_t n = 312, m = 156;  // mt19937_64's state size and shift
  /// The seeding recurrence of std::mersenne_twister_engine, up to word j.
  void seed_words(std::size_t j) {
    for (; seeded_ <= j; ++seeded_)
      words_[seeded_] = 6364136223846793005ULL * (words_[seeded_ - 1] ^ (words_[seeded_ - 1] >> 62)) + seeded_;
  }
  result_type seed_;
  result_type words_[n];
  std::size_t seeded_ = 1, drawn_ = 0;
  std::optional<std::mt19937_64> engine_;
};

/// The generator of particle `index` in a run seeded with `seed`.
class ParticleRng {
 public:
  ParticleRng(std::uint64_t seed, std::uint64_t index)
      : engine_(splitmix64(splitmix64(seed) ^ splitmix64(~index))) {}
  /// Uniform in [0, 1) with 53 random bits (portable, unlike std::uniform_real_distribution).
  double uniform() { return double(engine_() >> 11) * 0x1.0p-53; }

 private:
  LazyMt19937_64 engine_;
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
