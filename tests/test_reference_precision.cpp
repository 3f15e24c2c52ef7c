// One flight code in three precisions: double, long double and 136-bit MPFR (the reference),
// free and driven.  Chaos amplifies rounding at the Lyapunov rate; integrable tables do not.
#include "billiards/analysis/divergence.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/precision.hpp"
#include "billiards/geometry.hpp"

#include <catch2/catch.hpp>

#include <boost/math/constants/constants.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <random>

using namespace billiards;
using dynamics::Reference;

namespace {

geometry::Region2 shape(const std::string& name) {
  return geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + name + ".yaml").region;
}

template <class T>
struct Tag {
  using type = T;
};

std::vector<dynamics::State> starts(const geometry::Region2& region, std::size_t count) {
  const dynamics::Table table(region);
  std::vector<dynamics::State> s;
  for (std::size_t i = 0; i < count; ++i) {
    dynamics::ParticleRng rng(7, i);
    s.push_back(dynamics::sample_microcanonical(table, 1.0, rng));
  }
  return s;
}

}  // namespace

TEST_CASE("the same flight code in double, long double and MPFR: identical walls, points within rounding") {
  const auto region = shape("clover");
  const dynamics::State s0 = starts(region, 1)[0];
  const std::size_t n = 8;  // the clover's λ ≈ 1.5 per collision: e^{1.5·8} 1e-16 ≈ 2e-11
  const dynamics::Table dt(region);
  const dynamics::BasicTable<long double> lt(region);
  const dynamics::BasicTable<Reference> rt(region);
  const auto d = dynamics::evolve(dt, dynamics::FreeFlight{}, s0, n);
  dynamics::BasicState<long double> sl;
  sl.x = s0.x.cast<long double>();
  sl.v = s0.v.cast<long double>();
  const auto l = dynamics::evolve(lt, dynamics::BasicFreeFlight<long double>{}, sl, n);
  dynamics::BasicState<Reference> sr;
  sr.x = s0.x.cast<Reference>();
  sr.v = s0.v.cast<Reference>();
  const auto r = dynamics::evolve(rt, dynamics::BasicFreeFlight<Reference>{}, sr, n);
  REQUIRE(d.size() == n);
  REQUIRE(l.size() == n);
  REQUIRE(r.size() == n);
  for (std::size_t k = 0; k < n; ++k) {
    CHECK(d[k].wall == r[k].wall);
    CHECK(l[k].wall == r[k].wall);
    const Eigen::Vector2d pr(double(r[k].point.x()), double(r[k].point.y()));
    CHECK((d[k].point - pr).norm() < 1e-9);
    CHECK((Eigen::Vector2d(double(l[k].point.x()), double(l[k].point.y())) - pr).norm() < 1e-12);
    // The reference point lies on its wall to its own precision, far below double rounding.
    const auto& w = rt.arcs()[r[k].wall.index];
    CHECK(double(abs((r[k].point - w.center).norm() - w.radius)) < 1e-35);
    // Time runs forward.
    CHECK(r[k].t > (k ? r[k - 1].t : Reference(0)));
  }
}

TEST_CASE("chaos amplifies rounding at the Lyapunov rate; long double holds the reference ln(2048)/λ collisions longer") {
  for (const char* name : {"clover", "stadium"}) {
    INFO(name);
    const auto region = shape(name);
    const auto s = starts(region, 25);
    const std::size_t n = 80;
    const auto ref = analysis::collision_points<Reference>(region, s, n);
    const auto ed = analysis::median_distance(analysis::collision_points<double>(region, s, n), ref, n);
    const auto el = analysis::median_distance(analysis::collision_points<long double>(region, s, n), ref, n);
    const double lambda_d = analysis::exponential_growth_rate(ed), lambda_l = analysis::exponential_growth_rate(el);
    // Both precisions see the same dynamics: the same exponent, and it is positive (chaos).
    CHECK(lambda_d > 0.3);
    CHECK(lambda_l == Approx(lambda_d).epsilon(0.2));
    // Errors start at rounding level, so long double (64-bit mantissa) lags double (53-bit)
    // by ln(2^11)/λ collisions before both reach the same distance.
    const std::size_t lost_d = analysis::first_exceeding(ed, 1e-3), lost_l = analysis::first_exceeding(el, 1e-3);
    REQUIRE(lost_d > 0);
    REQUIRE(lost_l > lost_d);
    const double lag = std::log(std::ldexp(1.0, LDBL_MANT_DIG - DBL_MANT_DIG)) / lambda_d;
    CHECK(double(lost_l - lost_d) == Approx(lag).epsilon(0.5));
    // Before the first collision the two start equal to rounding of their own precision.
    CHECK(ed[0] < 1e-14);
    CHECK(el[0] < 1e-17);
  }
}

