// Magnetic flights (2-D, B perpendicular to the plane): the cyclotron orbit's closed forms, exit
// times against circle–line and circle–circle intersections solved in MPFR and against a
// brute-force MPFR scan, hits within ulps of joints and at grazing incidence, energy over 1e7
// collisions, Santaló's collision rate, and the scene file's checks.
#include "billiards/analysis/coefficients.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/follow.hpp"
#include "billiards/dynamics/magnetic_flight.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/dynamics/scene.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/shape_file.hpp"

#include "brute_force_root.hpp"
#include "energy_moments.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>

using namespace billiards;
using dynamics::Vec2;
using dynamics::Vec2T;
using MP = brute_force::Real;

namespace {

const double pi = geometry::pi;

dynamics::Table table_of(const std::string& yaml) { return dynamics::Table(geometry::parse_shape(yaml, "test").region); }

geometry::Arc full_circle(Vec2 c, double r, bool focusing) {
  geometry::Arc a{c, r, 0, focusing ? 2 * pi : -2 * pi, c + Vec2(r, 0), c + Vec2(r, 0)};
  return a;
}

/// The orbit in T, independently of the flight's formula: x(τ) = c + R(−Ωτ)(x0 − c) with the
/// centre c = x0 − J v0/Ω.
template <class T>
std::pair<T, T> orbit_point(const dynamics::State& s, double omega, const T& tau) {
  using std::cos;
  using std::sin;
  const T W = omega, cx = T(s.x.x()) + T(s.v.y()) / W, cy = T(s.x.y()) - T(s.v.x()) / W;
  const T rx = T(s.x.x()) - cx, ry = T(s.x.y()) - cy, c = cos(W * tau), sn = sin(W * tau);
  return {cx + c * rx + sn * ry, cy - sn * rx + c * ry};
}

/// The angle swept by the orbit from x0 to the point (px, py) on it, in [0, 2π), in MPFR.
MP swept(const dynamics::State& s, double omega, const MP& px, const MP& py) {
  const MP W = omega, cx = MP(s.x.x()) + MP(s.v.y()) / W, cy = MP(s.x.y()) - MP(s.v.x()) / W;
  const MP a0 = atan2(MP(s.x.y()) - cy, MP(s.x.x()) - cx), a1 = atan2(py - cy, px - cx);
  MP turn = omega > 0 ? MP(a0 - a1) : MP(a1 - a0);  // clockwise for Ω > 0
  const MP two_pi = 2 * boost::multiprecision::mpfr_float_100(boost::math::constants::pi<MP>());
  while (turn < 0) turn += two_pi;
  while (turn >= two_pi) turn -= two_pi;
  return turn;
}

/// The first time at which the orbit enters the disk (cw, r) (a dispersing wall), from the
/// circle–circle intersection in MPFR; −1 if the circles do not meet.
double enter_disk_exactly(const dynamics::State& s, double omega, Vec2 cw, double r) {
  const MP W = omega, cx = MP(s.x.x()) + MP(s.v.y()) / W, cy = MP(s.x.y()) - MP(s.v.x()) / W;
  const MP rho = sqrt(MP(s.v.x()) * s.v.x() + MP(s.v.y()) * s.v.y()) / abs(W);
  const MP dx = MP(cw.x()) - cx, dy = MP(cw.y()) - cy, d = sqrt(dx * dx + dy * dy);
  const MP a = (d * d + rho * rho - MP(r) * r) / (2 * d), h2 = rho * rho - a * a;
  if (h2 <= 0) return -1;
  const MP h = sqrt(h2), mx = cx + a * dx / d, my = cy + a * dy / d;
  const MP t1 = swept(s, omega, mx + h * dy / d, my - h * dx / d), t2 = swept(s, omega, mx - h * dy / d, my + h * dx / d);
  return static_cast<double>((t1 < t2 ? t1 : t2) / abs(W));
}

dynamics::State random_state(dynamics::ParticleRng& rng, Vec2 centre, double spread, double speed) {
  dynamics::State s;
  const double a = 2 * pi * rng.uniform();
  s.x = centre + spread * Vec2(rng.uniform() - 0.5, rng.uniform() - 0.5);
  s.v = speed * Vec2(std::cos(a), std::sin(a));
  return s;
}

}  // namespace

