// billiard chaos SHAPE: the evidence that the undriven table is chaotic and ergodic, which the
// energy-diffusion theory assumes; and the short form of the same check that `coeffs` and
// `compare` print beside their prediction; 2-D and 3-D (analysis/chaos.hpp for the cells).
#include "commands.hpp"
#include "phase_space.hpp"
#include "progress.hpp"

#include "billiards/analysis/chaos.hpp"

#include <fmt/core.h>

#include <iostream>

namespace billiards::cli {

namespace {

nlohmann::json verdict_json(const analysis::ChaosVerdict& v, const analysis::ChaosOptions& o) {
  nlohmann::json orbits = nlohmann::json::array();
  for (const auto& e : v.orbits)
    orbits.push_back({{"lyapunov", e.lyapunov}, {"lyapunov_per_collision", e.lyapunov_per_collision},
                      {"distance", e.distance}, {"coverage", e.coverage}, {"escaped", e.escaped}});
  return {{"ergodic", v.ergodic()},
          {"chaotic", v.chaotic},
          {"uniform", v.uniform},
          {"lyapunov", v.lyapunov.mean},
          {"lyapunov_se", v.lyapunov.se},
          {"lyapunov_per_collision", v.lyapunov_per_collision.mean},
          {"lyapunov_per_collision_se", v.lyapunov_per_collision.se},
          {"pooled_distance", v.pooled_distance},
          {"pooled_coverage", v.pooled_coverage},
          {"noise_distance", v.noise_distance},
          {"min_exponent_per_collision", o.min_exponent_per_collision},
          {"max_distance", o.max_distance},
          {"cells", {v.position_cells, o.cells_p}},
          {"orbits", o.orbits},
          {"collisions", o.collisions},
          {"seed", o.seed},
          {"per_orbit", orbits}};
}

/// Why the verdict is what it is, in one line.
std::string reason_of(const analysis::ChaosVerdict& v, const analysis::ChaosOptions& o) {
  double least_exponent = 1e300, worst_distance = 0;
  for (const auto& e : v.orbits)
    least_exponent = std::min(least_exponent, e.lyapunov_per_collision), worst_distance = std::max(worst_distance, e.distance);
  return fmt::format("smallest orbit exponent {:.3g} per collision (chaotic above {:g}); largest distance of an "
                     "orbit's boundary map from uniform {:.3g} (uniform below {:g}; noise alone {:.2g})",
                     least_exponent, o.min_exponent_per_collision, worst_distance, o.max_distance, v.noise_distance);
}

}  // namespace

nlohmann::json ergodicity_check(const geometry::Region2& region) {
  analysis::ChaosOptions o;
  o.orbits = 8;
  o.collisions = 20000;
  const auto v = analysis::chaos_of(region, o);
  auto j = verdict_json(v, o);
  j["reason"] = reason_of(v, o);
  return j;
}

void print_ergodicity(const nlohmann::json& check) {
  if (check["ergodic"].get<bool>()) {
    fmt::print("  chaos check: the undriven table is chaotic and ergodic (maximal exponent {:.4g} ± {:.2g} per unit "
               "time at speed 1)\n",
               check["lyapunov"].get<double>(), check["lyapunov_se"].get<double>());
    return;
  }
  fmt::print("  warning: the undriven table is NOT chaotic and ergodic ({}), so the prediction's assumption fails and "
             "g1, g2 need not describe its dynamics ('billiard chaos' gives the evidence)\n",
             check["reason"].get<std::string>());
}

void add_chaos(CLI::App& app) {
  auto* cmd = app.add_subcommand("chaos", "Is the undriven table chaotic and ergodic? (the theory's assumption)");
  struct Args : PhaseSpaceArgs {
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  const analysis::ChaosOptions defaults;
  add_phase_space_options(cmd, *args, defaults.orbits, defaults.collisions);
  cmd->add_flag("--json", args->json, "print JSON");
  cmd->callback([args] {
    const auto scene = load_phase_space_scene(*args);
    analysis::ChaosOptions o;
    o.orbits = scene.particles;
    o.collisions = args->collisions;
    o.seed = scene.seed;
    o.threads = args->threads;
    Progress progress("chaos", o.orbits, !args->quiet);
    const auto tick = [&](std::size_t d) { progress.update(d); };
    const auto v = scene.dimension() == 3 ? analysis::chaos_of(scene.shape<3>().region, o, tick)
                                        : analysis::chaos_of(scene.shape<2>().region, o, tick);
    progress.finish();
    if (args->json) {
      std::cout << verdict_json(v, o).dump(2) << "\n";
      return;
    }
    fmt::print("{}: {} free orbits x {} collisions at speed 1\n", scene.shape_name(), o.orbits, o.collisions);
    fmt::print("maximal Lyapunov exponent: {:.6g} ± {:.2g} per unit time, {:.6g} ± {:.2g} per collision\n",
               v.lyapunov.mean, v.lyapunov.se, v.lyapunov_per_collision.mean, v.lyapunov_per_collision.se);
    fmt::print("boundary map against {} on {} x {} cells: pooled distance {:.3g}, coverage {:.3g}\n",
               scene.dimension() == 3 ? "dA cos(theta) dOmega (walls x cos^2 theta)" : "ds dp", v.position_cells,
               o.cells_p, v.pooled_distance, v.pooled_coverage);
    for (std::size_t i = 0; i < v.orbits.size(); ++i) {
      const auto& e = v.orbits[i];
      fmt::print("  orbit {:>3}: exponent {:.4g} per collision, distance {:.3g}, coverage {:.3g}\n", i,
                 e.lyapunov_per_collision, e.distance, e.coverage);
    }
    fmt::print("ergodic: {} ({})\n", v.ergodic() ? "true" : "false", reason_of(v, o));
  });
}

}  // namespace billiards::cli
