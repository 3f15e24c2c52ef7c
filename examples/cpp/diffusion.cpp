// Energy diffusion in a driven billiard, from C++: a scene (the paper's driven clover unless a
// scene file is given), the theory's coefficients (billiards::analysis) and a small ensemble
// (billiards::dynamics) whose mean energy change and variance at the end time it prints next to
// the prediction <dE> = g1 t, Var(dE) = g2 t.
#include <billiards/analysis/coefficients.hpp>
#include <billiards/analysis/statistics.hpp>
#include <billiards/dynamics/scene_run.hpp>
#include <billiards/version.hpp>

#include <cstdio>
#include <exception>
#include <string>

using namespace billiards;

int main(int argc, char** argv) try {
  const std::string file = argc > 1 ? argv[1] : BILLIARDS_DATA_DIR "/scenes/clover-driven.yaml";
  dynamics::SceneOverrides overrides;
  overrides.particles = 200;
  overrides.time = 2;
  const dynamics::Scene scene = dynamics::load_scene(file, overrides);

  const auto c = analysis::prediction_of(scene);
  if (!c) throw std::runtime_error(file + ": the theory needs a periodic drive and a microcanonical start");

  // energies[i * m + k]: particle i at record time k (k = 0 is the start).
  const dynamics::EnsembleResult result = dynamics::with_flight(scene, [&](const auto& flight) {
    using Flight = std::decay_t<decltype(flight)>;
    const auto table = dynamics::table_of<Flight>(scene);
    return dynamics::run_ensemble(table, flight, dynamics::initial_states(scene, table, flight),
                                  dynamics::run_options<Flight>(scene, false), scene.particles, 1);
  });
  const std::size_t m = scene.record_times.size(), n = scene.particles;
  const auto dE = analysis::sample_moments(result.energy_changes(m - 1, m));

  std::printf("billiards %s\n", billiards::version);
  std::printf("scene %s\n", scene.file.c_str());
  std::printf("V %.17g\nS %.17g\nmean_free_path %.17g\nC %.17g\n", c->volume, c->surface, c->mean_free_path, c->C);
  std::printf("particles %zu\ntime %.17g\ncollisions %zu\n", n, scene.time, std::size_t(result.collisions()));
  std::printf("mean_dE %.17g +- %.2g (predicted %.6g)\n", dE.mean, dE.se_mean, c->g1 * scene.time);
  std::printf("var_dE %.17g +- %.2g (predicted %.6g)\n", dE.variance, dE.se_variance, c->g2 * scene.time);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "diffusion: error: %s\n", e.what());
  return 1;
}
