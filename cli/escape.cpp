// billiard escape TABLE: escape times through the exits a shape file lists, the survival
// probability P(t) and the mean escape time against Kac's lemma.  2-D only.
#include "commands.hpp"
#include "output.hpp"
#include "phase_space.hpp"
#include "progress.hpp"
#include "python.hpp"

#include "billiards/analysis/escape.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/dynamics/scene_run.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <iostream>

namespace billiards::cli {

namespace {

struct EscapeArgs : PhaseSpaceArgs {
  bool entering = false, json = false;
  std::string out;
};

/// P(t): the fraction of particles still inside at `points` times up to the last escape.
std::string survival_csv(std::vector<double> times, std::size_t particles) {
  std::sort(times.begin(), times.end());
  std::string csv = "t,P\n";
  const double end = times.empty() ? 0 : times.back();
  constexpr int points = 400;
  for (int k = 0; k <= points; ++k) {
    const double t = end * k / points;
    const auto left = std::size_t(times.end() - std::upper_bound(times.begin(), times.end(), t));
    csv += fmt::format("{:.9g},{:.9g}\n", t, double(particles - times.size() + left) / double(particles));
  }
  return csv;
}

void run_escape(const EscapeArgs& args) {
  auto scene = load_phase_space_scene(args, "escape");
  const analysis::BoundaryCoordinates coordinates(scene.shape.region);
  const analysis::Exits exits(coordinates, analysis::read_exits(scene.shape, coordinates));
  if (exits.empty())
    throw InputError(scene.shape.region.origin.file, 0,
                     "the shape lists no exits ('exits: [{from: [x1, y1], to: [x2, y2]}]'): nothing can escape");
  const std::string out_dir = !args.out.empty() ? args.out : scene.output_dir + "-escape";
  OutputDir::require_creatable(out_dir);
  const double speed = std::sqrt(2 * scene.energy / scene.mass);
  Progress progress("escape", scene.particles, !args.quiet);
  const auto records = dynamics::with_flight(scene, [&](const auto& flight) {
    using Flight = std::decay_t<decltype(flight)>;
    if constexpr (dynamics::is_3d<Flight>) {
      throw InputError(scene.file, 0, "escape works on 2-D tables only");
      return std::vector<analysis::EscapeRecord>{};
    } else {
      const auto table = dynamics::table_of<Flight>(scene);
      const auto inside = dynamics::initial_states(scene, table, flight);
      const auto initial = [&](std::size_t i) {
        if (!args.entering) return inside(i);
        dynamics::ParticleRng rng(scene.seed, i);
        return flight.start(analysis::entering_state(coordinates, exits, speed, rng));
      };
      return analysis::escape_times(table, coordinates, exits, flight, initial, scene.particles, args.collisions,
                                    args.threads, [&](std::size_t d) { progress.update(d); });
    }
  });
  progress.finish();

  std::vector<double> times;
  std::size_t lost = 0;
  std::string csv = "particle,escape_time,collisions,escaped\n";
  for (std::size_t i = 0; i < records.size(); ++i) {
    const auto& r = records[i];
    lost += r.lost;
    if (r.escaped) times.push_back(r.time);
    csv += fmt::format("{},{:.17g},{},{}\n", i, r.time, r.collisions, int(r.escaped));
  }
  const auto m = times.size() >= 2 ? analysis::sample_moments(times) : analysis::SampleMoments{};
  const double V = scene.measures().volume;
  nlohmann::json j = {{"mean_escape_time", m.mean},
                      {"mean_escape_time_se", m.se_mean},
                      {"exit_length", exits.length()},
                      {"kac_mean_escape_time", geometry::pi * V / (exits.length() * speed)},
                      {"ensemble", args.entering ? "through_exit" : "microcanonical"},
                      {"particles", scene.particles},
                      {"escaped", times.size()},
                      {"still_inside", scene.particles - times.size() - lost},
                      {"max_collisions", args.collisions},
                      {"speed", speed},
                      {"V", V},
                      {"table", scene.file},
                      {"shape", scene.shape_name()},
                      {"force", scene.force.name()},
                      {"seed", scene.seed}};
  OutputDir out(out_dir);
  out.write_text("escape.csv", csv);
  out.write_text("survival.csv", survival_csv(times, scene.particles));
  out.write_json("escape.json", j);
  run_python(script_path("plot_escape.py"), {out.path("").string(), out.path("survival.png").string()});
  out.commit();
  if (args.json) {
    std::cout << j.dump(2) << "\n";
  } else {
    fmt::print("{}: {} of {} particles escaped through exits of total length {:.6g}; mean escape time {:.6g} ± {:.2g} "
               "(Kac, entering ensemble: pi V/(w v) = {:.6g}); results in {}/\n",
               scene.shape_name(), times.size(), scene.particles, exits.length(), m.mean, m.se_mean,
               j["kac_mean_escape_time"].get<double>(), out_dir);
  }
  if (times.size() + lost < scene.particles)
    fmt::print(stderr, "billiard: warning: {} particle(s) still inside after {} collisions: the mean is over those that left\n",
               scene.particles - times.size() - lost, args.collisions);
  if (lost > 0) {
    fmt::print(stderr, "billiard: error: {} particle(s) escaped the region through a wall\n", lost);
    throw CLI::RuntimeError(3);
  }
}

}  // namespace

void add_escape(CLI::App& app) {
  auto* cmd = app.add_subcommand("escape", "Escape times through the exits a shape lists, and P(t) (2-D)");
  auto args = std::make_shared<EscapeArgs>();
  add_phase_space_options(cmd, *args, 10000, 1000000);
  cmd->add_flag("--entering", args->entering,
                "particles enter through the exits (measure cos phi ds dphi) instead of starting inside");
  cmd->add_flag("--json", args->json, "print JSON");
  cmd->add_option("--out", args->out, "output directory (default: out/NAME-escape)");
  cmd->callback([args] { run_escape(*args); });
}

}  // namespace billiards::cli
