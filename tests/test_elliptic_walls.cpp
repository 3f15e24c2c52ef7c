// Elliptic walls in the collision core: every flight's exit time through an elliptic arc (the
// mapped flight's through a unit arc) against roots of the ellipse's own equation found without
// that map — in closed form in MPFR for straight flights, by a brute-force MPFR scan for the
// drive and the static force — and the circle as the ellipse with a = b.
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <boost/multiprecision/mpfr.hpp>
#include "brute_force_root.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace billiards;
using dynamics::Vec2;
using Real = boost::multiprecision::mpfr_float_100;

namespace {

const double pi = geometry::pi;

geometry::EllipticArc ellipse(Vec2 c, double a, double b, double angle, double start, double sweep) {
  geometry::EllipticArc e{c, Vec2(a, b), angle, start, sweep, Vec2::Zero(), Vec2::Zero()};
  e.source = e.point_at(start);
  e.target = e.point_at(start + sweep);
  return e;
}

/// The ellipse's implicit function q(x) − 1 at x, in T: > 0 outside.
template <class T>
T outside(const geometry::EllipticArc& e, const T& x, const T& y) {
  using std::cos;
  using std::sin;
  const T c = cos(T(e.angle)), s = sin(T(e.angle)), dx = x - e.center.x(), dy = y - e.center.y();
  const T u = (c * dx + s * dy) / e.semi_axes.x(), w = (-s * dx + c * dy) / e.semi_axes.y();
  return u * u + w * w - 1;
}


}  // namespace

TEST_CASE("straight flights leave a full ellipse at the larger root of its quadratic, solved in MPFR") {
  dynamics::ParticleRng rng(3, 0);
  for (int k = 0; k < 2000; ++k) {
    const auto e = ellipse(Vec2(rng.uniform() - 0.5, rng.uniform() - 0.5), 0.5 + 2 * rng.uniform(),
                           0.2 + rng.uniform(), 2 * pi * rng.uniform(), 0, 2 * pi);
    const dynamics::EllipticArcWall wall(e);
    // A point inside: the centre plus a fraction of the way to the ellipse.
    const double phi = 2 * pi * rng.uniform(), dir = 2 * pi * rng.uniform();
    dynamics::State s;
    s.x = e.center + rng.uniform() * (e.point_at(phi) - e.center);
    s.v = Vec2(std::cos(dir), std::sin(dir));
    const double got = dynamics::elliptic_exit_time(dynamics::FreeFlight{}, s, wall, dynamics::never);
    // q(x + v t) = 1: A t² + 2 B t + C = 0 in MPFR, the larger root.
    const auto q = [&](const Real& t) { return outside<Real>(e, Real(s.x.x()) + t * s.v.x(), Real(s.x.y()) + t * s.v.y()); };
    const Real C = q(Real(0)), qp = q(Real(1)), qm = q(Real(-1));
    const Real A = (qp + qm) / 2 - C, B = (qp - qm) / 4;
    const Real root = (-B + sqrt(B * B - A * C)) / A;
    INFO("case " << k);
    CHECK(std::abs(got - static_cast<double>(root)) <= 1e-13 * (1 + static_cast<double>(root)));
  }
}

TEST_CASE("forced flights' exit times through elliptic arcs equal a brute-force MPFR root scan") {
  dynamics::ParticleRng rng(11, 0);
  int compared = 0, missed = 0;
  for (const double omega : {2 * pi, 40 * pi, 640 * pi}) {
    for (int k = 0; k < 12; ++k) {
      // Focusing (region inside) and dispersing (region outside) arcs over part of the ellipse.
      const bool focusing = k % 2 == 0;
      const double start = 2 * pi * rng.uniform(), extent = (0.5 + 1.4 * rng.uniform()) * pi;
      const auto e = ellipse(Vec2(0.1, -0.2), 1.3, 0.6, 0.4, focusing ? start : start + extent,
                             focusing ? extent : -extent);
      const dynamics::EllipticArcWall wall(e);
      const double angle = 2 * pi * rng.uniform(), dir = 2 * pi * rng.uniform();
      const dynamics::PeriodicDriveFlight drive{8 * Vec2(std::cos(angle), std::sin(angle)), omega, 2 * pi * rng.uniform()};
      const dynamics::ConstantForceFlight gravity{2 * Vec2(std::cos(angle), std::sin(angle))};
      dynamics::State s0;
      s0.v = Vec2(std::cos(dir), std::sin(dir));
      s0.x = focusing ? Vec2(e.center + 0.3 * Vec2(rng.uniform() - 0.5, rng.uniform() - 0.5))
                      : Vec2(e.center + 2.5 * Vec2(std::cos(dir + pi), std::sin(dir + pi)));
      const double sign = focusing ? 1 : -1;
      // The outward gap along each flight, from its own closed form in T.
      const auto driven = [&]<class T>(const T& t) -> T {
        using std::cos;
        using std::sin;
        const T w = omega, th0 = T(drive.phase0), th = w * t + drive.phase0;
        T x[2];
        for (int i = 0; i < 2; ++i)
          x[i] = s0.x[i] + (s0.v[i] - drive.accel[i] / w * sin(th0)) * t - drive.accel[i] / (w * w) * (cos(th) - cos(th0));
        return sign * outside<T>(e, x[0], x[1]);
      };
      const auto parabola = [&]<class T>(const T& t) -> T {
        return sign * outside<T>(e, s0.x.x() + s0.v.x() * t + gravity.accel.x() * t * t / 2,
                                 s0.x.y() + s0.v.y() * t + gravity.accel.y() * t * t / 2);
      };
      const auto check = [&](double expected, double got, const auto& at, const char* what) {
        INFO(what << " omega " << omega << " case " << k << ": expected " << expected << ", got " << got);
        if (expected < 0) {
          CHECK(got == dynamics::never);
          return;
        }
        // A crossing outside the span is no collision: then the flight must not stop there.
        if (!wall.within_span(at(expected))) {
          CHECK(got != expected);
          ++missed;
          return;
        }
        CHECK(std::abs(got - expected) <= 1e-10 * (1 + expected));
        ++compared;
      };
      const double h = std::min(2 * pi / omega / 256, 1e-3);
      const auto s = drive.start(s0);
      const double root = brute_force::first_upward_root(driven, h, 3.0);
      auto at = [&](double t) { return drive.advance(s, t).x; };
      // The mapped flight's scan, and its search in windows (DrivenScan's, which the lanes share).
      check(root, dynamics::elliptic_exit_time(drive, s, wall, 3.0), at, "drive");
      check(root, drive.exit_time(s, wall, 3.0), at, "drive, in windows");
      check(brute_force::first_upward_root(parabola, 1e-3, 3.0), dynamics::elliptic_exit_time(gravity, s0, wall, 3.0),
            [&](double t) { return gravity.advance(s0, t).x; }, "static force");
    }
  }
  CHECK(compared > 30);
}

