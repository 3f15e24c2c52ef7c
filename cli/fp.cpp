// billiard fp SCENE --times 10,100,1000 -o fp.csv: the energy distribution predicted by the
// Fokker–Planck equation, numerically (Chang–Cooper) and analytically (U = 0) side by side; with
// a potential, numerically only.
#include "commands.hpp"
#include "options.hpp"
#include "output.hpp"

#include "billiards/analysis.hpp"
#include "billiards/dynamics/scene.hpp"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace billiards::cli {

namespace {

struct FpArgs {
  std::string scene, output;
  std::vector<double> times;
  int cells = 4000;
  std::vector<std::string> set;
  dynamics::SceneOverrides overrides;
};

void fp(FpArgs& args) {
  args.overrides.set = parse_overrides(args.set);
  const auto scene = dynamics::load_scene(args.scene, args.overrides);
  const auto c = analysis::prediction_of(scene);
  if (!c)
    throw InputError(args.scene, 0, "fp needs a periodic force (uniform or field) and a microcanonical initial energy");
  std::sort(args.times.begin(), args.times.end());
  args.times.erase(std::unique(args.times.begin(), args.times.end()), args.times.end());
  if (args.times.empty() || !(args.times.front() > 0)) throw InputError("--times", 0, "times must be positive");
  const int d = c->dimension;
  const double E0 = scene.energy;
  const auto solution = *analysis::fokker_planck_of(scene, args.times, args.cells);
  const auto& grid = solution.grid;
  warn_if_coarse(solution);
  // With a potential there is no analytic solution: numerical columns only.
  std::string csv = "E";
  for (double t : args.times)
    csv += c->closed_form ? fmt::format(",eta_numerical(t={0}),eta_analytic(t={0})", t)
                          : fmt::format(",eta_numerical(t={})", t);
  csv += "\n";
  for (std::size_t i = 0; i < grid.cells(); ++i) {
    csv += fmt::format("{:.10g}", grid.center(i));
    for (std::size_t k = 0; k < args.times.size(); ++k) {
      csv += fmt::format(",{:.10g}", solution.eta[k][i]);
      if (c->closed_form)
        csv += fmt::format(",{:.10g}", analysis::fokker_planck_eta(grid.center(i), c->C * args.times[k], E0, d));
    }
    csv += "\n";
  }
  write_file_atomically(args.output, csv);
  if (c->closed_form)
    fmt::print("wrote {}: eta(E, t) at t = {} (C = {:.6g})\n", args.output, fmt::join(args.times, ", "), c->C);
  else
    fmt::print("wrote {}: eta(E, t) at t = {}, numerical only (U != 0: no analytic solution); {} cells on E = "
               "{:.6g} .. {:.6g}, {} evaluations of g1, g2\n",
               args.output, fmt::join(args.times, ", "), grid.cells(), grid.edges.front(), grid.edges.back(),
               solution.evaluations);
}

}  // namespace

void warn_if_coarse(const analysis::FokkerPlanckSolution& solution) {
  if (solution.resolution < 5)
    fmt::print(stderr,
               "warning: the first time's spread covers {:.2g} cells of the Fokker-Planck grid (one grid serves "
               "every time): its eta is smeared by the cells; use more --cells\n",
               solution.resolution);
}

void add_fp(CLI::App& app) {
  auto* cmd = app.add_subcommand("fp", "Fokker-Planck prediction of the energy distribution (numerical, and analytic for U = 0)");
  auto args = std::make_shared<FpArgs>();
  cmd->add_option("scene", args->scene, "scene file (YAML)")->required();
  cmd->add_option("--times", args->times, "times t1,t2,... at which to write eta(E, t)")->delimiter(',')->required()->transform(expression_value);
  cmd->add_option("-o,--output", args->output, "CSV file to write")->required();
  cmd->add_option("--cells", args->cells, "energy cells (default 4000)")->check(CLI::Range(10, 10000000));
  cmd->add_option("--omega", args->overrides.omega, "drive frequency (an expression: 320*pi)")->transform(expression_value);
  add_set_option(cmd, args->set);
  cmd->callback([args] { fp(*args); });
}

}  // namespace billiards::cli
