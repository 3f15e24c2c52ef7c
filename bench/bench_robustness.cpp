// Robustness at scale: escapes over N collisions per bundled shape with every flight's
// midpoint checked by the independent point-in-region test, and the energy drift of free
// flights over 1e8 collisions.
// Usage: bench_robustness [collisions per shape, default 1e7] [collisions for drift, default 1e8]
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/geometry.hpp"

#include <fmt/core.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>

using namespace billiards;

int main(int argc, char** argv) {
  const double per_shape = argc > 1 ? std::atof(argv[1]) : 1e7;
  const double drift_collisions = argc > 2 ? std::atof(argv[2]) : 1e8;
  std::vector<std::string> shapes;
  for (const auto& e : std::filesystem::directory_iterator(BILLIARDS_SOURCE_DIR "/shapes"))
    if (e.path().extension() == ".yaml") shapes.push_back(e.path().string());
  std::sort(shapes.begin(), shapes.end());
  std::uint64_t total = 0, escapes = 0;
  fmt::print("{:<12} {:>12} {:>8} {:>16}\n", "shape", "collisions", "escapes", "max |dE|/E");
  for (const auto& path : shapes) {
    const auto shape = geometry::load_shape(path);
    const dynamics::Table table(shape.region);
    const double lambda = geometry::mean_free_path(geometry::measures_of(shape.region));
    const std::size_t particles = 1000;
    dynamics::RunOptions opt;
    opt.record_times = {per_shape / double(particles) * lambda};
    opt.verify_every_flight = true;
    const dynamics::FreeFlight flight;
    const auto res = dynamics::run_ensemble(table, flight, dynamics::microcanonical(table, flight, 1.0, 99), opt,
                                            particles, 2);
    double worst = 0;
    for (double e : res.energies) worst = std::max(worst, std::abs(e - 0.5) / 0.5);
    fmt::print("{:<12} {:>12} {:>8} {:>16.2e}\n", shape.region.name, res.collisions(), res.escapes(), worst);
    total += res.collisions();
    escapes += res.escapes();
  }
  fmt::print("total: {} collisions, {} escapes\n", total, escapes);

  const auto clover = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
  const dynamics::Table table(clover.region);
  dynamics::ParticleRng rng(5, 0);
  dynamics::RunOptions opt;
  opt.record_times = {drift_collisions * geometry::mean_free_path(geometry::measures_of(clover.region))};
  double energy = 0;
  const auto log = dynamics::simulate(table, dynamics::FreeFlight{}, dynamics::sample_microcanonical(table, 1.0, rng),
                                      opt, &energy);
  fmt::print("clover, one trajectory: {} collisions, relative energy drift {:.2e}, escaped: {}\n", log.collisions,
             std::abs(energy - 0.5) / 0.5, log.escaped);
  return escapes > 0 || log.escaped;
}
