// Free billiard dynamics on every bundled shape.
#include "billiards/analysis/coefficients.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/geometry.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <random>

using namespace billiards;
using dynamics::Vec2;

namespace {

/// Every bundled 2-D shape.
std::vector<std::string> bundled_shapes() {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(BILLIARDS_SOURCE_DIR "/shapes"))
    if (e.path().extension() == ".yaml") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

struct RateCheck {
  double measured, se, expected;
  std::uint64_t collisions, escapes;
};

/// Collisions per unit time of a microcanonical ensemble, against the analysis layer's
/// prediction ∫ γ_E dS.  Stationarity of the Liouville measure makes E[collisions in [0, T]]
/// = T ∫ γ_E dS exactly, for any shape and any T, ergodic or not (Santaló: = T v/λ).
RateCheck collision_rate(const std::string& path, std::size_t particles, double collisions_each) {
  const auto shape = geometry::load_shape(path);
  const dynamics::Table table(shape.region);
  const auto m = geometry::measures_of(shape.region);
  const double lambda = geometry::mean_free_path(m);
  // m = 1, speed 1: E = 1/2; γ_E is uniform on the wall for a standard billiard.
  const double predicted_rate = analysis::collision_rate_density(m, 1.0, 0.5) * m.surface;
  const double T = collisions_each * lambda;  // speed 1
  dynamics::RunOptions opt;
  opt.record_times = {T};
  opt.verify_every_flight = true;
  const dynamics::FreeFlight flight;
  const auto res = dynamics::run_ensemble(table, flight, dynamics::microcanonical(table, flight, 1.0, 2024), opt,
                                          particles, 2);
  double sum = 0, sum2 = 0;
  for (const auto& l : res.logs) {
    sum += double(l.collisions);
    sum2 += double(l.collisions) * double(l.collisions);
  }
  const double n = double(particles), mean = sum / n, var = sum2 / n - mean * mean;
  return {mean / T, std::sqrt(var / n) / T, predicted_rate, res.collisions(), res.escapes()};
}

}  // namespace

TEST_CASE("measured collision rate equals the integral of gamma_E over the wall (= v / lambda) on every bundled shape, with no escape") {
  for (const auto& path : bundled_shapes()) {
    INFO(path);
    const auto r = collision_rate(path, 4000, 50);
    CHECK(r.escapes == 0);
    CHECK(r.collisions > 150000);
    CHECK(std::abs(r.measured - r.expected) < 4 * r.se);
    CHECK(r.se < 0.01 * r.expected);  // the test has teeth: a 4% error in λ would fail
  }
}

TEST_CASE("energy is conserved by reflection over a million collisions") {
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
  const dynamics::Table table(shape.region);
  dynamics::ParticleRng rng(7, 0);
  const auto s = dynamics::sample_microcanonical(table, 1.0, rng);
  dynamics::RunOptions opt;
  opt.record_times = {1e6 * geometry::mean_free_path(geometry::measures_of(shape.region))};
  double energy = 0;
  const auto log = dynamics::simulate(table, dynamics::FreeFlight{}, s, opt, &energy);
  CHECK(log.collisions > 900000);
  CHECK_FALSE(log.escaped);
  // (restore_speed's band, and one bounce's rounding)
  CHECK(std::abs(energy - 0.5) <= (dynamics::speed_band<double> + 2 * std::numeric_limits<double>::epsilon()) * 0.5);
}

TEST_CASE("grid traversal finds exactly the hits of the brute-force search") {
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/wavy-1200.yaml");
  const dynamics::Table table(shape.region);
  REQUIRE(table.grid() != nullptr);
  dynamics::ParticleRng rng(11, 0);
  auto s = dynamics::sample_microcanonical(table, 1.0, rng);
  for (int k = 0; k < 20000; ++k) {
    const auto fast = dynamics::collision(table, dynamics::FreeFlight{}, s);
    dynamics::Hit slow;
    slow.t = dynamics::never;
    for (const auto& w : table.wall_ids())
      dynamics::detail::try_wall(table, dynamics::FreeFlight{}, s, w, slow);
    REQUIRE(fast.wall == slow.wall);
    REQUIRE(fast.t == slow.t);
    dynamics::bounce(dynamics::FreeFlight{}, s, fast);
  }
}

TEST_CASE("a particle's generator draws std::mt19937_64's sequence, word for word") {
  // LazyMt19937_64 computes the first 156 outputs from the seeded words they need and hands
  // over to the standard engine after them: the sequence must be the standard one across the
  // hand-over, for seeds as ParticleRng makes them and for edge seeds.
  std::vector<std::uint64_t> seeds = {0, 1, 5489, ~std::uint64_t(0), std::uint64_t(1) << 63};
  for (std::uint64_t i = 0; i < 200; ++i) seeds.push_back(dynamics::splitmix64(dynamics::splitmix64(42) ^ dynamics::splitmix64(~i)));
  int mismatches = 0;
  for (const std::uint64_t seed : seeds) {
    std::mt19937_64 standard(seed);
    dynamics::LazyMt19937_64 lazy(seed);
    for (int k = 0; k < 1000; ++k) mismatches += lazy() != standard();
  }
  CHECK(mismatches == 0);
}

TEST_CASE("an exception thrown inside the parallel run is rethrown after it: the lowest particle's, for any thread count") {
  const dynamics::Table table(geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml").region);
  dynamics::RunOptions opt;
  opt.record_times = {0, 100};
  const dynamics::FreeFlight flight;
  const auto sampled = dynamics::microcanonical(table, flight, 1.0, 7);
  // Particles 9 and 30 fail; 9's error is the one reported, whichever thread meets which first.
  const auto initial = [&](std::size_t i) {
    if (i == 9 || i == 30) throw std::runtime_error("particle " + std::to_string(i) + " cannot start");
    return sampled(i);
  };
  for (const int threads : {1, 2})
    CHECK_THROWS_WITH(dynamics::run_ensemble(table, flight, initial, opt, 64, threads), "particle 9 cannot start");
}
