// Reference precision: the same free-flight code (walls, exit times, collision, bounce) run in
// double, long double and 136-bit MPFR (precision.hpp) from the same initial conditions.  The
// MPFR run is the reference; the distance of the other runs' collision points from it, per
// collision, shows how chaos amplifies rounding: its exponential growth rate (the Lyapunov
// exponent per collision), the collision at which double and long double lose the reference
// (median distance > 1e-3), and the cost of each precision.
// Usage: bench_reference [trajectories per shape, default 40] [collisions, default 400] [CSV file]
#include "billiards/analysis/divergence.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/precision.hpp"
#include "billiards/geometry.hpp"

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>

using namespace billiards;
using dynamics::Reference;

namespace {

using Clock = std::chrono::steady_clock;

/// Collision points in precision Real, and the collisions per second it took.
template <class Real>
std::pair<std::vector<std::vector<Eigen::Vector2d>>, double> timed(const geometry::Region2& region,
                                                                    const std::vector<dynamics::State>& starts,
                                                                    std::size_t n) {
  const auto t0 = Clock::now();
  auto points = analysis::collision_points<Real>(region, starts, n);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  std::size_t count = 0;
  for (const auto& p : points) count += p.size();
  return {std::move(points), double(count) / seconds};
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t trajectories = argc > 1 ? std::size_t(std::atof(argv[1])) : 40;
  const std::size_t n = argc > 2 ? std::size_t(std::atof(argv[2])) : 400;
  std::ofstream csv(argc > 3 ? argv[3] : "reference-errors.csv");
  csv << "shape,collision,median_error_double,median_error_long_double\n";
  fmt::print("{} trajectories x {} collisions per shape; error = median distance of the collision point "
             "from the 136-bit MPFR run\n\n",
             trajectories, n);
  fmt::print("{:<10} {:>14} {:>14} {:>12} {:>12} {:>10} {:>10} {:>10} {:>9} {:>9}\n", "shape", "growth double",
             "growth long d.", "lost: double", "long double", "double M/s", "long d.", "MPFR k/s", "MPFR/dbl",
             "ld/dbl");
  for (const char* name : {"circle", "stadium", "sinai", "mushroom", "clover"}) {
    const auto shape = geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml");
    const dynamics::Table table(shape.region);
    std::vector<dynamics::State> starts;
    for (std::size_t i = 0; i < trajectories; ++i) {
      dynamics::ParticleRng rng(1, i);
      starts.push_back(dynamics::sample_microcanonical(table, 1.0, rng));
    }
    const auto [d, rate_d] = timed<double>(shape.region, starts, n);
    const auto [l, rate_l] = timed<long double>(shape.region, starts, n);
    const auto [r, rate_r] = timed<Reference>(shape.region, starts, n);
    const auto ed = analysis::median_distance(d, r, n), el = analysis::median_distance(l, r, n);
    for (std::size_t k = 0; k < n; ++k) csv << fmt::format("{},{},{:.6g},{:.6g}\n", name, k + 1, ed[k], el[k]);
    fmt::print("{:<10} {:>14.3g} {:>14.3g} {:>12} {:>12} {:>10.3g} {:>10.3g} {:>10.3g} {:>9.0f} {:>9.1f}\n", name,
               analysis::exponential_growth_rate(ed), analysis::exponential_growth_rate(el),
               analysis::first_exceeding(ed, 1e-3), analysis::first_exceeding(el, 1e-3), rate_d / 1e6, rate_l / 1e6,
               rate_r / 1e3, rate_d / rate_r, rate_d / rate_l);
  }
  fmt::print("\n(growth: slope of ln(error) per collision while 1e-13 < error < 1e-4; lost: first collision with "
             "median error > 1e-3, 0 if never; per-collision rates on one core)\n");
}