TEST_CASE("an integrable table (the circle) does not amplify rounding exponentially") {
  const auto region = shape("circle");
  const auto s = starts(region, 5);
  const std::size_t n = 2000;
  const auto ref = analysis::collision_points<Reference>(region, s, n);
  const auto ed = analysis::median_distance(analysis::collision_points<double>(region, s, n), ref, n);
  // A rounding error in the angular momentum shifts every later bounce by the same angle, and
  // one is made at every bounce: the distance grows like k², not like e^{λ k}.  Doubling the
  // number of bounces multiplies it by about 4 (measured 4.9 from 1000 to 2000; any λ > 0.002
  // would give more than 8).
  CHECK(ed[n - 1] / ed[n / 2 - 1] < 8);
  CHECK(ed[n - 1] < 1e-7);
}

TEST_CASE("the driven flight in double, long double and MPFR: the same collisions; rounding grows at one rate") {
  const auto region = shape("clover");
  const auto s = starts(region, 20);
  const std::size_t n = 40;
  const auto drive = [](auto tag) {
    using Real = typename decltype(tag)::type;
    const Real a = Real(10) / sqrt(Real(2));  // the paper's F = 10 along (1, 1)/√2, m = 1, ω = 40π
    return dynamics::BasicPeriodicDriveFlight<Real>{dynamics::Vec2T<Real>(a, a),
                                                    40 * boost::math::constants::pi<Real>(), Real(0)};
  };
  // evolve() searches with no horizon: every wall's scan must end (it once looped at τ = ∞).
  const auto ref = analysis::collision_points(region, drive(Tag<Reference>{}), s, n);
  const auto d = analysis::collision_points(region, drive(Tag<double>{}), s, n);
  const auto l = analysis::collision_points(region, drive(Tag<long double>{}), s, n);
  for (std::size_t i = 0; i < s.size(); ++i) REQUIRE(ref[i].size() == n);
  const auto ed = analysis::median_distance(d, ref, n), el = analysis::median_distance(l, ref, n);
  // The first collisions agree to the roots' polish (a few ulps of the table's size).
  CHECK(ed[0] < 1e-13);
  CHECK(el[0] < 1e-16);
  const double lambda_d = analysis::exponential_growth_rate(ed), lambda_l = analysis::exponential_growth_rate(el);
  CHECK(lambda_d > 0.3);
  CHECK(lambda_l == Approx(lambda_d).epsilon(0.25));
  const std::size_t lost_d = analysis::first_exceeding(ed, 1e-3), lost_l = analysis::first_exceeding(el, 1e-3);
  REQUIRE(lost_d > 0);
  CHECK(lost_l >= lost_d);
  CHECK(double(lost_l - lost_d) == Approx(std::log(std::ldexp(1.0, LDBL_MANT_DIG - DBL_MANT_DIG)) / lambda_d).margin(2));
}

TEST_CASE("the drive's sin_cos in double: within 1.5 ulp of 1 of MPFR's sine and cosine, in every quadrant") {
  // Random phases as a flight's samples meet them (up to 10⁶ rad, where the two-part reduction
  // must still be exact), and the points next to multiples of π/2 where the reduced argument
  // cancels to nothing and the quadrant changes.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> wide(-1e6, 1e6), narrow(0, 20);
  std::vector<double> thetas;
  for (int i = 0; i < 100000; ++i) thetas.push_back(i % 2 ? wide(rng) : narrow(rng));
  for (int k = -40; k <= 4000; ++k) {
    const double edge = double(k * (boost::math::constants::half_pi<Reference>()));
    for (double t = std::nextafter(edge, -1e300), n = 0; n < 5; t = std::nextafter(t, 1e300), ++n) thetas.push_back(t);
  }
  double worst = 0;
  for (const double theta : thetas) {
    const auto [s, c] = dynamics::sin_cos(theta);
    const Reference exact_s = sin(Reference(theta)), exact_c = cos(Reference(theta));
    worst = std::max({worst, double(abs(Reference(s) - exact_s)), double(abs(Reference(c) - exact_c))});
  }
  INFO("worst absolute error " << worst);
  CHECK(worst <= 1.5 * DBL_EPSILON / 2);
  // Beyond 2¹⁹π the function falls back on std's.
  CHECK(dynamics::sin_cos(3e6).first == std::sin(3e6));
}

TEST_CASE("PhaseSample::shifted: sin and cos of theta + h within 2 ulp of 1 of MPFR's, for |h| up to h_max") {
  // The root search's last step and the hit's state take their sine and cosine from the last
  // sample's by the angle-sum formulas and the Taylor series of sin h and cos h − 1; a wrong
  // coefficient of the series shows at |h| ~ h_max (1e-7 for the h⁷ term's).
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> phase(0, 7), shift(-dynamics::PhaseSample<double>::h_max,
                                                          dynamics::PhaseSample<double>::h_max);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const double theta = phase(rng), h = i % 4 ? shift(rng) : std::copysign(0.05, shift(rng));
    const auto [s0, c0] = dynamics::sin_cos(theta);
    const auto [s, c] = dynamics::PhaseSample<double>{theta, s0, c0}.shifted(h);
    const Reference exact = Reference(theta) + Reference(h);
    worst = std::max({worst, double(abs(Reference(s) - sin(exact))), double(abs(Reference(c) - cos(exact)))});
  }
  INFO("worst absolute error " << worst);
  CHECK(worst <= 2 * DBL_EPSILON);
}

