// Magnetic flights in 3-D (helices about B): the helix against Rodrigues' rotation, exit times
// through planes (across, along and oblique to B), spheres and triangles against a brute-force
// MPFR scan of the orbit, without and with a static or periodic force, grazing planes, energy
// over long runs, Santaló's collision rate in the 3-D Sinai billiard with every flight verified,
// the drive at ω ≫ Ω against g1 Δt and g2 Δt, trapped orbits, and the scene file and
// `billiard run`/`coeffs` on a 3-D magnetic scene.
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/follow.hpp"
#include "billiards/dynamics/magnetic_flight.hpp"
#include "billiards/dynamics/scene.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include "brute_force_root.hpp"
#include "cli_helpers.hpp"
#include "energy_moments.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace billiards;
using dynamics::Vec3;
using MP = brute_force::Real;
namespace fs = std::filesystem;

namespace {

const double pi = 3.14159265358979323846;

/// The helix in T, independently of the flight's formula: the centre c0 = x0 + (v × Ω)/|Ω|²
/// drifts by v∥ τ and x0 − c0 turns by −|Ω|τ about Ω (Rodrigues' formula).
template <class T>
std::array<T, 3> helix_point(const dynamics::State3& s, const Vec3& omega_c, const T& tau) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  std::array<T, 3> W, x0, v, b, c0, r, out;
  for (int i = 0; i < 3; ++i) W[i] = omega_c[i], x0[i] = s.x[i], v[i] = s.v[i];
  const T k2 = W[0] * W[0] + W[1] * W[1] + W[2] * W[2], k = sqrt(k2);
  for (int i = 0; i < 3; ++i) b[i] = W[i] / k;
  const std::array<T, 3> vxW = {v[1] * W[2] - v[2] * W[1], v[2] * W[0] - v[0] * W[2], v[0] * W[1] - v[1] * W[0]};
  const T along = v[0] * b[0] + v[1] * b[1] + v[2] * b[2];
  for (int i = 0; i < 3; ++i) c0[i] = x0[i] + vxW[i] / k2, r[i] = x0[i] - c0[i];
  const T c = cos(k * tau), sn = -sin(k * tau);
  const std::array<T, 3> bxr = {b[1] * r[2] - b[2] * r[1], b[2] * r[0] - b[0] * r[2], b[0] * r[1] - b[1] * r[0]};
  for (int i = 0; i < 3; ++i) out[i] = c0[i] + along * b[i] * tau + c * r[i] + sn * bxr[i];
  return out;
}

template <class T>
T dot(const std::array<T, 3>& x, const Vec3& n, const Vec3& a) {
  return n.x() * (x[0] - a.x()) + n.y() * (x[1] - a.y()) + n.z() * (x[2] - a.z());
}

/// The driven helix in T, independently of the flight's complex formulation: across the field
/// the particular solution P cos θ + Q sin θ (θ = ωt + φ0) with Q = ω a⊥/(ω² − k²) and
/// P = k b × a⊥/(ω² − k²) (ω = 0: the E×B drift a × Ω/k²), plus the free gyration of what is
/// left, h = v⊥0 − P cos θ0 − Q sin θ0; along the field the free driven motion.  Off resonance.
template <class T>
std::array<T, 3> driven_helix_point(const dynamics::MagneticDriveFlight3& f, const dynamics::State3& s, const T& tau) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  using A = std::array<T, 3>;
  auto cross = [](const A& x, const A& y) {
    return A{x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
  };
  A W, a, v0, b;
  for (int i = 0; i < 3; ++i) W[i] = f.omega_c[i], a[i] = f.accel[i], v0[i] = s.v[i];
  const T k = sqrt(W[0] * W[0] + W[1] * W[1] + W[2] * W[2]), w = f.omega, den = w * w - k * k;
  for (int i = 0; i < 3; ++i) b[i] = W[i] / k;
  const T a_along = a[0] * b[0] + a[1] * b[1] + a[2] * b[2], v_along = v0[0] * b[0] + v0[1] * b[1] + v0[2] * b[2];
  A a_perp, P, Q, h;
  for (int i = 0; i < 3; ++i) a_perp[i] = a[i] - a_along * b[i];
  const A b_a = cross(b, a_perp);
  const T theta0 = w * T(s.t) + T(f.phase0), theta = w * tau + theta0;
  for (int i = 0; i < 3; ++i) {
    P[i] = k * b_a[i] / den, Q[i] = w * a_perp[i] / den;
    h[i] = v0[i] - v_along * b[i] - P[i] * cos(theta0) - Q[i] * sin(theta0);
  }
  const A b_h = cross(b, h);
  // ∫ v: the gyration, the particular solution, and along b.
  const T gyr_h = sin(k * tau) / k, gyr_bh = (cos(k * tau) - 1) / k;
  const T along = w == 0 ? T(v_along * tau + a_along * cos(theta0) * tau * tau / 2)
                         : T(v_along * tau + a_along / w * (-(cos(theta) - cos(theta0)) / w - tau * sin(theta0)));
  A out;
  for (int i = 0; i < 3; ++i) {
    const T particular = w == 0 ? T(P[i] * cos(theta0) * tau)
                                : T(P[i] * (sin(theta) - sin(theta0)) / w - Q[i] * (cos(theta) - cos(theta0)) / w);
    out[i] = T(s.x[i]) + gyr_h * h[i] + gyr_bh * b_h[i] + particular + along * b[i];
  }
  return out;
}

