#include "billiards/dynamics/ensemble.hpp"

#include "billiards/dynamics/table.hpp"

namespace billiards::dynamics {

std::uint64_t EnsembleResult::collisions() const {
  std::uint64_t n = 0;
  for (const auto& l : logs) n += l.collisions;
  return n;
}

std::uint64_t EnsembleResult::escapes() const {
  std::uint64_t n = 0;
  for (const auto& l : logs) n += l.escaped;
  return n;
}

State sample_microcanonical(const Table& table, double speed, ParticleRng& rng) {
  State s;
  const Vec2 lo = table.lo(), size = table.hi() - table.lo();
  do {
    s.x = lo + Vec2(rng.uniform() * size.x(), rng.uniform() * size.y());
  } while (!table.contains(s.x));
  const double angle = 2 * geometry::pi * rng.uniform();
  s.v = speed * Vec2(std::cos(angle), std::sin(angle));
  return s;
}

}  // namespace billiards::dynamics
