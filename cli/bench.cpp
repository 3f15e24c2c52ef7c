// billiard bench speed-error: the toolkit's exact driven flight against an Odeint baseline on the
// same initial conditions (analysis/speed_error.hpp), written as speed-error.csv and drawn as
// speed-error.png by scripts/plot_speed_error.py.
#include "commands.hpp"
#include "output.hpp"
#include "python.hpp"

#include "billiards/dynamics/scene.hpp"
#include "billiards/dynamics/table.hpp"
#include "billiards/analysis/speed_error.hpp"

#include <fmt/core.h>

#include <cmath>
#include <string>
#include <vector>

namespace billiards::cli {

namespace {

struct SpeedErrorArgs {
  std::string scene = (data_dir() / "scenes/clover-driven.yaml").string();
  std::vector<std::string> omegas = {"40*pi", "320*pi"};
  std::string out = "out/speed-error";
  bool quick = false;
  std::size_t particles = 0, mpfr_particles = 0;  // 0: the defaults of the mode
};

std::string csv_row(const analysis::SpeedErrorRow& r) {
  return fmt::format("{},{:.17g},{:.17g},{:.3g},{},{},{},{:.6g},{:.17g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n",
                     r.method, r.omega, r.omega / geometry::pi, r.tolerance, r.particles, r.escapes, r.unconfirmed,
                     r.cpu_seconds_per_time, r.var_dE, r.var_dE_error, r.var_dE_se, r.median_position_error,
                     r.median_first_collision_error, r.collisions_per_particle);
}

void print_rows(const std::vector<analysis::SpeedErrorRow>& rows) {
  fmt::print("  {:<7} {:>8} {:>12} {:>12} {:>10} {:>10} {:>10} {:>8} {:>7}\n", "method", "tol", "cpu s/t/part",
             "Var(dE)", "|err Var|", "|dx| end", "|dx| 1st", "escapes", "coll.");
  for (const auto& r : rows)
    fmt::print("  {:<7} {:>8.0e} {:>12.3e} {:>12.6e} {:>10.2e} {:>10.2e} {:>10.2e} {:>8} {:>7.2f}\n", r.method,
               r.tolerance, r.cpu_seconds_per_time, r.var_dE, r.var_dE_error, r.median_position_error,
               r.median_first_collision_error, r.escapes + r.unconfirmed, r.collisions_per_particle);
}

void speed_error(const SpeedErrorArgs& args) {
  analysis::SpeedErrorOptions opt;
  opt.tolerances = args.quick ? std::vector<double>{1e-3, 1e-5, 1e-7, 1e-9}
                              : std::vector<double>{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};
  opt.particles = args.particles ? args.particles : args.quick ? 24 : 200;
  opt.mpfr_particles = args.mpfr_particles ? args.mpfr_particles : args.quick ? 8 : 50;
  std::string csv =
      "method,omega,omega_over_pi,tolerance,particles,escapes,unconfirmed,cpu_seconds_per_time,var_dE,var_dE_error,"
      "var_dE_se,median_position_error,median_first_collision_error,collisions_per_particle\n";
  const auto as_given = dynamics::load_scene(args.scene);
  if (as_given.force.kind != dynamics::Force::Kind::periodic)
    throw InputError(as_given.file, 0, "bench speed-error needs a periodic drive");
  if (!as_given.initial_csv.empty())
    throw InputError(as_given.file, 0, "bench speed-error needs a microcanonical start");
  if (as_given.dimension() != 2) throw InputError(as_given.file, 0, "bench speed-error runs 2-D scenes only");
  for (const auto& omega : args.omegas) {
    dynamics::SceneOverrides overrides;
    overrides.set["omega"] = omega;  // the scene's parameter, so that the drive may use it
    const auto scene = dynamics::load_scene(args.scene, overrides);
    opt.t_end = scene.time;
    opt.mass = scene.mass;
    opt.energy = scene.energy;
    opt.seed = scene.seed;
    const dynamics::Table table(scene.shape<2>().region);
    const dynamics::PeriodicDriveFlight flight{dynamics::Vec2(scene.force.amplitude / scene.mass), scene.force.omega,
                                               scene.force.phase};
    fmt::print("omega = {} = {:.6g}: {} particles to t = {}, {} checked in MPFR\n", omega, flight.omega,
               opt.particles, opt.t_end, std::min(opt.particles, opt.mpfr_particles));
    std::fflush(stdout);
    const auto rows = analysis::speed_error(table, flight, opt);
    print_rows(rows);
    for (const auto& r : rows) csv += csv_row(r);
    const auto ratios = analysis::speed_ratios(rows);
    const auto report = [&](const char* what, const analysis::SpeedErrorRow* r) {
      if (r)
        fmt::print("  odeint / exact CPU time, {}: {:.0f} (tolerance {:.0e}, error {:.2e})\n", what, ratios.ratio(r),
                   r->tolerance, r->var_dE_error);
      else
        fmt::print("  odeint / exact CPU time, {}: no tolerance reaches it\n", what);
    };
    report("at the exact flight's error in Var(dE)", ratios.equal);
    report("at an error in Var(dE) below its sampling SE", ratios.within_se);
    report("at the cheapest tolerance", ratios.cheapest);
  }
  OutputDir out(args.out);
  out.write_text("speed-error.csv", csv);
  run_python(script_path("plot_speed_error.py"),
             {out.path("speed-error.csv").string(), out.path("speed-error.png").string()});
  out.commit();
  fmt::print("wrote {0}/speed-error.csv and {0}/speed-error.png\n", args.out);
}

}  // namespace

void add_bench(CLI::App& app) {
  auto* cmd = app.add_subcommand("bench", "Benchmarks");
  cmd->require_subcommand(1);
  auto* se = cmd->add_subcommand(
      "speed-error", "CPU time against error: the exact driven flight and an Odeint (dopri5) baseline");
  auto args = std::make_shared<SpeedErrorArgs>();
  se->add_option("scene", args->scene, "scene with a periodic drive and a microcanonical start")
      ->capture_default_str();
  se->add_flag("--quick", args->quick, "a few particles and tolerances (< 30 s)");
  se->add_option("--omega", args->omegas, "drive frequencies (expressions, e.g. 320*pi); repeatable")
      ->expected(1, -1)
      ->capture_default_str();
  se->add_option("--particles", args->particles, "particles (same initial conditions for every method)")
      ->check(CLI::Range(std::size_t(2), std::size_t(1) << 30));
  se->add_option("--mpfr-particles", args->mpfr_particles, "particles of the exact flight checked in MPFR")
      ->check(CLI::Range(std::size_t(2), std::size_t(1) << 30));
  se->add_option("--out", args->out, "output directory (speed-error.csv, speed-error.png)")
      ->capture_default_str();
  se->callback([args] { speed_error(*args); });
}

}  // namespace billiards::cli