/// The first upward zero of the gap along the orbit before t_max at which `in_span` holds at
/// the orbit's point, orbit(τ) (brute force: samples every h in long double, bisection in
/// MPFR); −1 if none.  `doubtful` is set when a zero lies within 1e-9 of the span's edge.
template <class Gap, class Span, class Orbit>
double first_crossing_in_span(Gap gap, Span in_span, Orbit orbit, double h, double t_max, bool& doubtful) {
  long double before = gap(0.0L);
  for (long n = 1; n * h <= t_max; ++n) {
    const long double now = gap((long double)n * h);
    if (before < 0 && now > 0) {
      MP a = MP(double(n - 1)) * h, b = MP(double(n)) * h;
      for (int k = 0; k < 120; ++k) {
        const MP m = (a + b) / 2;
        (gap(m) > 0 ? b : a) = m;
      }
      const auto p = orbit(b);
      const Vec3 x{double(p[0]), double(p[1]), double(p[2])};
      if (in_span(x, 1e-9) != in_span(x, -1e-9)) doubtful = true;
      if (in_span(x, 0.0)) return static_cast<double>(b);
    }
    before = now;
  }
  return -1;
}

dynamics::State3 random_state(dynamics::ParticleRng& rng, double spread, double speed) {
  dynamics::State3 s;
  s.x = spread * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
  const double z = 2 * rng.uniform() - 1, phi = 2 * pi * rng.uniform(), rho = std::sqrt(1 - z * z);
  s.v = speed * Vec3(rho * std::cos(phi), rho * std::sin(phi), z);
  return s;
}

Vec3 random_direction(dynamics::ParticleRng& rng) {
  const double z = 2 * rng.uniform() - 1, phi = 2 * pi * rng.uniform(), rho = std::sqrt(1 - z * z);
  return Vec3(rho * std::cos(phi), rho * std::sin(phi), z);
}

void compare(double tolerance, double got, double want) {
  if (want < 0) {
    CHECK(got == dynamics::never);
  } else {
    CHECK(std::abs(got - want) <= tolerance * (1 + want));
  }
}

const double slack = dynamics::slack_ulps;

