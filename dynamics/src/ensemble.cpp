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

std::vector<double> EnsembleResult::energies_at(std::size_t k, std::size_t m) const {
  std::vector<double> E;
  for (std::size_t i = 0; i < logs.size(); ++i)
    if (!logs[i].escaped) E.push_back(energies[i * m + k]);
  return E;
}

std::vector<double> EnsembleResult::energy_changes(std::size_t k, std::size_t m) const {
  std::vector<double> dE;
  for (std::size_t i = 0; i < logs.size(); ++i)
    if (!logs[i].escaped) dE.push_back(energies[i * m + k] - energies[i * m]);
  return dE;
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
