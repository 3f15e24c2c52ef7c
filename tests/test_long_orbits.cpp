// Long orbits keep their invariants: rounding may make an invariant random-walk (√N over N
// bounces) but must not push it one way at every bounce (a drift linear in N).
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/follow.hpp"
#include "billiards/dynamics/magnetic_flight.hpp"
#include "billiards/dynamics/precision.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

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

namespace {

const geometry::Shape& shape(const std::string& name, const billiards::Overrides& overrides = {}) {
  static std::map<std::pair<std::string, billiards::Overrides>, geometry::Shape> loaded;
  const auto key = std::pair{name, overrides};
  auto it = loaded.find(key);
  if (it == loaded.end())
    it = loaded.emplace(key, geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + name + ".yaml", overrides)).first;
  return it->second;
}

/// How far an orbit's invariant and speed strayed: the largest (|invariant(s) − invariant(s0)|
/// / (scale ε) − drift k) / √k at the checkpoints k = 1e5, 2e5, ... (the c of a bound
/// drift ε k + c ε √k in units of `scale`), and the largest ||v|² − |v0|²| / (|v0|² ε) after
/// any bounce.
struct Walk {
  double c = 0, speed = 0;
};

/// Follows the orbit from s0 through `bounces` bounces with `evolve` (each flight on its own
/// clock, the speed restored as in every run).
template <class Invariant>
Walk walk(const geometry::Shape& table_shape, const dynamics::State& s0, std::size_t bounces, Invariant&& invariant,
          double scale, double drift = 0) {
  const dynamics::Table table(table_shape.region);
  const double I0 = invariant(s0), v2 = s0.v.squaredNorm();
  Walk w;
  std::size_t k = 0;
  const std::size_t made = dynamics::evolve(table, dynamics::FreeFlight{}, s0, bounces, [&](const auto&, const auto& s) {
    w.speed = std::max(w.speed, std::abs(double(squared_norm(s.v) - v2)) / (v2 * eps));
    if (++k % 100'000 == 0)
      w.c = std::max(w.c, (std::abs(invariant(s) - I0) / (scale * eps) - drift * double(k)) / std::sqrt(double(k)));
  });
  if (made < bounces) FAIL("escaped at bounce " << made);
  return w;
}

/// A start on the circle of radius r about the origin at `phi`, at angle `theta` from the
/// tangent.
dynamics::State on_circle(double r, double phi, double theta) {
  dynamics::State s;
  s.x = r * Vec2(std::cos(phi), std::sin(phi));
  s.v = Vec2(-std::sin(phi + theta), std::cos(phi + theta));
  return s;
}

/// The bounds of both invariant tests: c of c ε √N, and the speed's (restore_speed's band and
/// one bounce's rounding), in units of ε.
const double c_bound = 10, speed_bound = dynamics::speed_band<double> / eps + 2;

}  // namespace

TEST_CASE("circle orbits keep their angular momentum over 1e8 bounces, grazing or steep") {
  // Angular momentum about the centre is conserved by the flight and by the reflection; the
  // angle of incidence θ is a function of it (L = r |v| cos θ).  Its relative change after N
  // bounces stays within c ε √N, c = 10, from a whispering-gallery orbit (θ = 0.01, flights of
  // 0.02 r) to a steep one (θ = 1.4: each flight crosses most of the table), in the unit
  // circle and in one of radius 1.3, whose numbers are not powers of two.  There, at steep
  // incidence, a drift d = 0.005 ε per bounce is allowed: the rounding of the reflected
  // velocity's components leaves one of about 0.003 ε (it goes when the reflection is computed
  // in long double, at a price in every collision).  Three biases are
  // gone: a chord started inside the circle by rounding and lengthened by it to reach the
  // circle (−0.02 ε per bounce at θ = 0.01); the reflection off a normal with n·n − 1 biased
  // (−1.06 ε per bounce at θ = 1.4: `reflect` divides by n·n exactly); and the hit point moved
  // onto the circle radially, which turned the hit time's biased rounding along the flight into
  // a change of L (−0.10 ε per bounce at θ = 1.4: `contact` moves it along the flight).
  for (const double r : {1.0, 1.3}) {
    for (const double theta : {0.01, 0.7, 1.4}) {
      const auto s0 = on_circle(r, 0.1, theta);
      const auto momentum = [](const dynamics::State& s) { return geometry::cross(s.x, s.v); };
      const double d = r != 1 && theta > 1 ? 0.005 : 0;
      const auto w = walk(shape("circle", {{"R", std::to_string(r)}}), s0, 100'000'000, momentum,
                          std::abs(momentum(s0)), d);
      INFO("r " << r << ", theta " << theta << ": largest (|ΔL/L| / ε − " << d << " N) / √N " << w.c
                << ", ||v|² − v0²| / (v0² ε) " << w.speed);
      CHECK(w.c <= c_bound);
      CHECK(w.speed <= speed_bound);
    }
  }
}