/// Exit times of `flight` from s through planes (z = const, x = const, oblique), a hole, a ball
/// and a triangle against the brute-force scan of orbit(τ), τ after s.t (samples every h up to
/// t_max), each wall the orbit starts inside; whether a zero lay within 1e-9 of a span's edge.
template <class Flight, class Orbit>
bool compare_exit_times(const Flight& flight, const typename Flight::State& s, Orbit orbit, double h, double t_max,
                        double tolerance) {
  auto check = [&](double got, double tau) { compare(tolerance, got, tau < 0 ? tau : s.t + tau); };
  auto everywhere = [](const Vec3&, double) { return true; };
  bool doubtful = false;
  // Planes: across, along and oblique to a field along z.
  for (const Vec3& n : {Vec3(0, 0, 1), Vec3(-1, 0, 0), Vec3(Vec3(1, 2, -2) / 3)}) {
    const Vec3 a = 0.7 * n;
    const dynamics::PlaneWall plane{n, 0.7, slack};
    auto gap = [&]<class T>(const T& tau) { return dot(orbit(tau), n, a); };
    if (gap(0.0L) < 0)
      check(flight.exit_time(s, plane, s.t + t_max), first_crossing_in_span(gap, everywhere, orbit, h, t_max, doubtful));
  }
  // A hole and a ball.
  const Vec3 c(0.1, -0.2, 0.15);
  for (const bool focusing : {false, true}) {
    const double r = focusing ? 1.2 : 0.3;
    const dynamics::SphereWall sphere{c, r, r * r, focusing, slack};
    auto gap = [&]<class T>(const T& tau) {
      const auto x = orbit(tau);
      const T d2 = (x[0] - c.x()) * (x[0] - c.x()) + (x[1] - c.y()) * (x[1] - c.y()) + (x[2] - c.z()) * (x[2] - c.z());
      return focusing ? T(d2 - r * r) : T(r * r - d2);
    };
    if (gap(0.0L) < 0)
      check(flight.exit_time(s, sphere, s.t + t_max), first_crossing_in_span(gap, everywhere, orbit, h, t_max, doubtful));
  }
  // A triangle, crossed many times by its plane: the first crossing within its span.
  const dynamics::TriangleWall tri(Vec3(0.5, -0.4, -0.3), Vec3(0.2, 0.6, -0.1), Vec3(-0.5, 0.1, 0.4), slack);
  auto tri_gap = [&]<class T>(const T& tau) { return dot(orbit(tau), tri.normal, tri.p[0]); };
  auto tri_span = [&](const Vec3& x, double margin) {
    for (int i = 0; i < 3; ++i)
      if (tri.edge_normal[i].dot(x - tri.p[i]) > margin) return false;
    return true;
  };
  if (tri_gap(0.0L) < 0)
    check(flight.exit_time(s, tri, s.t + t_max), first_crossing_in_span(tri_gap, tri_span, orbit, h, t_max, doubtful));
  return doubtful;
}

/// N particles at speed 1 over T = 10, every flight verified at mid-arc and none escaped: the
/// result and the collision rate × λ/v with its standard error (Santaló: 1 for any flow that
/// keeps the Liouville measure and brings almost every orbit to the wall).
struct RateRun {
  dynamics::EnsembleResult result;
  double mean, se;
};
RateRun verified_rate(const dynamics::Table3& table, const dynamics::MagneticFlight3& flight, double lambda,
                      std::size_t N, std::uint64_t seed) {
  dynamics::RunOptions opt;
  const double T = 10;
  opt.record_times = {0, T};
  opt.verify_every_flight = true;
  auto result = dynamics::run_ensemble(table, flight, dynamics::microcanonical(table, flight, 1.0, seed), opt, N, 2);
  REQUIRE(result.escapes() == 0);
  double sum = 0, sum2 = 0;
  for (const auto& log : result.logs) {
    const double x = double(log.collisions) / T * lambda;
    sum += x, sum2 += x * x;
  }
  const double mean = sum / double(N);
  return {std::move(result), mean, std::sqrt((sum2 / double(N) - mean * mean) / double(N - 1))};
}

}  // namespace

TEST_CASE("a helix: Rodrigues' rotation about B, back on its axis after 2π/|Ω| displaced by v∥ T") {
  dynamics::ParticleRng rng(31, 0);
  for (int k = 0; k < 20; ++k) {
    const Vec3 omega_c = std::exp(3 * rng.uniform() - 1) * random_direction(rng);
    const dynamics::MagneticFlight3 flight{omega_c};
    const auto s = random_state(rng, 1, 0.5 + rng.uniform());
    for (const double tau : {1e-3, 0.7, 13.0}) {
      const auto x = flight.advance(s, tau).x;
      const auto want = helix_point(s, omega_c, MP(tau));
      for (int i = 0; i < 3; ++i) CHECK(std::abs(x[i] - double(want[i])) <= 1e-13 * (1 + std::abs(tau)));
      CHECK(flight.advance(s, tau).v.norm() == Approx(s.v.norm()).epsilon(1e-14));
    }
    const double T = flight.period();
    const Vec3 drift = s.v.dot(omega_c) / omega_c.squaredNorm() * omega_c;
    CHECK((flight.advance(s, T).x - (s.x + T * drift)).norm() <= 1e-12 * (1 + T));
  }
}

