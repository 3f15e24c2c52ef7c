// billiard coeffs SCENE: the theory's prediction, before any dynamics.
#include "commands.hpp"
#include "options.hpp"
#include "phase_space.hpp"

#include "billiards/analysis.hpp"
#include "billiards/dynamics/scene.hpp"

#include <fmt/core.h>

#include <iostream>

namespace billiards::cli {

void print_prediction(const analysis::Coefficients& c, double dt) {
  const auto pm = [](double error) { return error > 0 ? fmt::format(" (± {:.2g})", error) : std::string(); };
  const std::string C = c.closed_form ? fmt::format("{:.6g}", c.C) : "none (potential)";
  fmt::print("prediction (E = {:g}): lambda = {:.6g}, wall integral = {:.6g}{}, C = {}\n", c.energy,
             c.mean_free_path, c.wall_integral, pm(c.wall_integral_error), C);
  fmt::print("  g1 = {:.6g}{}, g2 = {:.6g}{}; over dt = {:g}: <dE> = {:.6g}, Var(dE) = {:.6g}\n", c.g1,
             pm(c.g1_error), c.g2, pm(c.g2_error), dt, c.g1 * dt, c.g2 * dt);
  fmt::print("  validity: F/(m omega v) = {:.3g}, v/(omega lambda) = {:.3g} (both must be << 1)\n", c.force_ratio,
             c.length_ratio);
  if (c.cyclotron_radius > 0 && c.dimension == 2)
    fmt::print("  magnetic field: r_c = {:.3g}, inradius = {:.3g} (every orbit meets the wall when r_c >= inradius), "
               "omega/|Omega| = {:.3g} (must be >> 1)\n",
               c.cyclotron_radius, c.inradius, c.drive_over_cyclotron);
  if (c.cyclotron_radius > 0 && c.dimension == 3)
    fmt::print("  magnetic field: r_c = {:.3g} (every orbit with a velocity component along B drifts to the wall; "
               "only the measure-zero set v perpendicular to B can circle without meeting it), "
               "omega/|Omega| = {:.3g} (must be >> 1)\n",
               c.cyclotron_radius, c.drive_over_cyclotron);
  for (const auto& w : c.warnings) fmt::print("  warning: {}\n", w);
}

void add_coeffs(CLI::App& app) {
  auto* cmd = app.add_subcommand("coeffs", "The energy-diffusion prediction of a driven scene, before any dynamics");
  struct Args {
    std::string scene;
    bool json = false;
    dynamics::SceneOverrides overrides;
    std::vector<std::string> set;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("scene", args->scene, "scene file (YAML)")->required();
  cmd->add_flag("--json", args->json, "print JSON");
  cmd->add_option("--omega", args->overrides.omega, "drive frequency (an expression: 320*pi)")->transform(expression_value);
  add_set_option(cmd, args->set);
  cmd->callback([args] {
    args->overrides.set = parse_overrides(args->set);
    const auto scene = dynamics::load_scene(args->scene, args->overrides);
    const auto c = analysis::prediction_of(scene);
    if (!c)
      throw InputError(args->scene, 0,
                       "coeffs needs a periodic force (uniform or field) and a microcanonical initial energy");
    // The theory assumes a chaotic, ergodic undriven table: its verdict beside the prediction.
    const auto chaos = scene.dimension() == 2 ? ergodicity_check(scene.shape<2>().region) : nlohmann::json();
    if (args->json) {
      auto j = nlohmann::json(*c);
      j["chaos_check"] = chaos;
      std::cout << j.dump(2) << "\n";
    } else {
      print_prediction(*c, scene.time);
      if (!chaos.is_null()) print_ergodicity(chaos);
    }
  });
}

}  // namespace billiards::cli