TEST_CASE("a square orbit keeps its two momenta exactly over 1e8 bounces") {
  // Each bounce off a side flips one component of v: the normals are exact axis vectors, so the
  // flip is exact, and |v|² never moves (restore_speed leaves v alone).  |v_x| and |v_y| are
  // invariant bit for bit (c = 0).
  dynamics::State s0;
  s0.x = Vec2(0.3, 0.6);
  s0.v = Vec2(std::cos(0.3), std::sin(0.3));
  const dynamics::Table table(shape("square").region);
  std::size_t changed = 0;
  const std::size_t bounces = 100'000'000;
  const std::size_t made = dynamics::evolve(table, dynamics::FreeFlight{}, s0, bounces, [&](const auto&, const auto& s) {
    changed += std::abs(s.v.x()) != s0.v.x() || std::abs(s.v.y()) != s0.v.y();
  });
  CHECK(made == bounces);
  CHECK(changed == 0);
}

TEST_CASE("a square orbit at direction (1, 1 + δ) leaves the corner at δ t: each flight on its own clock") {
  // Unfolded, the orbit from (½, ½) is X = ½ + v_x t, Y = ½ + v_y t: it meets the sides in pairs
  // near a corner, each hit at δ t (1 + O(δ)) from it, δ = v_y − v_x = 1.1e-15.  A clock carried
  // in one double quantizes each flight's time, and so each hit point, to ulp(t) (1e-9 at
  // t = 1e7), and the orbit stays pinned near the corner instead; on its own clock each flight
  // is resolved to its rounding, 1e-16, which a random walk of 2e7 bounces makes 1e-13.
  dynamics::State s0;
  s0.x = Vec2(0.5, 0.5);
  s0.v = Vec2(1, 1 + 1e-15);
  const double delta = s0.v.y() - s0.v.x();  // (exact: Sterbenz)
  const dynamics::Table table(shape("square").region);
  const auto corner_distance = [](const Vec2& p) {
    const double dx = std::min(p.x(), 1 - p.x()), dy = std::min(p.y(), 1 - p.y());
    return std::max(dx, dy);  // (one of them is 0: the point is on a side)
  };
  double worst = 0;  // the largest |distance − δ t| over the hits after t = 1e4
  std::size_t checked = 0;
  dynamics::evolve(table, dynamics::FreeFlight{}, s0, 20'000'000, [&](const auto& hit, const auto&) {
    if (hit.t < 1e4) return;
    ++checked;
    worst = std::max(worst, std::abs(corner_distance(hit.point) - delta * hit.t));
  });
  INFO("largest |distance from the corner − δ t| " << worst << " over " << checked << " hits");
  CHECK(checked > 10'000'000);
  CHECK(worst <= 1e-12);
}