TEST_CASE("helix exit times through planes, spheres and triangles equal a brute-force MPFR scan") {
  dynamics::ParticleRng rng(32, 0);
  int doubtful_cases = 0;
  for (int k = 0; k < 40; ++k) {
    // Every third field along z, so that the planes z = const and x = const are across and
    // along it (the closed forms); the others oblique (the scan).
    const Vec3 direction = k % 3 == 0 ? Vec3(0, 0, k % 2 ? 1 : -1) : random_direction(rng);
    const Vec3 omega_c = std::exp(3 * rng.uniform() - 1) * direction;
    const dynamics::MagneticFlight3 flight{omega_c};
    const auto s = random_state(rng, 0.6, 0.5 + rng.uniform());
    const double turn = flight.period(), t_max = 3 * turn, h = turn / 4000;
    INFO("case " << k << " omega " << omega_c.transpose() << " x " << s.x.transpose() << " v " << s.v.transpose());
    auto orbit = [&]<class T>(const T& tau) { return helix_point(s, omega_c, tau); };
    doubtful_cases += compare_exit_times(flight, s, orbit, h, t_max, 1e-11);
  }
  CHECK(doubtful_cases <= 2);
}

TEST_CASE("exit times of the helix under a static or periodic force equal a brute-force scan of an independent solution") {
  dynamics::ParticleRng rng(36, 0);
  int doubtful_cases = 0;
  for (int k = 0; k < 36; ++k) {
    // Static (the E×B drift), fast (ω ≫ |Ω|) and slow drives; every third field along z.
    const Vec3 direction = k % 3 == 0 ? Vec3(0, 0, k % 2 ? 1 : -1) : random_direction(rng);
    const double K = std::exp(2 * rng.uniform() - 0.5);
    const double omega = k % 3 == 0 ? 0.0 : k % 3 == 1 ? 40 * pi : 0.37 * K;
    const dynamics::MagneticDriveFlight3 flight{K * direction, 3 * random_direction(rng), omega, 2 * pi * rng.uniform()};
    auto start = random_state(rng, 0.6, 0.5 + rng.uniform());
    start.t = 0.4;  // (the drive's phase at the start: ω t + φ0)
    const auto s = flight.start(start);
    // Independent of the flight's arithmetic: its own advance agrees with the solution here.
    const auto want = driven_helix_point(flight, s, MP(1.3));
    const auto got = flight.advance(s, s.t + 1.3).x;
    for (int i = 0; i < 3; ++i) CHECK(std::abs(got[i] - double(want[i])) <= 1e-11 * (1 + std::abs(double(want[i]))));
    const double t_max = 6, h = 2 * pi / std::max(K, omega) / 200;
    INFO("case " << k << " omega_c " << (K * direction).transpose() << " omega " << omega);
    auto orbit = [&]<class T>(const T& tau) { return driven_helix_point(flight, s, tau); };
    doubtful_cases += compare_exit_times(flight, s, orbit, h, t_max, 1e-10);
  }
  CHECK(doubtful_cases <= 2);
}