TEST_CASE("an elliptic arc with a = b is its circular arc") {
  dynamics::ParticleRng rng(5, 0);
  for (int k = 0; k < 500; ++k) {
    const Vec2 c(rng.uniform() - 0.5, rng.uniform() - 0.5);
    const double r = 0.5 + rng.uniform(), start = 2 * pi * rng.uniform(), sweep = (k % 2 ? 1 : -1) * pi * (0.5 + rng.uniform());
    const auto e = ellipse(c, r, r, 0, start, sweep);
    const geometry::Arc arc{c, r, start, sweep, e.source, e.target};
    const dynamics::EllipticArcWall as_ellipse(e);
    const dynamics::ArcWall as_circle(arc);
    const double dir = 2 * pi * rng.uniform();
    dynamics::State s;
    s.x = c + 2 * r * Vec2(rng.uniform() - 0.5, rng.uniform() - 0.5);
    s.v = Vec2(std::cos(dir), std::sin(dir));
    const double te = dynamics::elliptic_exit_time(dynamics::FreeFlight{}, s, as_ellipse, dynamics::never);
    const double tc = dynamics::FreeFlight{}.exit_time(s, as_circle, dynamics::never);
    INFO("case " << k);
    REQUIRE((te == dynamics::never) == (tc == dynamics::never));
    if (tc == dynamics::never) continue;
    CHECK(std::abs(te - tc) <= 1e-13 * (1 + tc));
    const Vec2 p = s.x + s.v * (tc - s.t);
    for (const auto& [pe, pc] : {std::pair{as_ellipse.contact(p, s.v), as_circle.contact(p, s.v)},
                                 std::pair{as_ellipse.radial_contact(p), as_circle.radial_contact(p)}}) {
      CHECK((pe.first - pc.first).norm() <= 1e-14 * (1 + c.norm()));
      CHECK((pe.second - pc.second).norm() <= 1e-14);
    }
    CHECK(std::abs(as_ellipse.curvature_at(p) - arc.curvature()) <= 1e-13 / r);
  }
}

TEST_CASE("the elliptic billiard conserves the product of the angular momenta about the foci") {
  // Integrable: L1 L2, Lᵢ = (x − fᵢ) × v, is conserved by the flight (angular momentum about
  // any point) and by the reflection (the caustic is a confocal conic).  Over N bounces its
  // drift relative to a² |v|² stays below c ε N: rounding, accumulated with a bias (it grows
  // linearly in N, not as the √N of a random walk; the circle's angular momentum does the same).
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/ellipse.yaml", {{"angle", "0.3"}});
  const dynamics::Table table(shape.region);
  const auto& e = std::get<geometry::EllipticArc>(shape.region.outer.pieces.front());
  const double a = e.semi_axes.x(), b = e.semi_axes.y(), focal = std::sqrt(a * a - b * b);
  const Vec2 axis(std::cos(e.angle), std::sin(e.angle)), f1 = e.center + focal * axis, f2 = e.center - focal * axis;
  const auto product = [&](const dynamics::State& s) {
    return geometry::cross(Vec2(s.x - f1), s.v) * geometry::cross(Vec2(s.x - f2), s.v);
  };
  constexpr std::size_t bounces = 2'000'000;
  constexpr double c = 400;
  for (std::uint64_t i = 0; i < 4; ++i) {
    dynamics::ParticleRng rng(29, i);
    const dynamics::State s0 = dynamics::sample_microcanonical(table, 1.0, rng);
    const double p0 = product(s0);
    double worst = 0, worst_tenth = 0;
    std::size_t k = 0;
    const std::size_t made = dynamics::evolve(table, dynamics::FreeFlight{}, s0, bounces, [&](const auto&, const auto& s) {
      worst = std::max(worst, std::abs(product(s) - p0));
      if (++k == bounces / 10) worst_tenth = worst;
    });
    const double eps = std::numeric_limits<double>::epsilon();
    INFO("particle " << i << ": L1 L2 = " << p0 << ", largest drift " << worst / (a * a) << " after " << bounces
                     << " bounces, " << worst_tenth / (a * a) << " after a tenth of them");
    REQUIRE(made == bounces);
    CHECK(worst_tenth / (a * a) <= c * eps * double(bounces / 10));
    CHECK(worst / (a * a) <= c * eps * double(bounces));
  }
}
