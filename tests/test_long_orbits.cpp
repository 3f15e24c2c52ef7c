// Long orbits keep their invariants: rounding may make an invariant random-walk (√N over N
// bounces) but must not push it one way at every bounce (a drift linear in N).
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace billiards;
using dynamics::Vec2;

namespace {

const double eps = std::numeric_limits<double>::epsilon();

/// Mean and standard error of a sample, accumulated one value at a time.
struct Mean {
  double n = 0, sum = 0, sum2 = 0;
  void add(double x) {
    n += 1;
    sum += x;
    sum2 += x * x;
  }
  double mean() const { return sum / n; }
  double se() const { return std::sqrt((sum2 / n - mean() * mean()) / (n - 1)); }
};

/// |v|² in long double: in double its rounding near 1 (where the spacing of doubles halves) is
/// itself biased.
long double squared_norm(const Vec2& v) { return (long double)v.x() * v.x() + (long double)v.y() * v.y(); }

}  // namespace

TEST_CASE("a reflection off a normal that is a unit vector to rounding keeps the speed without bias") {
  // The normal as contact() computes it, u/|u|, so n·n = 1 + η.  The reflection must keep |v|
  // to rounding noise of zero mean: a bias would turn every orbit toward (or away from) the
  // normal a little at every bounce.  (Dividing by a rounded n·n, or multiplying by 2 − n·n,
  // adds such a bias, −0.07 ε per reflection: the rounding of n·n near 1 is itself biased.)
  dynamics::ParticleRng rng(3, 0);
  Mean change;
  for (int k = 0; k < 1'000'000; ++k) {
    const double phi = 2 * geometry::pi * rng.uniform(), psi = 2 * geometry::pi * rng.uniform();
    const Vec2 u = (0.5 + rng.uniform()) * Vec2(std::cos(phi), std::sin(phi));
    const Vec2 n = u * (1 / std::sqrt(u.squaredNorm()));
    const Vec2 v(std::cos(psi), std::sin(psi));
    const Vec2 r = dynamics::reflect(v, n);
    change.add(double((squared_norm(r) - squared_norm(v)) / eps));
  }
  INFO("mean change of |v|² per reflection " << change.mean() << " ± " << change.se() << " ε");
  CHECK(std::abs(change.mean()) <= 3 * change.se());
}

TEST_CASE("a whispering-gallery orbit of the circle keeps its angular momentum over 1e8 bounces") {
  // Angular momentum about the centre is conserved by the flight and by the reflection.  From a
  // start on the circle at 0.01 rad from the tangent, its relative change after N bounces stays
  // within c ε √N, c = 10.  (A chord started inside the circle by rounding and lengthened by it
  // to reach the circle turned the orbit toward the normal at every such bounce: −0.02 ε per
  // bounce, 180 ε √N after 1e8.)  Each flight starts its own clock (t = 0): a clock carried
  // across flights quantizes the flight time to its ulp, which dwarfs this.
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/circle.yaml");
  const dynamics::Table table(shape.region);
  const dynamics::FreeFlight flight;
  const double theta = 0.01, phi = 0.1;
  dynamics::State s;
  s.x = Vec2(std::cos(phi), std::sin(phi));
  s.v = Vec2(-std::sin(phi + theta), std::cos(phi + theta));
  const auto momentum = [](const dynamics::State& s) { return geometry::cross(s.x, s.v); };
  const double L0 = momentum(s), v2 = s.v.squaredNorm();
  constexpr std::size_t bounces = 100'000'000;
  constexpr double c = 10;
  double worst = 0;  // the largest |ΔL/L| / (ε √k) at the checkpoints k = 1e5, 2e5, ...
  for (std::size_t k = 1; k <= bounces; ++k) {
    const auto hit = dynamics::collision(table, flight, s);
    if (!hit.found()) FAIL("escaped at bounce " << k);
    dynamics::bounce(flight, s, hit);
    dynamics::restore_speed(s.v, v2);
    s.t = 0;
    if (k % 100'000 == 0) worst = std::max(worst, std::abs(momentum(s) / L0 - 1) / (eps * std::sqrt(double(k))));
  }
  INFO("largest |ΔL/L| / (ε √N) " << worst);
  CHECK(worst <= c);
}
