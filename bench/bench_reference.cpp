// Reference precision: the same free-flight code (walls, exit times, collision, bounce) run in
// double, long double and 136-bit MPFR (precision.hpp) from the same initial conditions.  The
// MPFR run is the reference; the distance of the other runs' collision points from it, per
// collision, shows how chaos amplifies rounding: its exponential growth rate (the Lyapunov
// exponent per collision), the collision at which double and long double lose the reference
// (median distance > 1e-3), and the cost of each precision.
// Usage: bench_reference [trajectories per shape, default 40] [collisions, default 400] [CSV file]
#include "billiards/analysis/divergence.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/forced_flight.hpp"
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

/// Collision points under `flight` (its scalar type is the precision), and collisions per second.
template <class Flight>
std::pair<std::vector<std::vector<Eigen::Vector2d>>, double> timed(const geometry::Region2& region, const Flight& flight,
                                                                    const std::vector<dynamics::State>& starts,
                                                                    std::size_t n) {
  const auto t0 = Clock::now();
  auto points = analysis::collision_points(region, flight, starts, n);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  std::size_t count = 0;
  for (const auto& p : points) count += p.size();
  return {std::move(points), double(count) / seconds};
}

template <class T>
struct Tag {
  using type = T;
};

/// One row: `make(Tag<Real>{})` builds the flight in precision Real.
template <class Make>
void compare(const std::string& label, const std::string& shape_name, std::size_t trajectories, std::size_t n,
             std::ofstream& csv, Make make) {
  const auto shape = geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + shape_name + ".yaml");
  const dynamics::Table table(shape.region);
  std::vector<dynamics::State> starts;
  for (std::size_t i = 0; i < trajectories; ++i) {
    dynamics::ParticleRng rng(1, i);
    starts.push_back(dynamics::sample_microcanonical(table, 1.0, rng));
  }
  const auto [d, rate_d] = timed(shape.region, make(Tag<double>{}), starts, n);
  const auto [l, rate_l] = timed(shape.region, make(Tag<long double>{}), starts, n);
  const auto [r, rate_r] = timed(shape.region, make(Tag<Reference>{}), starts, n);
  const auto ed = analysis::median_distance(d, r, n), el = analysis::median_distance(l, r, n);
  for (std::size_t k = 0; k < n; ++k) csv << fmt::format("{},{},{:.6g},{:.6g}\n", label, k + 1, ed[k], el[k]);
  fmt::print("{:<18} {:>14.3g} {:>14.3g} {:>12} {:>12} {:>10.3g} {:>10.3g} {:>10.3g} {:>9.0f} {:>9.1f}\n", label,
             analysis::exponential_growth_rate(ed), analysis::exponential_growth_rate(el),
             analysis::first_exceeding(ed, 1e-3), analysis::first_exceeding(el, 1e-3), rate_d / 1e6, rate_l / 1e6,
             rate_r / 1e3, rate_d / rate_r, rate_d / rate_l);
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t trajectories = argc > 1 ? std::size_t(std::atof(argv[1])) : 40;
  const std::size_t n = argc > 2 ? std::size_t(std::atof(argv[2])) : 400;
  std::ofstream csv(argc > 3 ? argv[3] : "reference-errors.csv");
  csv << "case,collision,median_error_double,median_error_long_double\n";
  fmt::print("{} trajectories x {} collisions per case; error = median distance of the collision point "
             "from the 136-bit MPFR run\n\n",
             trajectories, n);
  fmt::print("{:<18} {:>14} {:>14} {:>12} {:>12} {:>10} {:>10} {:>10} {:>9} {:>9}\n", "case", "growth double",
             "growth long d.", "lost: double", "long double", "double M/s", "long d.", "MPFR k/s", "MPFR/dbl",
             "ld/dbl");
  for (const char* name : {"circle", "stadium", "sinai", "mushroom", "clover"})
    compare(name, name, trajectories, n, csv,
            [](auto tag) { return dynamics::BasicFreeFlight<typename decltype(tag)::type>{}; });
  // The paper's drive: F = 10 along (1, 1)/√2, m = 1.
  for (const int w : {40, 320})
    compare(fmt::format("clover driven {}pi", w), "clover", trajectories, n, csv, [w](auto tag) {
      using Real = typename decltype(tag)::type;
      const Real a = Real(10) / sqrt(Real(2));
      return dynamics::BasicPeriodicDriveFlight<Real>{dynamics::Vec2T<Real>(a, a),
                                                      Real(w) * boost::math::constants::pi<Real>(), Real(0)};
    });
  fmt::print("\n(growth: slope of ln(error) per collision while 1e-13 < error < 1e-4; lost: first collision with "
             "median error > 1e-3, 0 if never; per-collision rates on one core)\n");
}