TEST_CASE("grazing an oblique plane: a crossing deeper than rounding is a hit at the MPFR time, a miss is a miss") {
  dynamics::ParticleRng rng(33, 0);
  for (int k = 0; k < 20; ++k) {
    const Vec3 omega_c = std::exp(2 * rng.uniform()) * random_direction(rng);
    const dynamics::MagneticFlight3 flight{omega_c};
    auto s = random_state(rng, 0.2, 1);
    const Vec3 n = Vec3(Vec3(2, -1, 2) / 3);
    // The plane's side moving away from the drift, so the gap rises and falls once per turn
    // and the orbit's highest point in the first turn decides.
    if (n.dot(s.v.dot(omega_c) * omega_c) > 0) s.v = -s.v;
    const double turn = flight.period();
    auto gap0 = [&]<class T>(const T& tau) { return dot(helix_point(s, omega_c, tau), n, Vec3::Zero()); };
    // The top of the gap in the first turn: the best sample, then a ternary search in MPFR.
    const int samples = 20000;
    double best = 0;
    for (int i = 1; i < samples; ++i)
      if (gap0((long double)i * turn / samples) > gap0((long double)best)) best = i * turn / samples;
    MP lo = std::max(0.0, best - turn / samples), hi = best + turn / samples;
    for (int i = 0; i < 200; ++i) {
      const MP m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      (gap0(m1) < gap0(m2) ? lo : hi) = (gap0(m1) < gap0(m2) ? m1 : m2);
    }
    const MP top = gap0(lo);
    if (!(lo > turn / 100 && lo < turn * 0.99)) continue;  // the top at the start: no graze
    for (const double depth : {1e-7, 1e-10, -1e-9}) {
      const double offset = double(top) - depth;
      const dynamics::PlaneWall plane{n, offset, slack};
      const double got = flight.exit_time(s, plane, turn);
      INFO("case " << k << " depth " << depth << " top at " << double(lo));
      if (depth < 0) {
        CHECK(got == dynamics::never);
        continue;
      }
      // The upward zero just before the top, bisected in MPFR.
      MP a = lo - std::sqrt(depth) * 1e-1 * turn, b = lo;
      while (gap0(a) - offset > 0) a -= (b - a);
      for (int i = 0; i < 200; ++i) {
        const MP m = (a + b) / 2;
        (gap0(m) - offset > 0 ? b : a) = m;
      }
      CHECK(std::abs(got - double(b)) <= 1e-9 * turn);  // a shallow root is as exact as √(rounding)
    }
  }
}

TEST_CASE("3-D Sinai in a weak and a strong field: rate × λ/v = 1, no escape with every flight verified, speed kept") {
  const auto shape = geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/sinai3.yaml");
  const dynamics::Table3 table(shape.region);
  const double lambda = geometry::mean_free_path(geometry3::measures_of(shape.region));
  // r_c = 20 ≫ the table and r_c = 0.1 < its inradius (every helix drifts to a wall anyway);
  // along z (closed forms for the faces) and oblique (the scan).
  for (const auto& [rc, direction] : {std::pair{20.0, Vec3(0, 0, 1)}, std::pair{20.0, Vec3(Vec3(1, 2, 2) / 3)},
                                      std::pair{0.1, Vec3(Vec3(2, -1, 2) / 3)}}) {
    const auto run = verified_rate(table, dynamics::MagneticFlight3{direction / rc}, lambda, 6000, 5);
    double worst = 0;
    for (double dE : run.result.energy_changes(1, 2)) worst = std::max(worst, std::abs(dE));
    INFO("r_c " << rc << " along " << direction.transpose() << ": rate × λ/v = " << run.mean << " ± " << run.se);
    CHECK(std::abs(run.mean - 1) <= 3 * run.se);
    CHECK(worst <= 1e-13);
  }
}

TEST_CASE("helices in the non-convex L-prism mesh (the BVH walked along the guiding axis): rate × λ/v = 1, no escape") {
  const auto shape = geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/l-prism.yaml");
  const dynamics::Table3 table(shape.region);
  const double lambda = geometry::mean_free_path(geometry3::measures_of(shape.region));
  for (const double rc : {5.0, 0.3}) {
    const auto run = verified_rate(table, dynamics::MagneticFlight3{Vec3(Vec3(1, -2, 2) / 3) / rc}, lambda, 4000, 6);
    INFO("r_c " << rc << ": rate × λ/v = " << run.mean << " ± " << run.se);
    CHECK(std::abs(run.mean - 1) <= 3 * run.se);
  }
}

TEST_CASE("a helix conserves the speed over 1e6 collisions in the 3-D Sinai billiard") {
  const auto shape = geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/sinai3.yaml");
  const dynamics::Table3 table(shape.region);
  const dynamics::MagneticFlight3 flight{Vec3(0.3, -0.4, 1.1)};
  dynamics::ParticleRng rng(34, 0);
  const auto s = dynamics::sample_microcanonical(table, 1.0, rng);
  constexpr long n = 1000000;
  const auto [drift, worst] = speed_change(table, flight, s, n);
  // Each flight keeps v² to a few roundings (0.8 ε per flight); summed, they show a bias of
  // +0.011 ± 0.001 ε per flight (the rounding of the three parts v∥, v⊥, w0 of the velocity),
  // below ε/32.
  const double eps = std::numeric_limits<double>::epsilon();
  INFO("relative change of v² over the flights " << drift << ", at most " << worst << " in one");
  CHECK(worst <= 16 * eps);
  CHECK(std::abs(drift) <= n * eps / 32);
}

