// billiard escape TABLE: escape times through the exits a shape file lists, the survival
// probability P(t) and the mean escape time against Kac's lemma; 2-D and 3-D.
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

/// Refuses a table without exits.
void require_exits(bool empty, const std::string& shape_file, const char* syntax) {
  if (empty)
    throw InputError(shape_file, 0, fmt::format("the shape lists no exits ('exits: [{}]'): nothing can escape", syntax));
}

/// The particles' escape records through the exits of the scene's table, in its dimension; the
/// exits' total length (area in 3-D) in `exit_measure`.
template <class Flight>
std::vector<analysis::EscapeRecord> escapes_of(const dynamics::Scene& scene, const Flight& flight,
                                               const EscapeArgs& args, const std::string& out_dir,
                                               double& exit_measure) {
  const auto table = dynamics::table_of<Flight>(scene);
  const auto run = [&](const auto& initial, const auto& leaves) {
    OutputDir::require_creatable(out_dir);
    Progress progress("escape", scene.particles, !args.quiet);
    auto records = analysis::escape_times(table, flight, initial, leaves, scene.particles, args.collisions,
                                          args.threads, [&](std::size_t d) { progress.update(d); });
    progress.finish();
    return records;
  };
  if constexpr (dynamics::is_3d<Flight>) {
    const analysis::Exits3 exits(analysis::read_exits3(scene.shape<3>()));
    require_exits(exits.empty(), scene.shape<3>().region.origin.file, "{disc: {center: [x, y, z], radius: r}}");
    exit_measure = exits.area();
    const auto enter = [&](double speed, auto& rng) { return exits.entering_state(speed, rng); };
    return run(analysis::open_table_initial_states(scene, table, flight, enter),
               [&](const auto& hit) { return exits.contains(hit.wall, hit.point); });
  } else {
    const analysis::BoundaryCoordinates coordinates(scene.shape<2>().region);
    const analysis::Exits exits(coordinates, analysis::read_exits(scene.shape<2>(), coordinates));
    require_exits(exits.empty(), scene.shape<2>().region.origin.file, "{from: [x1, y1], to: [x2, y2]}");
    exit_measure = exits.length();
    return run(analysis::open_table_initial_states(scene, table, flight, coordinates, exits),
               [&](const auto& hit) { return exits.contains(coordinates.s_of(table, hit)); });
  }
}

void run_escape(const EscapeArgs& args) {
  auto scene = load_phase_space_scene(args);
  refuse_forced_magnetic(scene, "billiard escape");
  if (args.entering) scene.through_exit = geometry::SourceRef{"--entering", 0};
  const std::string out_dir = !args.out.empty() ? args.out : scene.output_dir + "-escape";
  const double speed = std::sqrt(2 * scene.energy / scene.mass);
  double exit_measure = 0;
  const auto records = dynamics::with_flight(
      scene, [&](const auto& flight) { return escapes_of(scene, flight, args, out_dir, exit_measure); });

  const auto summary = analysis::summarize(records);
  std::string csv = "particle,escape_time,collisions,escaped\n";
  for (std::size_t i = 0; i < records.size(); ++i)
    csv += fmt::format("{},{:.17g},{},{}\n", i, records[i].time, records[i].collisions, int(records[i].escaped));
  const auto P = analysis::survival(summary.times, scene.particles);
  std::string survival_csv = "t,P\n";
  for (std::size_t k = 0; k < P.t.size(); ++k) survival_csv += fmt::format("{:.9g},{:.9g}\n", P.t[k], P.P[k]);
  const double V = scene.measures().volume;
  nlohmann::json j = {{"mean_escape_time", summary.mean},
                      {"mean_escape_time_se", summary.se},
                      {"exit_length", exit_measure},
                      {"kac_mean_escape_time", analysis::kac_mean_escape_time(V, exit_measure, speed, scene.dimension())},
                      {"dimension", scene.dimension()},
                      {"ensemble", scene.through_exit ? "through_exit" : scene.initial_csv.empty() ? "microcanonical" : "csv"},
                      {"particles", scene.particles},
                      {"escaped", summary.times.size()},
                      {"still_inside", summary.still_inside(scene.particles)},
                      {"max_collisions", args.collisions},
                      {"speed", speed},
                      {"V", V},
                      {"table", scene.file},
                      {"shape", scene.shape_name()},
                      {"force", scene.force.name()},
                      {"seed", scene.seed}};
  OutputDir out(out_dir);
  out.write_text("escape.csv", csv);
  out.write_text("survival.csv", survival_csv);
  out.write_json("escape.json", j);
  run_python(script_path("plot_escape.py"), {out.path("").string(), out.path("survival.png").string()});
  out.commit();
  if (args.json) {
    std::cout << j.dump(2) << "\n";
  } else {
    fmt::print("{}: {} of {} particles escaped through exits of total {} {:.6g}; mean escape time {:.6g} ± {:.2g} "
               "(Kac, entering ensemble: {} = {:.6g}); results in {}/\n",
               scene.shape_name(), summary.times.size(), scene.particles, scene.dimension() == 3 ? "area" : "length",
               exit_measure, summary.mean, summary.se, scene.dimension() == 3 ? "4 V/(A v)" : "pi V/(w v)",
               j["kac_mean_escape_time"].get<double>(), out_dir);
  }
  if (summary.still_inside(scene.particles) > 0)
    fmt::print(stderr, "billiard: warning: {} particle(s) still inside after {} collisions: the mean is over those that left\n",
               summary.still_inside(scene.particles), args.collisions);
  if (summary.lost > 0) {
    fmt::print(stderr, "billiard: error: {} particle(s) escaped the region through a wall\n", summary.lost);
    throw CLI::RuntimeError(3);
  }
}

}  // namespace

void add_escape(CLI::App& app) {
  auto* cmd = app.add_subcommand("escape", "Escape times through the exits a shape lists, and P(t)");
  auto args = std::make_shared<EscapeArgs>();
  add_phase_space_options(cmd, *args, 10000, 1000000);
  cmd->add_flag("--entering", args->entering,
                "particles enter through the exits (measure cos phi ds dphi) instead of starting inside: the scene "
                "key 'initial: {through_exit: {energy: E}}' on the command line");
  cmd->add_flag("--json", args->json, "print JSON");
  cmd->add_option("--out", args->out, "output directory (default: out/NAME-escape)");
  cmd->callback([args] { run_escape(*args); });
}

}  // namespace billiards::cli