TEST_CASE("far from the walls a charge circles forever, back at its start after 2π/Ω") {
  const auto table = table_of("boundary:\n  circle: {center: [0, 0], radius: 100}\n");
  for (const double omega : {1.0, -3.0, 1e-3 * 50}) {
    const dynamics::MagneticFlight flight{omega};
    dynamics::State s;
    s.x = Vec2(0.3, -0.2);
    s.v = Vec2(0.6, 0.8) * (omega == 0.05 ? 2.0 : 1.0);  // r_c = 1, 1/3, 40: all inside
    CHECK_FALSE(dynamics::collision(table, flight, s).found());
    const auto back = flight.advance(s, flight.period());
    CHECK((back.x - s.x).norm() <= 1e-13 * (1 + s.v.norm() / std::abs(omega)));
    CHECK((back.v - s.v).norm() <= 1e-14);
    // Half a turn: the diametrically opposite point, velocity reversed.
    const auto half = flight.advance(s, flight.period() / 2);
    CHECK((half.v + s.v).norm() <= 1e-14);
    CHECK(std::abs((half.x - s.x).norm() - 2 * s.v.norm() / std::abs(omega)) <= 1e-12 * s.v.norm() / std::abs(omega));
    // Followed with no end time, it is trapped (it circles inside), not escaped.
    const auto made = dynamics::follow(table, flight, s, {10, dynamics::never}, dynamics::SampleClock{},
                                       [](const auto&, const auto&) {}, [](const auto&) {});
    CHECK(made.trapped);
    CHECK_FALSE(made.escaped);
    CHECK(made.collisions == 0);
  }
}

TEST_CASE("a skipping orbit along a flat wall hits it at spacing 2 r_c sin α") {
  const auto table = table_of("boundary:\n  polygon: [[-1e4, 0], [1e4, 0], [1e4, 1e4], [-1e4, 1e4]]\n");
  for (const double alpha : {1e-6, 0.01, 0.3, 1.2, 2.5, 3.1}) {
    const double omega = 2.0, speed = 1.5, rc = speed / omega;
    const dynamics::MagneticFlight flight{omega};  // clockwise: moving along +x it turns down into y = 0
    dynamics::State s;
    s.x = Vec2(-9000, 0);
    s.v = speed * Vec2(std::cos(alpha), std::sin(alpha));
    const double spacing = 2 * rc * std::sin(alpha);
    int n = 0;
    dynamics::evolve(table, flight, s, 1000, [&](const dynamics::Hit& hit, const dynamics::State& after) {
      ++n;
      INFO("alpha " << alpha << " bounce " << n);
      REQUIRE(hit.wall == dynamics::WallId{dynamics::wall_kind::segment, 0});
      CHECK(std::abs(hit.point.x() - (-9000 + n * spacing)) <= 1e-12 * 9000 + 4e-15 * n * spacing);
      // α walks by the rounding of the flight times (absolute, ~ε t each, turned into an angle by
      // k): a random walk.
      const double step = 4 * std::numeric_limits<double>::epsilon() * omega * hit.t * speed;
      CHECK(std::abs(after.v.y() - s.v.y()) <= step * std::sqrt(double(n)));
    });
    CHECK(n == 1000);
  }
}

TEST_CASE("exit times through lines and circles equal their intersections with the cyclotron circle, in MPFR") {
  dynamics::ParticleRng rng(25, 0);
  int hits = 0;
  for (int k = 0; k < 4000; ++k) {
    const double omega = (k % 2 ? 1 : -1) * std::exp(4 * rng.uniform() - 2);
    const dynamics::MagneticFlight flight{omega};
    const auto s = random_state(rng, Vec2::Zero(), 1.0, 0.2 + rng.uniform());
    INFO("case " << k << " omega " << omega);
    // A dispersing circle (a scatterer): entered at the first intersection reached.
    const Vec2 cw(1.2 * (rng.uniform() - 0.5) + 1.5, rng.uniform() - 0.5);
    const double r = 0.2 + rng.uniform();
    if ((s.x - cw).norm() <= r) continue;
    const dynamics::ArcWall scatterer(full_circle(cw, r, false));
    const double exact = enter_disk_exactly(s, omega, cw, r), got = flight.exit_time(s, scatterer, dynamics::never);
    if (exact < 0) {
      CHECK(got == dynamics::never);
    } else {
      ++hits;
      CHECK(std::abs(got - exact) <= 1e-12 * (1 + exact));
    }
    // A line y = h below the particle, region above: the crossing where the orbit goes down.
    const double h = -1 - rng.uniform();
    const dynamics::SegmentWall line(geometry::Segment{Vec2(-1e3, h), Vec2(1e3, h)});
    const double t_line = flight.exit_time(s, line, dynamics::never);
    const MP W = omega, cy = MP(s.x.y()) - MP(s.v.x()) / W;
    const MP rho = sqrt(MP(s.v.x()) * s.v.x() + MP(s.v.y()) * s.v.y()) / abs(W), depth = cy - h;
    if (depth >= rho) {
      CHECK(t_line == dynamics::never);
    } else {
      const MP cx = MP(s.x.x()) + MP(s.v.y()) / W, half = sqrt(rho * rho - depth * depth);
      // Clockwise (Ω > 0) the orbit goes down on its right side, counter-clockwise on its left.
      const MP px = omega > 0 ? MP(cx + half) : MP(cx - half);
      const double want = static_cast<double>(swept(s, omega, px, MP(h)) / abs(W));
      CHECK(std::abs(t_line - want) <= 1e-12 * (1 + want));
    }
  }
  CHECK(hits > 500);
}

