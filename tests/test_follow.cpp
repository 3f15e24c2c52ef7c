// dynamics::follow: a trajectory streamed bounce by bounce and sampled densely between bounces.
// The samples of a driven flight are checked against the closed form of its flight written
// here again; the streamed bounces against `evolve`'s, bit for bit; and the stream's memory
// against its length: it allocates nothing per collision.
#include "billiards/dynamics/follow.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/geometry.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <vector>

namespace {

// Every allocation of this test program is counted.
std::atomic<std::size_t> allocations{0};

}  // namespace

void* operator new(std::size_t n) {
  ++allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace billiards;
using dynamics::Vec2;

namespace {

const geometry::Shape& clover() {
  static const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
  return shape;
}
const geometry::Shape& stadium() {
  static const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/stadium.yaml");
  return shape;
}

template <class Flight>
typename Flight::State start(const dynamics::Table& table, const Flight& flight, std::uint64_t seed) {
  dynamics::ParticleRng rng(seed, 0);
  return flight.start(sample_microcanonical(table, 1.0, rng));
}

/// Appendix B's flight under F cos(ω t + φ)/m from (x_s, v_s) at t_s, written out again.
Vec2 driven_position(const Vec2& a, double omega, double phase, const dynamics::State& s, double t) {
  const double th_s = omega * s.t + phase, th = omega * t + phase;
  return s.x + (s.v - a / omega * std::sin(th_s)) * (t - s.t) - a / (omega * omega) * (std::cos(th) - std::cos(th_s));
}

}  // namespace

TEST_CASE("dense samples of a driven flight follow its closed form between bounces", "[follow]") {
  const dynamics::Table table(clover().region);
  const dynamics::PeriodicDriveFlight flight{Vec2(3, 1), 40, 0.3};
  const double dt = 0.0137, t_end = 40.0;
  dynamics::State last = start(table, flight, 7);  // the state after the latest bounce
  std::vector<double> times;
  double worst = 0;
  const auto result = dynamics::follow(
      table, flight, start(table, flight, 7), {.t_end = t_end}, dynamics::SampleClock{0, dt},
      [&](const auto&, const auto& after) { last = after; },
      [&](const auto& s) {
        times.push_back(s.t);
        const Vec2 x = driven_position(flight.accel, flight.omega, flight.phase0, last, s.t);
        worst = std::max(worst, (s.x - x).norm());
        CHECK(table.contains(s.x, 1e-9));
      });
  CHECK(!result.escaped);
  CHECK(result.collisions > 10);  // many bounces, so the samples span many flights
  // Every time k dt up to t_end, in order, each computed from k.
  REQUIRE(times.size() == std::size_t(std::floor(t_end / dt)) + 1);
  for (std::size_t k = 0; k < times.size(); ++k) CHECK(times[k] == double(k) * dt);
  // The closed form and advance() round differently: agreement to rounding over ~0.1 long flights.
  CHECK(worst < 1e-12);
}

TEST_CASE("dense samples of a flight under a constant force lie on its parabolas", "[follow]") {
  const dynamics::Table table(stadium().region);
  const dynamics::ConstantForceFlight flight{Vec2(0.2, -1.5)};
  dynamics::State last = start(table, flight, 3);
  std::size_t samples = 0;
  double worst = 0;
  dynamics::follow(
      table, flight, last, {.collisions = 200}, dynamics::SampleClock{0, 0.01},
      [&](const auto&, const auto& after) { last = after; },
      [&](const auto& s) {
        const double tau = s.t - last.t;
        worst = std::max(worst, (s.x - (last.x + last.v * tau + 0.5 * flight.accel * tau * tau)).norm());
        ++samples;
      });
  CHECK(samples > 200);
  CHECK(worst < 1e-12);
}

TEMPLATE_TEST_CASE("a streamed trajectory is the collected one, bit for bit", "[follow]", dynamics::FreeFlight,
                   dynamics::PeriodicDriveFlight) {
  const dynamics::Table table(clover().region);
  const auto flight = [] {
    if constexpr (std::is_same_v<TestType, dynamics::FreeFlight>) return TestType{};
    else return TestType{Vec2(10, 10), 40 * geometry::pi, 0};
  }();
  const auto s0 = start(table, flight, 11);
  constexpr std::size_t n = 3000;
  std::vector<typename TestType::State> evolved, streamed;
  CHECK(dynamics::evolve(table, flight, s0, n, [&](const auto&, const auto& s) { evolved.push_back(s); }) == n);
  // With samples in between: sampling must not disturb the bounces.
  const auto result = dynamics::follow(table, flight, s0, {.collisions = n}, dynamics::SampleClock{0, 0.01},
                                       [&](const auto&, const auto& s) { streamed.push_back(s); }, [](const auto&) {});
  CHECK(result.collisions == n);
  REQUIRE(streamed.size() == n);
  for (std::size_t k = 0; k < n; ++k) {
    INFO("bounce " << k);
    REQUIRE(streamed[k].t == evolved[k].t);
    REQUIRE(streamed[k].x == evolved[k].x);
    REQUIRE(streamed[k].v == evolved[k].v);
  }
}

TEST_CASE("a streamed trajectory allocates nothing per collision", "[follow]") {
  // Bounded memory for any length: the allocations of a stream of 10⁵ collisions are those of
  // one of 10² (none, or a fixed few), not proportional to its length.
  const dynamics::Table table(clover().region);
  const dynamics::PeriodicDriveFlight flight{Vec2(10, 10), 40 * geometry::pi, 0};
  const auto s0 = start(table, flight, 5);
  const auto count = [&](std::size_t collisions) {
    std::size_t bounces = 0, samples = 0;
    const std::size_t before = allocations;
    dynamics::follow(table, flight, s0, {.collisions = collisions}, dynamics::SampleClock{0, 0.01},
                     [&](const auto&, const auto&) { ++bounces; }, [&](const auto&) { ++samples; });
    const std::size_t made = allocations - before;
    CHECK(bounces == collisions);
    CHECK(samples > collisions);
    return made;
  };
  const std::size_t short_run = count(100), long_run = count(100000);
  CHECK(long_run == short_run);
}

TEST_CASE("a stream ends at its end time, with a sample at each time up to it", "[follow]") {
  const dynamics::Table table(clover().region);
  const dynamics::FreeFlight flight;
  double last_t = 0;
  std::size_t samples = 0;
  const auto r = dynamics::follow(table, flight, start(table, flight, 2), {.t_end = 5.0}, dynamics::SampleClock{0, 0.5},
                                  [&](const auto&, const auto& s) { last_t = s.t; }, [&](const auto&) { ++samples; });
  CHECK(!r.escaped);
  CHECK(samples == 11);
  CHECK(last_t <= 5.0);
  CHECK(r.collisions > 0);
}