TEST_CASE("driven 3-D Sinai (320π) in a weak field at ω ≫ Ω: <ΔE> and Var ΔE equal g1 Δt and g2 Δt") {
  const auto shape = geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/sinai3.yaml");
  const double F = 10, omega = 320 * pi;
  const Vec3 amplitude = F * Vec3(1, 1, 1) / std::sqrt(3.0);
  check_energy_moments(dynamics::Table3(shape.region), dynamics::MagneticDriveFlight3{Vec3(0.3, 0, 0.4), amplitude, omega, 0},
                       geometry3::measures_of(shape.region), amplitude, omega, 4, 6000);
}

TEST_CASE("the driven helix equals an integration of m v̇ = q v × B + F cos(ωt + φ), at resonance too") {
  // Classical RK4 with a small step, against the closed form.
  auto integrated = [](const dynamics::MagneticDriveFlight3& f, dynamics::State3 s, double tau, int steps) {
    const double h = tau / steps;
    auto accel = [&](const Vec3& v, double t) { return Vec3(v.cross(f.omega_c) + f.accel * std::cos(f.omega * t + f.phase0)); };
    for (int i = 0; i < steps; ++i) {
      const double t = s.t;
      const Vec3 k1v = accel(s.v, t), k1x = s.v;
      const Vec3 k2v = accel(s.v + h / 2 * k1v, t + h / 2), k2x = s.v + h / 2 * k1v;
      const Vec3 k3v = accel(s.v + h / 2 * k2v, t + h / 2), k3x = s.v + h / 2 * k2v;
      const Vec3 k4v = accel(s.v + h * k3v, t + h), k4x = s.v + h * k3v;
      s.x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      s.v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
      s.t += h;
    }
    return s;
  };
  dynamics::ParticleRng rng(35, 0);
  const Vec3 W = 2 * random_direction(rng);
  for (const double omega : {0.0, 7.0, 2.0}) {  // static, off resonance, at ω = |Ω|
    const dynamics::MagneticDriveFlight3 f{W, 3 * random_direction(rng), omega, 0.4};
    auto s = random_state(rng, 1, 1);
    s.t = 0.3;
    const auto want = integrated(f, s, 2.5, 20000);
    const auto got = f.advance(f.start(s), s.t + 2.5);
    INFO("omega " << omega);
    CHECK((got.x - want.x).norm() <= 1e-9);
    CHECK((got.v - want.v).norm() <= 1e-9);
  }
}

TEST_CASE("a helix meeting no wall is trapped only without drift along B; with drift it reaches the wall") {
  const auto shape = geometry3::parse_shape3("name: ball\ndimension: 3\nboundary:\n  sphere: {center: [0, 0, 0], radius: 10}\n",
                                             "test");
  const dynamics::Table3 table(shape.region);
  const dynamics::MagneticFlight3 flight{Vec3(0, 0, 2)};  // r_c = 1/2 at speed 1
  dynamics::State3 s;
  s.v = Vec3(1, 0, 0);
  auto none = [](const auto&, const auto&) {};
  auto no_sample = [](const auto&) {};
  const auto circling = dynamics::follow(table, flight, s, {}, {}, none, no_sample);
  CHECK(circling.trapped);
  CHECK_FALSE(circling.escaped);
  CHECK(circling.collisions == 0);
  s.v = Vec3(1, 0, 1e-3).normalized();
  dynamics::FollowLimits limits;
  limits.collisions = 1;
  const auto drifting = dynamics::follow(table, flight, s, limits, {}, none, no_sample);
  CHECK_FALSE(drifting.trapped);
  CHECK_FALSE(drifting.escaped);
  CHECK(drifting.collisions == 1);
}