TEST_CASE("the half angle's arctangent is atan2 to 2 ulps in MPFR, over every direction of the upper half plane") {
  // Directions at every angle of [0, π] and every scale, the reduction's thresholds
  // (tan ψ = 0.66 and tan(3π/8)) and the axes among them.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  const dynamics::ScalarLanes<double> l;
  double worst = 0;
  auto check = [&](double x, double y) {
    const double psi = dynamics::half_angle_of(l, dynamics::HalfAngle<double>{x, y});
    const MP exact = boost::multiprecision::atan2(MP(y), MP(x));
    const double ulp = std::nextafter(double(exact), 4.0) - double(exact);
    worst = std::max(worst, double(abs(MP(psi) - exact) / ulp));
  };
  for (int i = 0; i < 200000; ++i) {
    const double angle = pi * unit(rng), scale = std::ldexp(1.0, int(600 * unit(rng)) - 300);
    check(scale * std::cos(angle), scale * std::sin(angle));
  }
  for (const double t : {0.66, 2.41421356237309504880})
    for (int k = -200; k <= 200; ++k) check(1.0, std::nextafter(t, 0.0) + k * 1e-16), check(-1.0, t + k * 1e-16);
  for (const double y : {0.0, 1e-300, 1e-20, 1.0}) check(1.0, y), check(-1.0, y), check(y, 1.0);
  CHECK(worst <= 2);
  CHECK(dynamics::half_angle_of(l, dynamics::HalfAngle<double>{1, 0}) == 0);
  CHECK(dynamics::half_angle_of(l, dynamics::HalfAngle<double>{0, 1}) == pi / 2);
  CHECK(dynamics::half_angle_of(l, dynamics::HalfAngle<double>{-1, 0}) == pi);
  INFO("worst error " << worst << " ulps");
  CHECK(worst > 0);  // (the check itself sees rounding)
}

TEST_CASE("exit times through circles, lines and ellipses equal a brute-force MPFR scan of the orbit") {
  dynamics::ParticleRng rng(26, 0);
  const geometry::EllipticArc ellipse{Vec2(0.1, -0.2), Vec2(1.3, 0.6), 0.4, 0, 2 * pi, Vec2::Zero(), Vec2::Zero()};
  geometry::EllipticArc e = ellipse;
  e.source = e.target = e.point_at(0);
  const dynamics::EllipticArcWall oval(e);
  const dynamics::ArcWall disk(full_circle(Vec2(0.1, 0.2), 1.1, true));
  const Vec2 n = Vec2(1, 2).normalized();
  const dynamics::SegmentWall line(geometry::Segment{Vec2(0.5, 0.5) + 1e3 * Vec2(n.y(), -n.x()), Vec2(0.5, 0.5) - 1e3 * Vec2(n.y(), -n.x())});
  for (int k = 0; k < 60; ++k) {
    const double omega = (k % 2 ? 1 : -1) * std::exp(3 * rng.uniform() - 1);
    const dynamics::MagneticFlight flight{omega};
    const auto s = random_state(rng, Vec2(0.1, -0.2), 0.6, 0.5 + rng.uniform());
    const double turn = flight.period(), h = turn / 20000;
    INFO("case " << k << " omega " << omega);
    // Each wall's gap along the orbit, > 0 beyond it.
    auto ellipse_gap = [&]<class T>(const T& tau) {
      using std::cos;
      using std::sin;
      const auto [x, y] = orbit_point(s, omega, tau);
      const T c = cos(T(e.angle)), sn = sin(T(e.angle)), dx = x - e.center.x(), dy = y - e.center.y();
      const T u = (c * dx + sn * dy) / e.semi_axes.x(), w = (-sn * dx + c * dy) / e.semi_axes.y();
      return T(u * u + w * w - 1);
    };
    auto circle_gap = [&]<class T>(const T& tau) {
      const auto [x, y] = orbit_point(s, omega, tau);
      return T((x - 0.1) * (x - 0.1) + (y - 0.2) * (y - 0.2) - T(1.1) * T(1.1));
    };
    auto line_gap = [&]<class T>(const T& tau) {
      const auto [x, y] = orbit_point(s, omega, tau);
      return T((x - 0.5) + 2 * (y - 0.5));  // ∝ n·(x − a), n = (1, 2)/√5
    };
    auto compare = [&](double got, double want) {
      if (want < 0) {
        CHECK(got == dynamics::never);
      } else {
        CHECK(std::abs(got - want) <= 1e-11 * (1 + want));
      }
    };
    if (ellipse_gap(0.0L) < 0) compare(flight.exit_time(s, oval, dynamics::never), brute_force::first_upward_root(ellipse_gap, h, turn));
    if (circle_gap(0.0L) < 0) compare(flight.exit_time(s, disk, dynamics::never), brute_force::first_upward_root(circle_gap, h, turn));
    // (The line runs along (−n.y, n.x), whose right is n: its region is on n's other side.)
    if (line_gap(0.0L) < 0) compare(flight.exit_time(s, line, dynamics::never), brute_force::first_upward_root(line_gap, h, turn));
  }
}

