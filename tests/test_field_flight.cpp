// Flights in general fields (FieldFlight): field expressions and their exact derivatives, scene
// keys and their errors, the integrator against the closed-form flights, a harmonic bowl against
// its closed form and conservation laws, and a position-dependent drive in the clover against
// the analysis layer's g1, g2.
#include "cli_helpers.hpp"

#include "billiards/analysis/coefficients.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/analysis/wall.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/field_flight.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/geometry.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

using namespace billiards;
using dynamics::FieldFlight;
using dynamics::Force;
using dynamics::Vec2;

namespace {

const double pi = geometry::pi;

CoordinateFunction parse(const std::string& text, const Expressions& params = {}) {
  return CoordinateFunction(text, params, "test.yaml", 7);
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string scene_error(const std::string& name, const std::string& text) {
  const auto dir = scratch("field-" + name);
  write_file(dir / "scene.yaml", text);
  try {
    dynamics::load_scene((dir / "scene.yaml").string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// A scene in the circle (shape path absolute), with the given extra keys.
std::string circle_scene(const std::string& keys) {
  return "shape: " BILLIARDS_SOURCE_DIR "/shapes/circle.yaml\nparameters: {k: 0.1}\ninitial:\n  microcanonical: "
         "{energy: 1/2}\nrun: {particles: 10, time: 1}\n" +
         keys;
}

Force periodic(const Vec2& F, double omega) {
  Force f;
  f.kind = Force::Kind::periodic;
  f.amplitude = F;
  f.omega = omega;
  return f;
}

dynamics::Potential harmonic(double k) {
  Expressions params;
  params.define("k", std::to_string(k), "test", 1);
  dynamics::Potential p;
  p.U = parse("0.5*k*(x^2 + y^2)", params);
  p.gradient = {p.U.derivative(0), p.U.derivative(1)};
  return p;
}

}  // namespace

TEST_CASE("field expressions: values and exact derivatives against hand-derived forms") {
  Expressions params;
  params.define("a", "3/2", "test", 1);
  const auto f = parse("sin(a*x)*exp(-y^2) + x^3*y/3 + sqrt(1 + x^2) + atan(y)", params);
  const double a = 1.5;
  for (const Vec2& p : {Vec2(0.3, -0.4), Vec2(-1.2, 0.9), Vec2(2.0, 0.1)}) {
    const double x = p.x(), y = p.y();
    CHECK(f(p) == Approx(std::sin(a * x) * std::exp(-y * y) + x * x * x * y / 3 + std::sqrt(1 + x * x) + std::atan(y))
                      .epsilon(1e-14));
    CHECK(f.derivative(0)(p) ==
          Approx(a * std::cos(a * x) * std::exp(-y * y) + x * x * y + x / std::sqrt(1 + x * x)).epsilon(1e-14));
    CHECK(f.derivative(1)(p) ==
          Approx(-2 * y * std::sin(a * x) * std::exp(-y * y) + x * x * x / 3 + 1 / (1 + y * y)).epsilon(1e-14));
  }
  // abs, powers with non-integer exponents, log, pi and e.
  const auto g = parse("abs(x)*log(1 + y^2) + x^(5/2) + pi*e*y");
  CHECK(g(Vec2(0.7, -0.5)) == Approx(0.7 * std::log(1.25) + std::pow(0.7, 2.5) - pi * std::exp(1.0) * 0.5));
  CHECK(g.derivative(0)(Vec2(0.7, -0.5)) == Approx(std::log(1.25) + 2.5 * std::pow(0.7, 1.5)));
  CHECK(g.derivative(0)(Vec2(-0.7, -0.5)) != g.derivative(0)(Vec2(-0.7, -0.5)));  // x^(3/2) at x < 0: NaN
  CHECK(g.derivative(1)(Vec2(0.7, -0.5)) == Approx(0.7 * 2 * -0.5 / 1.25 + pi * std::exp(1.0)));
  CHECK(parse("2.5").constant());
  CHECK_FALSE(parse("y").constant());
}

TEST_CASE("field expressions: errors name file and line") {
  CHECK(error_of("x + z").find("test.yaml:7: bad expression 'x + z': unknown name 'z'") != std::string::npos);
  CHECK(error_of("x +* 2").find("test.yaml:7: bad expression") != std::string::npos);
  // GiNaC's parser crashes on a call with no argument (a fuzz finding): refused before it reads.
  CHECK(error_of("1/sqrt()2").find("test.yaml:7: bad expression '1/sqrt()2': sqrt() has no argument") !=
        std::string::npos);
  CHECK(error_of("x*sin ( )").find("sin() has no argument") != std::string::npos);
  CHECK(error_of("min(x, y)").find("test.yaml:7:") != std::string::npos);
  CHECK(error_of("x > 0 ? 1 : 2").find("test.yaml:7:") != std::string::npos);
  // muparser reads x^-1/2 as (x^-1)/2; a parser that read it otherwise would change its meaning.
  const std::string e = error_of("x^-1/2");
  if (!e.empty()) CHECK(e.find("read differently") != std::string::npos);
  if (e.empty()) CHECK(parse("x^-1/2")(Vec2(2, 0)) == Approx(0.25));
}

TEST_CASE("scene files: field and potential keys; errors name file and line") {
  const auto ok = circle_scene("force: {field: {amplitude: [\"x\", \"k*y\"], omega: 2*pi}}\n"
                               "potential: {expression: \"k*x^2\", gradient: [\"2*k*x\", \"0\"]}\n"
                               "integrator: {tolerance: 1e-9}\n");
  const auto dir = scratch("field-ok");
  write_file(dir / "scene.yaml", ok);
  const auto scene = dynamics::load_scene((dir / "scene.yaml").string());
  CHECK(scene.force.kind == Force::Kind::field);
  CHECK(scene.force.field[1](Vec2(0, 2)) == Approx(0.2));
  REQUIRE(scene.potential);
  CHECK(scene.potential->gradient[0](Vec2(3, 0)) == Approx(0.6));
  CHECK(scene.integrator_tolerance == 1e-9);

  CHECK(scene_error("bad-expr", circle_scene("force: {field: {amplitude: [\"x\", \"q*y\"], omega: 1}}\n"))
            .find("scene.yaml:6: bad expression 'q*y': unknown name 'q'") != std::string::npos);
  CHECK(scene_error("three", circle_scene("force: {field: {amplitude: [x, y, x], omega: 1}}\n"))
            .find("scene.yaml:6: a field amplitude must be a list of two expressions") != std::string::npos);
  CHECK(scene_error("no-omega", circle_scene("force: {field: {amplitude: [x, y]}}\n"))
            .find("scene.yaml:6: a field force needs 'omega'") != std::string::npos);
  CHECK(scene_error("grad-length", circle_scene("potential:\n  expression: x^2\n  gradient: [2*x]\n"))
            .find("scene.yaml:8: a potential's gradient must be a list of two expressions") != std::string::npos);
  CHECK(scene_error("grad-wrong", circle_scene("potential:\n  expression: x^2*y\n  gradient: [2*x*y, x]\n"))
            .find("scene.yaml:8: gradient[1] is not the derivative of the potential along y") != std::string::npos);
  CHECK(scene_error("pot-key", circle_scene("potential: {expr: x}\n")).find("scene.yaml:6: unknown key 'expr'") !=
        std::string::npos);
  CHECK(scene_error("tol", circle_scene("integrator: {tolerance: 1}\n")).find("scene.yaml:6:") != std::string::npos);
  const std::string cube = "shape: " BILLIARDS_SOURCE_DIR "/shapes/3d/cube.yaml\ninitial: {microcanonical: {energy: 1}}\n"
                           "run: {particles: 1, time: 1}\n";
  CHECK(scene_error("field3", cube + "force: {field: {amplitude: [x, y], omega: 1}}\n")
            .find("scene.yaml:4: a field force is implemented in 2-D only") != std::string::npos);
  CHECK(scene_error("potential3", cube + "potential: {expression: x}\n")
            .find("scene.yaml:4: a potential is implemented in 2-D only") != std::string::npos);
}

TEST_CASE("a uniform drive through the integrator reproduces the closed-form flight, collision by collision") {
  // From the same state both flights must find the same next wall at the same time and point
  // (within the integrator's tolerance); the closed form's state after each bounce is the next
  // start, so chaos cannot amplify the differences.  Then whole sequences of 4 collisions.  In
  // tables with elliptic walls the integrator's flight scans their gap (walls.hpp's
  // gap_sample), the closed form maps the flight onto a circular arc.
  for (const char* name : {"clover", "sinai-ellipse", "elliptic-stadium"}) {
    INFO("table " << name);
    const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + std::string(name) + ".yaml");
    const dynamics::Table table(shape.region);
    for (const double omega : {2 * pi, 40 * pi, 320 * pi}) {
      const Vec2 F = 10 / std::sqrt(2.0) * Vec2(1, 1);
      const dynamics::PeriodicDriveFlight exact{F, omega, 0.3};
      Force force = periodic(F, omega);
      force.phase = 0.3;
      const FieldFlight field(force, std::nullopt, 1.0, table, 1e-12);
      double worst_t = 0, worst_x = 0;
      for (int p = 0; p < 4; ++p) {
        dynamics::ParticleRng rng(7, p);
        auto s = exact.start(dynamics::sample_microcanonical(table, 1.0, rng));
        for (int k = 0; k < 25; ++k) {
          const auto want = dynamics::collision(table, exact, s);
          const auto got = dynamics::collision(table, field, field.start(s));
          REQUIRE(want.found());
          REQUIRE(got.wall == want.wall);
          worst_t = std::max(worst_t, std::abs(got.t - want.t));
          worst_x = std::max(worst_x, (got.point - want.point).norm());
          dynamics::bounce(exact, s, want);
        }
        // Whole sequences: both bounce on their own.
        dynamics::ParticleRng rng2(8, p);
        const auto s0 = dynamics::sample_microcanonical(table, 1.0, rng2);
        const auto a = dynamics::evolve(table, exact, exact.start(s0), 4);
        const auto b = dynamics::evolve(table, field, field.start(s0), 4);
        REQUIRE(a.size() == 4);
        REQUIRE(b.size() == 4);
        for (int k = 0; k < 4; ++k) {  // (differences grow by the Lyapunov factor per collision)
          CHECK(a[k].wall == b[k].wall);
          CHECK(std::abs(a[k].t - b[k].t) < 1e-5);
        }
      }
      INFO("omega = " << omega);
      CHECK(worst_t < 1e-8);
      CHECK(worst_x < 1e-8);
    }
  }
}

TEST_CASE("a static uniform force through the integrator reproduces the parabolic flight") {
  for (const char* name : {"stadium", "sinai-ellipse", "elliptic-stadium", "ellipse"}) {
    INFO("table " << name);
    const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + std::string(name) + ".yaml");
    const dynamics::Table table(shape.region);
    const Vec2 F(0.3, -0.8);
    const dynamics::ConstantForceFlight exact{F};
    Force force;
    force.kind = Force::Kind::constant;
    force.amplitude = F;
    const FieldFlight field(force, std::nullopt, 1.0, table, 1e-12);
    int elliptic = 0;  // hits on elliptic arcs
    for (int p = 0; p < 8; ++p) {
      dynamics::ParticleRng rng(9, p);
      auto s = dynamics::sample_microcanonical(table, 1.0, rng);
      for (int k = 0; k < 25; ++k) {
        // (A horizon: the parabolic flight's search does not end without one.)
        const auto want = dynamics::collision(table, exact, s, s.t + 50);
        const auto got = dynamics::collision(table, field, field.start(s), s.t + 50);
        REQUIRE(got.wall == want.wall);
        CHECK(std::abs(got.t - want.t) < 1e-8);
        CHECK((got.point - want.point).norm() < 1e-8);
        // The per-wall search of the flight interface gives the same time for that wall.
        const auto st = field.start(s);
        const double t_wall = table.visit(got.wall, [&](const auto& w) { return field.exit_time(st, w, s.t + 50); });
        CHECK(t_wall == got.t);
        elliptic += got.wall.kind == dynamics::wall_kind::elliptic_arc;
        dynamics::bounce(exact, s, want);
      }
    }
    if (std::string(name) != "stadium") CHECK(elliptic >= 20);
  }
}

TEST_CASE("harmonic bowl in the circle: collision times equal the closed form, E and L conserved") {
  // x(t) = x0 cos Ωt + (v0/Ω) sin Ωt, so |x|² = A + B cos 2Ωt + C sin 2Ωt: the exit time from the
  // unit circle is a closed form.  A radial wall keeps the angular momentum L, and the flow keeps
  // E and L, so both are invariants of the whole trajectory.  With E/k > 1 every orbit's
  // ellipse reaches the wall.
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/circle.yaml");
  const dynamics::Table table(shape.region);
  const double k = 0.4, Omega = std::sqrt(k);
  const FieldFlight flight(Force{}, harmonic(k), 1.0, table, 1e-11);
  for (int p = 0; p < 10; ++p) {
    dynamics::ParticleRng rng(11, p);
    auto s = flight.start(dynamics::sample_microcanonical(
        table, 0.5, 1.0, [&](const Vec2& x) { return flight.potential(x); }, rng));
    const double E0 = 0.5 * s.v.squaredNorm() + flight.potential(s.x), L0 = geometry::cross(s.x, s.v);
    CHECK(E0 == Approx(0.5).epsilon(1e-14));
    for (int c = 0; c < 40; ++c) {
      const Vec2 x0 = s.x, v0 = s.v;
      const double A = (x0.squaredNorm() + v0.squaredNorm() / k) / 2, B = (x0.squaredNorm() - v0.squaredNorm() / k) / 2,
                   C = x0.dot(v0) / Omega;
      const double D = std::hypot(B, C), phi0 = std::atan2(C, B);
      const double q = std::clamp((1 - A) / D, -1.0, 1.0);
      double phi = phi0 - std::acos(q);
      while (phi <= 1e-9) phi += 2 * pi;  // the first outward crossing after the start
      const auto hit = dynamics::collision(table, flight, s, s.t + 100);
      REQUIRE(hit.found());
      CHECK(std::abs(hit.t - s.t - phi / (2 * Omega)) < 1e-8);
      dynamics::bounce(flight, s, hit);
      CHECK(std::abs(0.5 * s.v.squaredNorm() + flight.potential(s.x) - E0) < 1e-9);
      CHECK(std::abs(geometry::cross(s.x, s.v) - L0) < 1e-9);
    }
  }
}

TEST_CASE("harmonic bowl in the circle from its centre: the closed-form exit time (no 0/0 at the centre)") {
  // From x0 = 0 the flight is x(t) = (v0/Ω) sin Ωt along v0, which reaches the unit circle at
  // sin Ωt = Ω/|v0|.  At the centre the arc's f' = p·v/|p| is 0/0 unless guarded.
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/circle.yaml");
  const dynamics::Table table(shape.region);
  const double k = 0.4, Omega = std::sqrt(k);
  const FieldFlight flight(Force{}, harmonic(k), 1.0, table, 1e-11);
  for (const Vec2& v0 : {Vec2(1, 0), Vec2(0.6, -0.8), Vec2(-3, 4)}) {
    dynamics::State free;
    free.x = Vec2(0, 0);
    free.v = v0;
    const auto hit = dynamics::collision(table, flight, flight.start(free), 100.0);
    REQUIRE(hit.found());
    CHECK(std::abs(hit.t - std::asin(Omega / v0.norm()) / Omega) < 1e-8);
    CHECK((hit.point - v0.normalized()).norm() < 1e-8);
  }
}

TEST_CASE("weak harmonic bowl in the stadium, F = 0: energy conserved to the integrator's tolerance") {
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/stadium.yaml");
  const dynamics::Table table(shape.region);
  auto drift = [&](double tol) {
    const FieldFlight flight(Force{}, harmonic(0.1), 1.0, table, tol);
    dynamics::RunOptions opt;
    opt.mass = 1;
    opt.record_times = {0, 50};
    opt.verify_every_flight = true;
    const auto res = dynamics::run_ensemble(table, flight, dynamics::microcanonical(table, flight, 1.0, 5), opt, 40, 2);
    REQUIRE(res.escapes() == 0);
    CHECK(res.collisions() > 40 * 50 / 4);  // (λ = 2.18 at |v| ≤ 1)
    double worst = 0;
    for (std::size_t i = 0; i < 40; ++i) {
      CHECK(res.energies[2 * i] == Approx(0.5).epsilon(1e-14));  // E = ½mv² + U(x) at the start
      worst = std::max(worst, std::abs(res.energies[2 * i + 1] - res.energies[2 * i]));
    }
    return worst;
  };
  const double loose = drift(1e-6), tight = drift(1e-10);
  CHECK(tight < 1e-8);
  CHECK(loose > 30 * tight);  // the drift is the integrator's error: it falls with the tolerance
}

TEST_CASE("position-dependent drive F0 (1 + x/L) in the clover at 320 pi: <dE>, Var(dE) match g1 dt, g2 dt") {
  const auto scene = dynamics::load_scene(BILLIARDS_SOURCE_DIR "/scenes/clover-field.yaml");
  REQUIRE(scene.force.kind == Force::Kind::field);
  const auto& F = scene.force.field;
  const auto c = analysis::coefficients(
      scene.shape<2>().region, [&](const Vec2& x) { return Vec2(F[0](x), F[1](x)); }, scene.force.omega, 1.0, 0.5);
  CHECK(c.wall_integral_error < 1e-6 * c.wall_integral);
  CHECK(c.warnings.empty());
  // The theory's F(x) matters here: a uniform F0 would predict 3.2× less.
  const auto uniform = analysis::coefficients(geometry::measures_of(scene.shape<2>().region),
                                              analysis::Drive{Eigen::Vector2d(30 / std::sqrt(2.0), 30 / std::sqrt(2.0)),
                                                              scene.force.omega, 1.0},
                                              0.5);
  CHECK(c.g2 > 3 * uniform.g2);

  const dynamics::Table table(scene.shape<2>().region);
  const FieldFlight flight(scene.force, std::nullopt, 1.0, table, 1e-7);
  const double dt = 8;
  dynamics::RunOptions opt;
  opt.record_times = {0, dt};
  const std::size_t n = 3000;
  const auto res = dynamics::run_ensemble(table, flight, dynamics::microcanonical(table, flight, 1.0, 2024), opt, n, 2);
  REQUIRE(res.escapes() == 0);
  const auto m = analysis::sample_moments(res.energy_changes(1, 2));
  INFO("<dE> = " << m.mean << " ± " << m.se_mean << " (g1 dt = " << c.g1 * dt << "), Var = " << m.variance << " ± "
                 << m.se_variance << " (g2 dt = " << c.g2 * dt << ")");
  CHECK(std::abs(m.mean - c.g1 * dt) < 3 * m.se_mean);
  CHECK(std::abs(m.variance - c.g2 * dt) < 3 * m.se_variance);
  CHECK(std::abs(m.variance - uniform.g2 * dt) > 10 * m.se_variance);  // resolution: the uniform F0 fails
}

TEST_CASE("coeffs: a uniform field given as expressions equals the closed form; --json has the error estimate") {
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
  const Vec2 F(3, -4);
  const double omega = 40 * pi;
  const auto closed = analysis::coefficients(geometry::measures_of(shape.region),
                                             analysis::Drive{Eigen::Vector2d(F), omega, 2.0}, 0.7);
  const auto quad = analysis::coefficients(shape.region, [&](const Vec2&) { return F; }, omega, 2.0, 0.7);
  CHECK(quad.wall_integral == Approx(closed.wall_integral).epsilon(1e-10));
  CHECK(quad.g1 == Approx(closed.g1).epsilon(1e-10));
  CHECK(quad.g2 == Approx(closed.g2).epsilon(1e-10));
  CHECK(quad.C == Approx(closed.C).epsilon(1e-10));

  const auto out = billiard("coeffs scenes/clover-field.yaml --json");
  REQUIRE(out.status == 0);
  CHECK(out.output.find("\"wall_integral_error\"") != std::string::npos);
  const auto bowl = billiard("coeffs scenes/stadium-bowl.yaml");  // a potential but no drive
  CHECK(bowl.status != 0);
  CHECK(bowl.output.find("needs a periodic force") != std::string::npos);
}

TEST_CASE("a potential: coeffs from the quadrature over {U < E}, and the driven clover in a tilt matches them") {
  // U = g y tilts the clover so strongly (E0 = 1/2, U up to ±0.86) that the top lobe is partly
  // forbidden: the prediction with the potential is 1.7× the one without, far beyond the SE.
  const auto dir = scratch("field-tilt");
  const std::string scene = "shape: " BILLIARDS_SOURCE_DIR
                            "/shapes/clover.yaml\nparameters: {g: 0.4, F: 10, omega: 320*pi}\ninitial:\n"
                            "  microcanonical: {energy: 1/2}\nforce:\n  periodic: {amplitude: [F/sqrt(2), F/sqrt(2)], "
                            "omega: omega}\nintegrator: {tolerance: 1e-8}\nrun: {particles: 3000, time: 8, seed: 5}\n";
  write_file(dir / "flat.yaml", scene);
  write_file(dir / "tilt.yaml", scene + "potential: {expression: g*y}\n");
  const auto coeffs = [&](const std::string& name) {
    const auto r = billiard("coeffs --json " + (dir / name).string());
    INFO(r.output);
    REQUIRE(r.status == 0);
    return nlohmann::json::parse(r.output);
  };
  const auto flat = coeffs("flat.yaml"), tilt = coeffs("tilt.yaml");
  CHECK(tilt["closed_form"] == false);
  CHECK(tilt["C"].is_null());
  CHECK(tilt["Sigma"].get<double>() < 0.95 * flat["Sigma"].get<double>());  // part of the table is forbidden
  CHECK(tilt["g2"].get<double>() > 1.5 * flat["g2"].get<double>());

  const auto r = billiard("run " + (dir / "tilt.yaml").string() + " --quiet --no-csv --threads 2 --out " +
                          (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  const auto summary = nlohmann::json::parse(read_file(dir / "out" / "summary.json"));
  CHECK(summary["escapes"] == 0);
  CHECK(summary["prediction"]["g2"] == tilt["g2"]);
  CHECK(std::abs(summary["mean_dE_deviation_se"].get<double>()) < 3);
  CHECK(std::abs(summary["var_dE_deviation_se"].get<double>()) < 3);
  CHECK(summary.count("fp_var_dE") == 0);  // no analytic Fokker–Planck solution with U ≠ 0
  const double se = summary["se_var_dE"];
  CHECK(std::abs(summary["var_dE"].get<double>() - 8 * flat["g2"].get<double>()) > 10 * se);
}

TEST_CASE("billiard run on field scenes: identical for 1 and 2 threads; a potential's energy is conserved") {
  for (const std::string scene : {"stadium-bowl", "clover-field"}) {
    const auto dir = scratch("field-run-" + scene);
    std::string energies[2];
    for (int threads = 1; threads <= 2; ++threads) {
      const auto out = dir / std::to_string(threads);
      const auto r = billiard("run scenes/" + scene + ".yaml --particles 24 --time 3 --quiet --no-csv --threads " +
                              std::to_string(threads) + " --out " + out.string());
      INFO(r.output);
      REQUIRE(r.status == 0);
      energies[threads - 1] = read_file(out / "energies.npy");
      if (scene == "stadium-bowl") {
        const auto summary = nlohmann::json::parse(read_file(out / "summary.json"));
        CHECK(summary["force"] == "none");
        CHECK(std::abs(summary["mean_dE"].get<double>()) < 1e-8);  // E = ½mv² + U, conserved
        CHECK(summary.count("prediction") == 0);
      }
    }
    CHECK(energies[0].size() >= 24 * 2 * 8);  // (two record times at least)
    CHECK(energies[0] == energies[1]);
  }
}
