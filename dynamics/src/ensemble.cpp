#include "billiards/dynamics/ensemble.hpp"

#include "billiards/dynamics/table.hpp"

#include <stdexcept>

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

namespace {

/// A point uniform over the part of the region where `allowed` holds (rejection from the
/// bounding box).
template <class Allowed>
Vec2 uniform_point(const Table& table, ParticleRng& rng, Allowed allowed) {
  const Vec2 lo = table.lo(), size = table.hi() - table.lo();
  for (long tries = 0; tries < 100000000; ++tries) {
    // The draws in a fixed order, y before x (the order of every run so far): the order in
    // which a constructor's arguments are evaluated is the compiler's choice (GCC on x86-64
    // right to left, on aarch64 and clang left to right).
    const double uy = rng.uniform(), ux = rng.uniform();
    const Vec2 x = lo + Vec2(ux * size.x(), uy * size.y());
    if (table.contains(x) && allowed(x)) return x;
  }
  throw std::runtime_error("no allowed point found in the region after 1e8 samples");
}

Vec2 isotropic(double speed, ParticleRng& rng) {
  const double angle = 2 * geometry::pi * rng.uniform();
  return speed * Vec2(std::cos(angle), std::sin(angle));
}

}  // namespace

State sample_microcanonical(const Table& table, double speed, ParticleRng& rng) {
  State s;
  s.x = uniform_point(table, rng, [](const Vec2&) { return true; });
  s.v = isotropic(speed, rng);
  return s;
}

State sample_microcanonical(const Table& table, double energy, double mass,
                            const std::function<double(const Vec2&)>& potential, ParticleRng& rng) {
  State s;
  s.x = uniform_point(table, rng, [&](const Vec2& x) { return potential(x) < energy; });
  s.v = isotropic(std::sqrt(2 * (energy - potential(s.x)) / mass), rng);
  return s;
}

}  // namespace billiards::dynamics