TEST_CASE("hits within ulps of a corner are found by one of the two walls, at the right time") {
  const auto table = table_of("boundary:\n  polygon: [[0, 0], [2, 0], [2, 2], [0, 2]]\n");
  dynamics::ParticleRng rng(27, 0);
  const Vec2 corners[] = {Vec2(0, 0), Vec2(2, 0), Vec2(2, 2), Vec2(0, 2)};
  int tested = 0;
  for (int k = 0; k < 4000; ++k) {
    const double omega = (k % 2 ? 1 : -1) * std::exp(2 * rng.uniform() - 1);
    const dynamics::MagneticFlight flight{omega};
    // Arrive at a corner (moved by a few ulps along either wall) from inside, then fly back.
    const Vec2 corner = corners[k % 4];
    const Vec2 inward = (Vec2(1, 1) - corner).normalized();
    const double spread = std::atan(1.0) * 0.7, a = std::atan2(-inward.y(), -inward.x()) + spread * (2 * rng.uniform() - 1);
    dynamics::State at;
    const int ulps = int(rng.uniform() * 9) - 4;
    at.x = corner + ulps * 4e-16 * (k % 8 < 4 ? Vec2(1, 0) : Vec2(0, 1)).cwiseProduct(inward.cwiseSign());
    at.v = Vec2(std::cos(a), std::sin(a));
    const double T = 0.05 + 0.15 * rng.uniform();
    auto s = flight.advance(at, -T);
    s.t = 0;
    bool inside = true;  // (the arc back from the corner stays in the square: no earlier hit)
    for (int j = 0; j < 8; ++j) inside = inside && table.contains(flight.advance(s, T * j / 8).x);
    if (!inside) continue;
    const auto hit = dynamics::collision(table, flight, s);
    INFO("case " << k);
    ++tested;
    REQUIRE(hit.found());
    CHECK(std::abs(hit.t - T) <= 1e-13);
    CHECK((hit.point - corner).norm() <= 1e-13);
  }
  CHECK(tested > 2000);
}

TEST_CASE("grazing a scatterer: crossings deeper than rounding are hits at the MPFR time, misses are misses") {
  dynamics::ParticleRng rng(28, 0);
  int hits = 0, misses = 0;
  for (int k = 0; k < 3000; ++k) {
    const double omega = (k % 2 ? 1 : -1) * (0.5 + rng.uniform()), speed = 1;
    const dynamics::MagneticFlight flight{omega};
    dynamics::State s;
    s.x = Vec2::Zero();
    const double a = 2 * pi * rng.uniform();
    s.v = speed * Vec2(std::cos(a), std::sin(a));
    const auto g = flight.scan_from(s);
    // The scatterer's centre at distance r + ρ ± δ from the orbit's centre (tangent outside),
    // or |r − ρ| ± δ (tangent inside the orbit), δ from 1e-3 down to 1e-12 relative.
    const double r = 0.3 + rng.uniform(), delta = std::pow(10.0, -3 - 9 * rng.uniform()) * (k % 4 < 2 ? 1 : -1);
    const double d = (k % 8 < 4 ? r + g.radius : std::abs(r - g.radius)) + delta;
    const double b = 2 * pi * rng.uniform();
    const Vec2 cw = g.center + d * Vec2(std::cos(b), std::sin(b));
    if ((s.x - cw).norm() <= r * (1 + 1e-6)) continue;
    const dynamics::ArcWall scatterer(full_circle(cw, r, false));
    const double got = flight.exit_time(s, scatterer, dynamics::never), exact = enter_disk_exactly(s, omega, cw, r);
    INFO("case " << k << " delta " << delta);
    if (std::abs(delta) < 1e-10) continue;  // within the rounding of the centre: either answer
    if (exact < 0) {
      ++misses;
      CHECK(got == dynamics::never);
    } else {
      ++hits;
      REQUIRE(got != dynamics::never);
      // The root of a shallow crossing is ill-conditioned: its time moves by ~ rounding/√δ.
      CHECK(std::abs(got - exact) <= 1e-13 / std::sqrt(std::abs(delta)) * (1 + exact));
    }
  }
  CHECK(hits > 500);
  CHECK(misses > 500);
}