TEST_CASE("an ellipse orbit keeps the product of its focal angular momenta over 1e8 bounces") {
  // In the ellipse of semi-axes a = 2, b = 1 about the origin (foci ±f (cos α, sin α),
  // f² = a² − b², α its angle) the product (x − F1) × v · (x − F2) × v is conserved (it fixes
  // the orbit's confocal caustic).  Its change after N bounces, in units of its natural size
  // a²|v|², stays within c ε √N, c = 10, for an orbit with a caustic ellipse and one with a
  // caustic hyperbola, with the axes along x and turned by 0.3 rad.  (Restoring the speed at
  // every bounce made it drift, −0.003 ε per bounce on the hyperbolic orbit: restore_speed.)
  const double a = 2, b = 1, f = std::sqrt(a * a - b * b);
  for (const double angle : {0.0, 0.3}) {
    const Vec2 focus = f * Vec2(std::cos(angle), std::sin(angle));
    const auto focal_product = [focus](const dynamics::State& s) {
      return geometry::cross(Vec2(s.x + focus), s.v) * geometry::cross(Vec2(s.x - focus), s.v);
    };
    for (const double heading : {0.1, 1.2}) {  // (product > 0: a caustic ellipse; < 0: a hyperbola)
      dynamics::State s0;
      s0.x = Vec2(0.5, 0.3);
      s0.v = Vec2(std::cos(angle + heading), std::sin(angle + heading));
      const auto w = walk(shape("ellipse", {{"angle", std::to_string(angle)}}), s0, 100'000'000, focal_product, a * a);
      INFO("angle " << angle << ", heading " << heading << ", product " << focal_product(s0)
                    << ": largest change / (a² ε √N) " << w.c << ", ||v|² − v0²| / (v0² ε) " << w.speed);
      CHECK(w.c <= c_bound);
      CHECK(w.speed <= speed_bound);
    }
  }
}

TEST_CASE("a driven magnetic orbit at t = 1e8 is the orbit from t = 0 with its drive's phase reduced in MPFR") {
  // The law of a flight in the field under F cos(ω t + φ0) reads the time only through the
  // drive's phase.  A particle at T = 1e8 (after a long run) must therefore move as one at
  // t = 0 with φ0 replaced by ω T + φ0 reduced mod 2π, here in MPFR (136 bits) independently
  // of the flight's own reduction.  A phase computed as ω t + φ0 in one double is off by up to
  // ulp(ω T) / 2 = 1e-6 rad at ω T = 1.3e10, which moves the velocity by (F/mω) 1e-6 ≈ 3e-8;
  // carried in the state (two doubles) from the start, the two orbits differ by the rounding
  // of the reduced φ0 to one double (2e-16 rad).  The driven orbit in the square is chaotic
  // (a difference grows ~3x a bounce), so it is compared over its first 10 bounces, where that
  // rounding stays below 1e-12 (measured 1.3e-14).
  const double omega_c = 0.7, omega = 40 * geometry::pi, phi0 = 0.3, T = 1e8 + 0.125;
  const Vec2 accel(3, 2);
  const dynamics::Reference two_pi = 2 * boost::multiprecision::acos(dynamics::Reference(-1));
  const double reduced = double(boost::multiprecision::fmod(dynamics::Reference(omega) * T + phi0, two_pi));
  const dynamics::MagneticDriveFlight late{omega_c, accel, omega, phi0}, early{omega_c, accel, omega, reduced};
  const dynamics::Table table(shape("square").region);
  dynamics::State s0;
  s0.x = Vec2(0.3, 0.6);
  s0.v = Vec2(std::cos(0.3), std::sin(0.3));
  const std::size_t bounces = 10;
  auto follow = [&](const dynamics::MagneticDriveFlight& flight, double start) {
    auto s = s0;
    s.t = start;
    std::vector<std::pair<dynamics::Hit, dynamics::DrivenState>> hits;
    dynamics::FollowLimits limits;
    limits.collisions = bounces;
    limits.t_end = start + 1e3;
    dynamics::follow(table, flight, flight.start(s), limits, {}, [&](const auto& hit, const auto& after) {
      hits.emplace_back(hit, after);
    }, [](const auto&) {});
    return hits;
  };
  const auto a = follow(late, T), b = follow(early, 0);
  REQUIRE(a.size() == bounces);
  REQUIRE(b.size() == bounces);
  double dx = 0, dv = 0, dt = 0;
  for (std::size_t k = 0; k < bounces; ++k) {
    dx = std::max(dx, (a[k].first.point - b[k].first.point).norm());
    dv = std::max(dv, (a[k].second.v - b[k].second.v).norm());
    dt = std::max(dt, std::abs((a[k].first.t - T) - b[k].first.t));  // (a's hit times rounded to ulp(T))
  }
  INFO("largest differences over " << bounces << " bounces: point " << dx << ", velocity " << dv << ", time " << dt);
  CHECK(dx <= 1e-12);
  CHECK(dv <= 1e-12);
  CHECK(dt <= 1e-8);
}
