// billiard coeffs SCENE: the theory's prediction, before any dynamics.
#include "commands.hpp"
#include "options.hpp"

#include "billiards/analysis.hpp"
#include "billiards/dynamics/scene.hpp"

#include <fmt/core.h>

#include <iostream>

namespace billiards::cli {

std::optional<analysis::Coefficients> prediction_of(const dynamics::Scene& scene) {
  using Kind = dynamics::Force::Kind;
  const Kind kind = scene.force.kind;
  if (scene.energy <= 0 || (kind != Kind::periodic && kind != Kind::field)) return std::nullopt;
  if (kind == Kind::periodic && !scene.potential) {
    analysis::Drive drive;
    drive.F = scene.force.amplitude;
    drive.omega = scene.force.omega;
    drive.mass = scene.mass;
    return analysis::coefficients(scene.measures(), drive, scene.energy);
  }
  // A field amplitude or a potential: quadrature along the wall (2-D scenes only).
  const auto& field = scene.force.field;
  const geometry::Vec2 uniform = kind == Kind::periodic ? geometry::Vec2(scene.force.amplitude) : geometry::Vec2::Zero();
  const analysis::ForceField F = [&](const geometry::Vec2& x) {
    return kind == Kind::field ? geometry::Vec2(field[0](x), field[1](x)) : uniform;
  };
  const auto& region = scene.shape.region;
  if (!scene.potential) return analysis::coefficients(region, F, scene.force.omega, scene.mass, scene.energy);
  const auto& U = scene.potential->U;
  return analysis::coefficients(region, [&](const geometry::Vec2& x) { return U(x); }, F, scene.force.omega,
                                scene.mass, scene.energy);
}

void print_prediction(const analysis::Coefficients& c, double dt) {
  const auto pm = [](double error) { return error > 0 ? fmt::format(" (± {:.2g})", error) : std::string(); };
  const std::string C = c.closed_form ? fmt::format("{:.6g}", c.C) : "none (potential)";
  fmt::print("prediction (E = {:g}): lambda = {:.6g}, wall integral = {:.6g}{}, C = {}\n", c.energy,
             c.mean_free_path, c.wall_integral, pm(c.wall_integral_error), C);
  fmt::print("  g1 = {:.6g}{}, g2 = {:.6g}{}; over dt = {:g}: <dE> = {:.6g}, Var(dE) = {:.6g}\n", c.g1,
             pm(c.g1_error), c.g2, pm(c.g2_error), dt, c.g1 * dt, c.g2 * dt);
  fmt::print("  validity: F/(m omega v) = {:.3g}, v/(omega lambda) = {:.3g} (both must be << 1)\n", c.force_ratio,
             c.length_ratio);
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
    const auto c = prediction_of(scene);
    if (!c)
      throw InputError(args->scene, 0,
                       "coeffs needs a periodic force (uniform or field) and a microcanonical initial energy");
    if (args->json)
      std::cout << nlohmann::json(*c).dump(2) << "\n";
    else
      print_prediction(*c, scene.time);
  });
}

}  // namespace billiards::cli