TEST_CASE("a magnetic field conserves the speed over 1e7 collisions in the clover, and no particle escapes") {
  const auto table = dynamics::Table(geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml").region);
  const dynamics::MagneticFlight flight{1.7};
  dynamics::ParticleRng rng(29, 0);
  const auto s = dynamics::sample_microcanonical(table, 1.0, rng);
  constexpr long n = 10000000;
  const double drift = speed_change(table, flight, s, n).sum;
  // Rounding of a rotation per flight: a random walk (1.3 ε per flight, so ~1.3 √n ε) and a
  // bias d ε n within d = 0.01 (measured −0.0034 ± 0.0004 ε per flight); c = 10.  Runs also
  // restore the speed after every bounce (conserves_energy), so nothing accumulates in them.
  // (The +0.11 ε per flight once seen here was the measure's: v² ratios rounded in double.)
  INFO("relative change of v² over the flights " << drift);
  const double eps = std::numeric_limits<double>::epsilon();
  CHECK(std::abs(drift) <= 0.01 * eps * double(n) + 10 * std::sqrt(double(n)) * eps);
}

TEST_CASE("Santaló: collisions per unit time are v/λ; with r_c below the inradius the orbits inside never collide") {
  for (const char* shape : {"clover", "stadium"}) {
    const auto region = geometry::load_shape(std::string(BILLIARDS_SOURCE_DIR "/shapes/") + shape + ".yaml").region;
    const dynamics::Table table(region);
    const auto measures = geometry::measures_of(region);
    const double lambda = geometry::mean_free_path(measures);
    for (const double rc : {20.0, 0.1}) {  // r_c ≫ the table's size; r_c below its inradius
      const dynamics::MagneticFlight flight{1 / rc};
      dynamics::RunOptions opt;
      const double T = 30;  // ≫ one turn at r_c = 0.1 and the longest flight at r_c = 20
      opt.record_times = {0, T};
      opt.verify_every_flight = true;
      const std::size_t N = 20000;
      const auto result = dynamics::run_ensemble(table, flight, dynamics::microcanonical(table, flight, 1.0, 7), opt, N, 2);
      REQUIRE(result.escapes() == 0);
      double sum = 0, sum2 = 0, never_collided = 0;
      for (const auto& log : result.logs) {
        const double x = double(log.collisions) / T * lambda;  // × λ/v, v = 1
        sum += x, sum2 += x * x, never_collided += log.collisions == 0;
      }
      // The rate is the flux through the wall of the uniform, isotropic density, whatever the
      // flight: trapped orbits make none of it, skipping ones more.
      const double mean = sum / N, se = std::sqrt((sum2 / N - mean * mean) / (N - 1));
      INFO(shape << " r_c " << rc << ": rate × λ/v = " << mean << " ± " << se << ", never collided " << never_collided);
      CHECK(std::abs(mean - 1) <= 4 * se);
      if (rc > 1) {
        CHECK(never_collided == 0);
      } else if (std::string(shape) == "stadium") {
        // An orbit never meets the wall iff its centre is farther than r_c from it: the
        // centres are uniform there, so the fraction is the area of the stadium shrunk by r_c
        // (a = r = 1) over the stadium's.
        const double p = (4 * (1 - rc) + pi * (1 - rc) * (1 - rc)) / measures.volume;
        CHECK(std::abs(never_collided / N - p) <= 4 * std::sqrt(p * (1 - p) / N));
      }
    }
  }
}

TEST_CASE("magnetic scenes: B and charge read with expressions; bad input is refused naming file and line") {
  const std::string head = "shape: " BILLIARDS_SOURCE_DIR "/shapes/clover.yaml\nparameters:\n  B0: 2\nmass: 2\n";
  const std::string tail = "initial:\n  microcanonical: {energy: 1/2}\nrun:\n  particles: 10\n  time: 1\n";
  const auto scene = dynamics::parse_scene(head + "magnetic: {B: 3*B0}\ncharge: -1/2\n" + tail, "s.yaml", ".");
  REQUIRE(scene.magnetic());
  CHECK(scene.cyclotron_frequency() == -1.5);  // qB/m = (−1/2)(6)/2
  dynamics::with_flight(scene, [](const auto& flight) {
    if constexpr (std::is_same_v<std::decay_t<decltype(flight)>, dynamics::MagneticFlight>) CHECK(flight.omega_c == -1.5);
    else FAIL("not a magnetic flight");
  });
  dynamics::SceneOverrides ov;
  ov.set["B0"] = "0";
  CHECK_FALSE(dynamics::parse_scene(head + "magnetic: {B: 3*B0}\n" + tail, "s.yaml", ".", ov).magnetic());

  auto refused = [&](const std::string& text, const std::string& what) {
    INFO(text);
    CHECK_THROWS_WITH(dynamics::parse_scene(text, "s.yaml", "."), Catch::Contains(what));
  };
  refused(head + "magnetic: {B: [0, 0, 1]}\n" + tail, "s.yaml:5: in 2-D the magnetic field is perpendicular");
  refused("shape: " BILLIARDS_SOURCE_DIR "/shapes/3d/cube.yaml\nmagnetic: {B: 1}\n" + tail, "s.yaml:2: in 3-D the magnetic field is a vector");
  refused(head + "magnetic: {B: 1}\ncharge: 0\n" + tail, "s.yaml:6: the charge must not be 0");
  refused(head + "magnetic: {B: 1/0}\n" + tail, "s.yaml:5");
  refused(head + "magnetic: {B: 1}\ncharge: nan\n" + tail, "s.yaml:6");
  refused(head + "magnetic: {B: 1, E: 2}\n" + tail, "s.yaml:5: unknown key 'E'");
  refused(head + "charge: 1\n" + tail, "s.yaml:5: 'charge' is the charge in a magnetic field");
}

// ---- The field and a uniform force ----------------------------------------------------------

namespace {

/// v̇ = −Ω J v + a cos(ωt + φ0) integrated by classical Runge–Kutta in long double with n steps:
/// an independent check of the closed form.
std::pair<Vec2, Vec2> integrated(const dynamics::MagneticDriveFlight& f, const dynamics::State& s, double tau, int n) {
  using L = long double;
  L x = s.x.x(), y = s.x.y(), vx = s.v.x(), vy = s.v.y();
  const L W = f.omega_c, h = L(tau) / n;
  auto rhs = [&](L t, L ux, L uy, L& ax, L& ay) {
    const L c = std::cos(L(f.omega) * (L(s.t) + t) + L(f.phase0));
    ax = W * uy + f.accel.x() * c;  // −Ω J v = Ω (v_y, −v_x)
    ay = -W * ux + f.accel.y() * c;
  };
  for (int k = 0; k < n; ++k) {
    const L t = k * h;
    L a1x, a1y, a2x, a2y, a3x, a3y, a4x, a4y;
    rhs(t, vx, vy, a1x, a1y);
    rhs(t + h / 2, vx + h / 2 * a1x, vy + h / 2 * a1y, a2x, a2y);
    rhs(t + h / 2, vx + h / 2 * a2x, vy + h / 2 * a2y, a3x, a3y);
    rhs(t + h, vx + h * a3x, vy + h * a3y, a4x, a4y);
    x += h / 6 * (vx + 2 * (vx + h / 2 * a1x) + 2 * (vx + h / 2 * a2x) + (vx + h * a3x));
    y += h / 6 * (vy + 2 * (vy + h / 2 * a1y) + 2 * (vy + h / 2 * a2y) + (vy + h * a3y));
    vx += h / 6 * (a1x + 2 * a2x + 2 * a3x + a4x);
    vy += h / 6 * (a1y + 2 * a2y + 2 * a3y + a4y);
  }
  return {Vec2(double(x), double(y)), Vec2(double(vx), double(vy))};
}

}  // namespace

TEST_CASE("the field with a static or periodic force: the closed form equals an integration, at resonance too") {
  dynamics::ParticleRng rng(30, 0);
  for (const double omega_c : {1.3, -2.0}) {
    // Static, fast, resonant (ω = |Ω|), within 1e-9 of resonance, slow.
    for (const double omega : {0.0, 40 * pi, std::abs(omega_c), std::abs(omega_c) * (1 + 1e-9), 0.3}) {
      const dynamics::MagneticDriveFlight f{omega_c, Vec2(3, -2), omega, 0.7};
      dynamics::State s;
      s.x = Vec2(0.2, 0.1);
      s.v = Vec2(rng.uniform() - 0.5, rng.uniform() - 0.5);
      s.t = 1.25;
      const double tau = 3.7;
      const auto r = f.advance(f.start(s), s.t + tau);
      const auto [x, v] = integrated(f, s, tau, omega > 10 ? 200000 : 20000);
      INFO("Ω " << omega_c << " ω " << omega);
      CHECK((r.x - x).norm() <= 1e-11 * (1 + x.norm()));
      CHECK((r.v - v).norm() <= 1e-11 * (1 + v.norm()));
    }
  }
  // At resonance the energy grows secularly: |v| ~ |a| τ/2 once the drive dominates.
  const dynamics::MagneticDriveFlight resonant{2.0, Vec2(1, 0), 2.0, 0};
  dynamics::State s;
  s.v = Vec2(1e-3, 0);
  const double tau = 1000 * 2 * pi / 2;
  CHECK(resonant.advance(resonant.start(s), tau).v.norm() == Approx(tau / 2).epsilon(1e-3));
}

TEST_CASE("exit times of the field with a force through lines, circles and ellipses equal a brute-force scan") {
  dynamics::ParticleRng rng(31, 0);
  geometry::EllipticArc e{Vec2(0.1, -0.2), Vec2(1.3, 0.6), 0.4, 0, 2 * pi, Vec2::Zero(), Vec2::Zero()};
  e.source = e.target = e.point_at(0);
  const dynamics::EllipticArcWall oval(e);
  const dynamics::ArcWall disk(full_circle(Vec2(0.1, -0.2), 1.1, true));
  // y = −0.9 run towards +x: its normal (right of travel) points down, the region is above.
  const dynamics::SegmentWall line(geometry::Segment{Vec2(-1e3, -0.9), Vec2(1e3, -0.9)});
  int compared = 0;
  for (int k = 0; k < 48; ++k) {
    const double omega_c = (k % 2 ? 1 : -1) * (0.5 + 2 * rng.uniform());
    const double omega = k % 3 == 0 ? 0.0 : k % 3 == 1 ? 40 * pi : std::abs(omega_c);
    const double angle = 2 * pi * rng.uniform();
    const dynamics::MagneticDriveFlight f{omega_c, 3 * Vec2(std::cos(angle), std::sin(angle)), omega, 2 * pi * rng.uniform()};
    const dynamics::BasicMagneticDriveFlight<long double> fl{omega_c, f.accel.cast<long double>(), omega, f.phase0};
    const auto s = f.start(random_state(rng, Vec2(0.1, -0.2), 0.5, 0.5 + rng.uniform()));
    const auto sl = fl.start({s.x.cast<long double>(), s.v.cast<long double>(), 0});
    const double horizon = 6, h = 2 * pi / std::max(std::abs(omega_c), omega) / 200;
    INFO("case " << k << " Ω " << omega_c << " ω " << omega);
    // The gaps along the flight, evaluated by the long double closed form (the brute force's
    // bisection then resolves the root to long double's rounding).
    auto along = [&](auto gap) {
      return [&, gap]<class T>(const T& tau) { return T(gap(fl.advance(sl, (long double)(tau)).x)); };
    };
    auto ellipse_gap = along([&](const Vec2T<long double>& x) {
      const long double c = std::cos((long double)e.angle), sn = std::sin((long double)e.angle);
      const long double dx = x.x() - e.center.x(), dy = x.y() - e.center.y();
      const long double u = (c * dx + sn * dy) / e.semi_axes.x(), w = (-sn * dx + c * dy) / e.semi_axes.y();
      return u * u + w * w - 1;
    });
    auto circle_gap = along([](const Vec2T<long double>& x) { return (x - Vec2T<long double>(0.1, -0.2)).squaredNorm() - 1.21L; });
    auto line_gap = along([](const Vec2T<long double>& x) { return -0.9L - x.y(); });
    auto compare = [&](double got, double want) {
      ++compared;
      if (want < 0) {
        CHECK(got == dynamics::never);
      } else {
        CHECK(std::abs(got - want) <= 1e-10 * (1 + want));
      }
    };
    if (ellipse_gap(0.0L) < 0) compare(f.exit_time(s, oval, horizon), brute_force::first_upward_root(ellipse_gap, h, horizon));
    compare(f.exit_time(s, disk, horizon), brute_force::first_upward_root(circle_gap, h, horizon));
    compare(f.exit_time(s, line, horizon), brute_force::first_upward_root(line_gap, h, horizon));
  }
  CHECK(compared > 120);
}

TEST_CASE("collision() meets elliptic arcs in a field with a force on the flight itself, not on an affine image") {
  // An affine map takes the cyclotron circle to an ellipse: the field's flights are no uniform
  // acceleration's, and must not borrow its elliptic exit time from the unit circle.
  STATIC_REQUIRE(!dynamics::affine_covariant<dynamics::MagneticDriveFlight>);
  const auto sh = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/sinai-ellipse.yaml");
  const dynamics::Table table(sh.region);
  int elliptic = 0;
  for (const dynamics::MagneticDriveFlight& f :
       {dynamics::MagneticDriveFlight{0.8, Vec2(0.4, -0.9)}, dynamics::MagneticDriveFlight{-0.8, Vec2(1.5, 1), 7, 0.3}}) {
    const auto initial = dynamics::microcanonical(table, f, 1.0, 5);
    for (std::size_t i = 0; i < 4; ++i) {
      auto s = initial(i);
      for (int k = 0; k < 30; ++k) {
        const auto hit = dynamics::collision(table, f, s, s.t + 100);
        REQUIRE(hit.found());
        INFO("particle " << i << ", collision " << k);
        CHECK((f.advance(s, hit.t).x - hit.point).norm() < 1e-9);  // (the contact projects onto the wall)
        elliptic += hit.wall.kind == dynamics::wall_kind::elliptic_arc;
        dynamics::bounce(f, s, hit);
      }
    }
  }
  CHECK(elliptic > 20);
}

// The paper's prediction with a weak field: every orbit meets the wall (r_c ≈ 2 at E0 = 1/2,
// the clover's size ~2), and ω = 40π ≫ Ω = 1/2, so the drive averages as without a field.
TEST_CASE("driven clover in a weak field at ω ≫ Ω: <ΔE> and Var ΔE equal g1 Δt and g2 Δt") {
  const auto region = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml").region;
  const double F = 10, omega = 40 * pi;
  const Vec2 amplitude = Vec2(F, F) / std::sqrt(2.0);
  check_energy_moments(dynamics::Table(region), dynamics::MagneticDriveFlight{0.5, amplitude, omega, 0},
                       geometry::measures_of(region), amplitude, omega, 4, 6000);
}

TEST_CASE("magnetic scenes with forces: constant and periodic run as MagneticDriveFlight; the rest is refused") {
  const std::string head = "shape: " BILLIARDS_SOURCE_DIR "/shapes/clover.yaml\nmagnetic: {B: 2}\n";
  const std::string tail = "initial:\n  microcanonical: {energy: 1/2}\nrun:\n  particles: 10\n  time: 1\n";
  for (const std::string force : {"force: {constant: {amplitude: [1, 2]}}\n", "force: {periodic: {amplitude: [1, 2], omega: 9}}\n"}) {
    const auto scene = dynamics::parse_scene(head + force + tail, "s.yaml", ".");
    dynamics::with_flight(scene, [&](const auto& flight) {
      if constexpr (std::is_same_v<std::decay_t<decltype(flight)>, dynamics::MagneticDriveFlight>) {
        CHECK(flight.omega_c == 2);
        CHECK(flight.accel == Vec2(1, 2));
        CHECK(flight.omega == (scene.force.kind == dynamics::Force::Kind::periodic ? 9 : 0));
      } else {
        FAIL("not a magnetic flight with a force");
      }
    });
  }
  auto refused = [&](const std::string& text, const std::string& what) {
    INFO(text);
    CHECK_THROWS_WITH(dynamics::parse_scene(text, "s.yaml", "."), Catch::Contains(what));
  };
  refused(head + "force: {field: {amplitude: [x, y], omega: 9}}\n" + tail, "s.yaml:2: a magnetic field is implemented with a uniform force only");
  refused(head + "force: {periodic: {amplitude: [1, 2], omega: 9, picture: quivering-walls}}\n" + tail, "not with quivering walls");
  refused(head + "potential: {expression: x^2}\n" + tail, "not with a potential");
}

TEST_CASE("coeffs in a magnetic field: the validity statement names r_c against the inradius and ω against Ω") {
  auto predict = [](const std::string& B, const std::string& omega) {
    const std::string text = "shape: " BILLIARDS_SOURCE_DIR "/shapes/stadium.yaml\nmagnetic: {B: " + B +
                             "}\nforce: {periodic: {amplitude: [1, 0], omega: " + omega +
                             "}}\ninitial:\n  microcanonical: {energy: 1/2}\nrun:\n  particles: 10\n  time: 1\n";
    return *analysis::prediction_of(dynamics::parse_scene(text, "s.yaml", "."));
  };
  const auto weak = predict("0.1", "40*pi"), strong = predict("4", "2");
  const auto none = *analysis::prediction_of(dynamics::parse_scene(
      "shape: " BILLIARDS_SOURCE_DIR "/shapes/stadium.yaml\nforce: {periodic: {amplitude: [1, 0], omega: 40*pi}}\n"
      "initial:\n  microcanonical: {energy: 1/2}\nrun:\n  particles: 10\n  time: 1\n", "s.yaml", "."));
  // The stadium's inradius is its caps' radius, 1 (found from below, to 1e-4 of its size).
  CHECK(weak.inradius <= 1 + 1e-12);
  CHECK(weak.inradius >= 1 - 4e-4);
  CHECK(weak.cyclotron_radius == Approx(10));
  CHECK(weak.warnings.empty());
  // λ, the wall integral and g1, g2 are the field-free ones (Santaló; Σ(E) does not depend on B).
  CHECK(weak.g1 == none.g1);
  CHECK(weak.g2 == none.g2);
  CHECK(none.cyclotron_radius == 0);
  REQUIRE(strong.warnings.size() >= 2);
  CHECK_THAT(strong.warnings[strong.warnings.size() - 2], Catch::Contains("cyclotron radius r_c = 0.25 is below the table's inradius"));
  CHECK_THAT(strong.warnings.back(), Catch::Contains("omega/|Omega| = 0.5 is not large"));
}