TEST_CASE("the phase in two doubles: theta + omega tau to 2^-104 of it, reduced within 1e-23 rad of MPFR's remainder") {
  // Flights of every length at every frequency (ω τ from 1e-6 to 1e15 rad: the three-part
  // reduction below 2²⁶·2π, MPFR beyond), the points beside multiples of 2π where the result
  // wraps, and negative phases.  Two doubles hold θ to 2⁻¹⁰⁶ of it (1e-18 rad at 10¹³ rad):
  // the advance is checked to that, the reduction against the exact value of what it is given.
  using dynamics::Phase;
  const Reference two_pi = boost::math::constants::two_pi<Reference>();
  auto exact_of = [](const Phase& p) { return Reference(p.hi) + Reference(p.lo); };
  auto as_phase = [](const Reference& x) {
    const double hi = double(x);
    return Phase(hi, double(Reference(x - hi)));
  };
  double worst_reduced = 0, worst_advanced = 0;
  bool in_range = true;
  auto check = [&](const Phase& theta) {
    const Phase r = dynamics::reduce_phase(theta);
    in_range = in_range && r.hi >= 0 && r.hi <= 0x1.921fb54442d18p+2 && std::abs(r.lo) <= std::abs(r.hi) * 0x1p-52;
    Reference exact = fmod(exact_of(theta), two_pi);
    if (exact < 0) exact += two_pi;
    Reference d = abs(exact_of(r) - exact);
    if (two_pi - d < d) d = two_pi - d;  // (a result within rounding of 2π is 0)
    worst_reduced = std::max(worst_reduced, double(d));
  };
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> unit(0, 1), exponent(-6, 15);
  for (int i = 0; i < 20000; ++i) {
    const Phase theta0 = dynamics::reduce_phase(Phase(6.28 * unit(rng)));
    const double omega = std::pow(10.0, 4 * unit(rng)), tau = std::pow(10.0, exponent(rng)) / omega;
    const Phase theta = dynamics::advance_phase(theta0, omega, tau);
    const Reference exact = exact_of(theta0) + Reference(omega) * Reference(tau);
    worst_advanced = std::max(worst_advanced, double(abs(exact_of(theta) - exact) / exact));
    check(theta);
  }
  for (long k : {1L, 2L, 1000L, 123456L, 16000000L, 60000000L, 1000000000L}) {
    for (double nudge : {-1e-20, -1e-25, 0.0, 1e-25, 1e-20}) {
      const Reference x = k * two_pi + nudge;
      check(as_phase(x));
      check(as_phase(-x));
    }
  }
  INFO("worst reduction " << worst_reduced << ", worst relative advance " << worst_advanced);
  CHECK(in_range);
  CHECK(worst_reduced <= 1e-23);
  CHECK(worst_advanced <= 0x1p-104);
}

TEST_CASE("reduce_phase in long double: within 2e-18 rad of MPFR's exact remainder by 2 pi, to 1e8 rad") {
  // Below 2²⁴·2π the reduction subtracts k·2π in two parts instead of calling fmod; it must
  // stay as accurate as fmod (which reduces by 2π rounded to 64 bits: off by k·2.5e-19), from
  // phases near 0 to 10⁸ rad, and beside multiples of 2π where the result wraps.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> exponent(-3, 8);
  std::vector<long double> thetas;
  for (int i = 0; i < 20000; ++i) thetas.push_back(std::pow(10.0L, (long double)exponent(rng)) * (i % 7 ? 1 : -1));
  for (long k : {1L, 2L, 1000L, 123456L, 16000000L}) {
    const long double edge = (long double)(k * boost::math::constants::two_pi<Reference>());
    for (long double t = std::nextafter(edge, 0.0L), n = 0; n < 3; t = std::nextafter(t, 1e30L), ++n) thetas.push_back(t);
  }
  const Reference two_pi = boost::math::constants::two_pi<Reference>();
  double worst = 0;
  for (const long double theta : thetas) {
    const Reference exact = fmod(fmod(Reference(theta), two_pi) + two_pi, two_pi);
    Reference d = abs(Reference(dynamics::reduce_phase(theta)) - exact);
    if (two_pi - d < d) d = two_pi - d;  // (a result within rounding of 2π is 0)
    worst = std::max(worst, double(d));
  }
  INFO("worst " << worst);
  CHECK(worst <= 2e-18);
}
