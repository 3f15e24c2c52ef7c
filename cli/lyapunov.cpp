// billiard lyapunov SHAPE|SCENE: the Lyapunov spectrum from tangent dynamics, per unit time and
// per collision, each with its standard error over independent trajectories; 4 exponents in 2-D,
// 6 in 3-D.
#include "commands.hpp"
#include "phase_space.hpp"
#include "progress.hpp"

#include "billiards/analysis/lyapunov.hpp"
#include "billiards/dynamics/scene_run.hpp"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <iostream>
#include <variant>

namespace billiards::cli {

namespace {

template <int D>
nlohmann::json spectrum_json(const analysis::BasicLyapunovSpectrum<D>& r, const dynamics::Scene& scene,
                             std::size_t collisions) {
  const auto means = [](const auto& e) {
    std::vector<double> m;
    for (const auto& x : e) m.push_back(x.mean);
    return m;
  };
  const auto ses = [](const auto& e) {
    std::vector<double> m;
    for (const auto& x : e) m.push_back(x.se);
    return m;
  };
  double time = 0, bounces = 0;
  for (const auto& t : r.trajectories) time += t.time, bounces += double(t.collisions);
  return {{"lyapunov", r.per_time[0].mean},
          {"lyapunov_se", r.per_time[0].se},
          {"lyapunov_per_collision", r.per_collision[0].mean},
          {"lyapunov_per_collision_se", r.per_collision[0].se},
          {"spectrum", means(r.per_time)},
          {"spectrum_se", ses(r.per_time)},
          {"spectrum_per_collision", means(r.per_collision)},
          {"spectrum_per_collision_se", ses(r.per_collision)},
          {"mean_free_time", time / bounces},
          {"speed", std::sqrt(2 * scene.energy / scene.mass)},
          {"particles", scene.particles},
          {"collisions", collisions},
          {"dimension", D},
          {"table", scene.file},
          {"shape", scene.shape_name()},
          {"force", scene.force.name()},
          {"magnetic", scene.magnetic()},
          {"seed", scene.seed},
          {"escapes", r.escapes()},
          {"trapped", r.trapped()}};
}

using AnySpectrum = std::variant<analysis::BasicLyapunovSpectrum<2>, analysis::BasicLyapunovSpectrum<3>>;

/// The scene's spectrum over args.collisions bounces of each particle; exit status 3 if a
/// particle escaped.
AnySpectrum lyapunov_of(const dynamics::Scene& scene, const PhaseSpaceArgs& args) {
  Progress progress("lyapunov", scene.particles, !args.quiet);
  const auto r = dynamics::with_flight(scene, [&](const auto& flight) -> AnySpectrum {
    using Flight = std::decay_t<decltype(flight)>;
    if constexpr (analysis::tangent_flight<Flight>) {
      const auto table = dynamics::table_of<Flight>(scene);
      return analysis::lyapunov_spectrum(table, flight, dynamics::initial_states(scene, table, flight), scene.particles,
                                         args.collisions, args.threads, [&](std::size_t d) { progress.update(d); });
    } else {
      throw InputError(scene.file, 0,
                       fmt::format("Lyapunov exponents are computed for {}; not for a position-dependent force or "
                                   "a potential (this scene: force {}{})",
                                   analysis::tangent_flights_named, scene.force.name(),
                                   scene.potential ? ", a potential" : ""));
    }
  });
  progress.finish();
  const auto escapes = std::visit([](const auto& s) { return s.escapes(); }, r);
  if (escapes > 0) {
    fmt::print(stderr, "billiard: error: {} particle(s) escaped the region\n", escapes);
    throw CLI::RuntimeError(3);
  }
  return r;
}

template <int D>
void print_spectrum(const analysis::BasicLyapunovSpectrum<D>& r, const dynamics::Scene& scene, std::size_t collisions,
                    const nlohmann::json& j) {
  fmt::print("{} ({}{}): {} trajectories x {} collisions, speed {:.6g}, mean free time {:.6g}\n", scene.shape_name(),
             scene.force.name(), scene.magnetic() ? ", magnetic field" : "", scene.particles, collisions,
             j["speed"].get<double>(), j["mean_free_time"].get<double>());
  fmt::print("maximal exponent: {:.6g} ± {:.2g} per unit time, {:.6g} ± {:.2g} per collision\n", r.per_time[0].mean,
             r.per_time[0].se, r.per_collision[0].mean, r.per_collision[0].se);
  for (int k = 0; k < 2 * D; ++k)
    fmt::print("  lambda_{} = {:+.6g} ± {:.2g} per unit time\n", k + 1, r.per_time[k].mean, r.per_time[k].se);
  if (r.trapped() > 0)
    fmt::print("{} particle(s) left out: on closed cyclotron orbits that meet no wall\n", r.trapped());
}

}  // namespace

void add_lyapunov(CLI::App& app) {
  auto* cmd = app.add_subcommand("lyapunov", "Lyapunov exponents from tangent dynamics (2-D: 4, 3-D: 6)");
  struct Args : PhaseSpaceArgs {
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  add_phase_space_options(cmd, *args, 16, 20000);
  cmd->add_flag("--json", args->json, "print JSON");
  cmd->callback([args] {
    const auto scene = load_phase_space_scene(*args);
    std::visit(
        [&](const auto& r) {
          const auto j = spectrum_json(r, scene, args->collisions);
          if (args->json) std::cout << j.dump(2) << "\n";
          else print_spectrum(r, scene, args->collisions, j);
        },
        lyapunov_of(scene, *args));
  });
}

}  // namespace billiards::cli