TEST_CASE("3-D magnetic scenes: B a vector with expressions and --set; bad input refused at its line, no output") {
  const std::string head = "shape: ../shapes/3d/sinai3.yaml\nparameters: {B: 0.5}\n";
  dynamics::SceneOverrides set_b;
  set_b.set = {{"B", "1"}};
  auto scene = dynamics::parse_scene(head + "magnetic: {B: [0, B, 2*B]}\ncharge: -2\nmass: 4\n"
                                            "initial: {microcanonical: {energy: 1}}\nrun: {particles: 10, time: 1}\n",
                                     "test.yaml", BILLIARDS_SOURCE_DIR "/scenes", set_b);
  REQUIRE(scene.magnetic());
  CHECK(scene.cyclotron_vector() == Vec3(0, -0.5, -1));  // qB/m = (−2)(0, 1, 2)/4
  dynamics::with_flight(scene, [](const auto& flight) {
    if constexpr (std::is_same_v<std::decay_t<decltype(flight)>, dynamics::MagneticFlight3>) CHECK(flight.omega_c == Vec3(0, -0.5, -1));
    else FAIL("not MagneticFlight3");
    return 0;
  });
  auto constant = dynamics::parse_scene(head + "magnetic: {B: [0, 0, B]}\ninitial: {microcanonical: {energy: 1}}\n"
                                               "force:\n  constant: {amplitude: [1, 0, 0]}\nrun: {particles: 10, time: 1}\n",
                                        "test.yaml", BILLIARDS_SOURCE_DIR "/scenes");
  dynamics::with_flight(constant, [](const auto& flight) {
    if constexpr (std::is_same_v<std::decay_t<decltype(flight)>, dynamics::MagneticDriveFlight3>) CHECK(flight.omega == 0);
    else FAIL("not MagneticDriveFlight3");
    return 0;
  });

  const auto dir = scratch("magnetic3");
  struct Case {
    std::string name, yaml, message;
  };
  const std::string rest = "initial: {microcanonical: {energy: 1}}\nrun: {particles: 10, time: 1}\n";
  const std::vector<Case> cases = {
      {"scalar", head + "magnetic: {B: B}\n" + rest, ":3: in 3-D the magnetic field is a vector [Bx, By, Bz], not a number"},
      {"two", head + "magnetic: {B: [1, 2]}\n" + rest, ":3: expected a vector [x, y, z]"},
      {"infinite", head + "magnetic: {B: [0, 1/0, 0]}\n" + rest, ":3: expression '1/0' is not a finite number"},
      {"uncharged", head + "magnetic: {B: [0, 0, B]}\ncharge: 0\n" + rest, ":4: the charge must not be 0 in a magnetic field"},
      {"constant", head + rest + "force:\n  constant: {amplitude: [0, 0, 1]}\n",
       ":6: a constant force is implemented in 3-D only with a magnetic field"},
  };
  for (const auto& c : cases) {
    const fs::path path = fs::path(BILLIARDS_SOURCE_DIR) / "scenes" / (".test-magnetic3-" + c.name + ".yaml");
    write_file(path, c.yaml);
    const auto r = billiard("run " + path.string() + " --quiet --out " + (dir / "bad").string());
    fs::remove(path);
    INFO(c.name << ": " << r.output);
    CHECK(r.status != 0);
    CHECK_THAT(r.output, Catch::Contains(".test-magnetic3-" + c.name + ".yaml" + c.message));
    CHECK_FALSE(fs::exists(dir / "bad"));
  }
}

TEST_CASE("billiard run and coeffs on the bundled 3-D magnetic scene") {
  const auto dir = scratch("magnetic3-run");
  const auto r = billiard("run scenes/sinai3-magnetic.yaml --particles 400 --time 4 --quiet --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  const auto s = read_json(dir / "out" / "summary.json");
  CHECK(s["dimension"] == 3);
  CHECK(s["escapes"] == 0);
  // The field does no work: every particle keeps E0.
  const auto E = read_npy(dir / "out" / "energies.npy");
  double worst = 0;
  for (double e : E) worst = std::max(worst, std::abs(e - 0.5));
  CHECK(worst <= 1e-13);
  const auto c = billiard("coeffs scenes/sinai3-magnetic-driven.yaml");
  INFO(c.output);
  REQUIRE(c.status == 0);
  CHECK_THAT(c.output, Catch::Contains("every orbit with a velocity component along B drifts to the wall"));
  CHECK_THAT(c.output, Catch::Contains("omega/|Omega|"));
}
