// billiard run SCENE: an ensemble run with the prediction before and the measurement after.
#include "commands.hpp"
#include "options.hpp"
#include "output.hpp"
#include "progress.hpp"

#include "billiards/analysis/fokker_planck.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/scene.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <omp.h>

#include <chrono>
#include <type_traits>
#include <filesystem>
#include <fstream>

namespace billiards::cli {

namespace {

namespace fs = std::filesystem;
using dynamics::EnsembleResult;
using dynamics::Scene;

struct RunArgs {
  std::string scene;
  dynamics::SceneOverrides overrides;
  int threads = 0;
  bool verify = false;
  bool quiet = false;
  std::size_t max_chunks = 0;  // 0: no limit
  std::vector<std::string> set;
};

/// Thrown when --max-chunks stops a run early; the checkpoint stays for the next run.
struct Interrupted {};

/// Particles run in chunks; each finished chunk is saved under <out>.partial so that an
/// interrupted run resumes where it stopped.  Particles are independent and each depends on
/// (seed, index) only, so a resumed run is identical to an uninterrupted one.
class Checkpoint {
 public:
  Checkpoint(const fs::path& out, std::string fingerprint)
      : dir_(fs::path(out.string() + ".partial")), fingerprint_(std::move(fingerprint)) {
    std::ifstream in(dir_ / "fingerprint.json");
    std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (old != fingerprint_) {  // another scene or other parameters: start afresh
      fs::remove_all(dir_);
      fs::create_directories(dir_);
      std::ofstream(dir_ / "fingerprint.json") << fingerprint_;
    }
  }

  bool load(std::size_t first, std::size_t last, std::size_t m, EnsembleResult& r) const {
    std::ifstream in(chunk(first, last), std::ios::binary);
    if (!in) return false;
    in.read(reinterpret_cast<char*>(&r.energies[first * m]), std::streamsize((last - first) * m * sizeof(double)));
    in.read(reinterpret_cast<char*>(&r.logs[first]), std::streamsize((last - first) * sizeof(dynamics::ParticleLog)));
    return bool(in);
  }

  void save(std::size_t first, std::size_t last, std::size_t m, const EnsembleResult& r) const {
    const fs::path tmp = chunk(first, last).string() + ".tmp";
    {
      std::ofstream out(tmp, std::ios::binary);
      out.write(reinterpret_cast<const char*>(&r.energies[first * m]), std::streamsize((last - first) * m * sizeof(double)));
      out.write(reinterpret_cast<const char*>(&r.logs[first]), std::streamsize((last - first) * sizeof(dynamics::ParticleLog)));
    }
    fs::rename(tmp, chunk(first, last));
  }

  void remove() const { fs::remove_all(dir_); }

 private:
  fs::path chunk(std::size_t first, std::size_t last) const {
    return dir_ / fmt::format("chunk-{}-{}.bin", first, last);
  }
  fs::path dir_;
  std::string fingerprint_;
};

/// Mean and variance of ΔE with their standard errors (the variance's from the fourth moment).
nlohmann::json delta_stats(const std::vector<double>& dE) {
  const double n = double(dE.size());
  double mean = 0;
  for (double x : dE) mean += x;
  mean /= n;
  double m2 = 0, m4 = 0;
  for (double x : dE) {
    const double d2 = (x - mean) * (x - mean);
    m2 += d2;
    m4 += d2 * d2;
  }
  const double var = m2 / (n - 1);
  m4 /= n;
  const double var_of_var = (m4 - var * var * (n - 3) / (n - 1)) / n;
  return {{"mean_dE", mean}, {"var_dE", var}, {"se_mean_dE", std::sqrt(var / n)},
          {"se_var_dE", std::sqrt(std::max(0.0, var_of_var))}};
}

nlohmann::json fingerprint_of(const Scene& scene) {
  return {{"scene_text", scene.text}, {"shape_parameters", scene.shape.parameters},
          {"particles", scene.particles}, {"record_times", scene.record_times},
          {"seed", scene.seed}, {"omega", scene.force.omega}, {"mass", scene.mass}};
}

template <class Flight>
EnsembleResult execute(const Scene& scene, const Flight& flight, const RunArgs& args, double& seconds) {
  const dynamics::Table table(scene.shape.region);
  dynamics::RunOptions opt;
  opt.record_times = scene.record_times;
  opt.mass = scene.mass;
  // A forced flight costs ~10 containment tests, so every flight of a driven run is checked
  // (12% measured); free flights are 2× slower checked, so there it is --verify.
  opt.verify_every_flight = args.verify || !std::is_same_v<Flight, dynamics::FreeFlight>;
  const auto sampled = dynamics::microcanonical(table, flight, std::sqrt(2 * scene.energy / scene.mass), scene.seed);
  auto initial = [&](std::size_t i) {
    return scene.initial_states.empty() ? sampled(i) : flight.start(scene.initial_states[i]);
  };
  const std::size_t n = scene.particles, m = opt.record_times.size();
  EnsembleResult result;
  result.energies.resize(n * m);
  result.logs.resize(n);
  const Checkpoint checkpoint(scene.output_dir, fingerprint_of(scene).dump());
  Progress progress("run", n, !args.quiet);
  const std::size_t chunk = std::max<std::size_t>(1024, n / 64);
  const auto start = std::chrono::steady_clock::now();
  std::size_t new_chunks = 0;
  for (std::size_t first = 0; first < n; first += chunk) {
    const std::size_t last = std::min(n, first + chunk);
    if (!checkpoint.load(first, last, m, result)) {
      if (args.max_chunks && new_chunks++ == args.max_chunks) throw Interrupted{};
      dynamics::run_particles(table, flight, initial, opt, first, last, args.threads, result,
                              [&](std::size_t done) { progress.update(first + done); });
      checkpoint.save(first, last, m, result);
    }
    progress.update(last);
  }
  progress.finish();
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  checkpoint.remove();
  return result;
}

nlohmann::json summarize(const Scene& scene, const EnsembleResult& r, double seconds, const RunArgs& args) {
  const std::size_t n = scene.particles, m = scene.record_times.size();
  nlohmann::json per_time = nlohmann::json::array();
  for (std::size_t k = 0; k < m; ++k) {
    std::vector<double> dE;
    for (std::size_t i = 0; i < n; ++i)
      if (!r.logs[i].escaped) dE.push_back(r.energies[i * m + k] - r.energies[i * m]);
    nlohmann::json s = delta_stats(dE);
    s["t"] = scene.record_times[k];
    per_time.push_back(s);
  }
  nlohmann::json j = per_time.back();
  j.erase("t");
  j.update({{"scene", scene.file}, {"scene_text", scene.text}, {"command", command_line()},
            {"shape", scene.shape.region.name}, {"shape_parameters", scene.shape.parameters},
            {"force", scene.force.name()}, {"F", {scene.force.amplitude.x(), scene.force.amplitude.y()}},
            {"omega", scene.force.omega}, {"mass", scene.mass}, {"E0", scene.energy},
            {"particles", n}, {"time", scene.time}, {"record_times", scene.record_times},
            {"seed", scene.seed}, {"threads", args.threads}, {"collisions", r.collisions()},
            {"escapes", r.escapes()}, {"wall_seconds", seconds},
            {"collisions_per_second", double(r.collisions()) / seconds}, {"per_time", per_time}});
  if (const auto c = prediction_of(scene)) {
    j["prediction"] = to_json(*c);
    // Deviation of the measurement from g1 Δt and g2 Δt, in standard errors.
    j["mean_dE_deviation_se"] = (j["mean_dE"].get<double>() - c->g1 * scene.time) / j["se_mean_dE"].get<double>();
    j["var_dE_deviation_se"] = (j["var_dE"].get<double>() - c->g2 * scene.time) / j["se_var_dE"].get<double>();
    // The exact Fokker–Planck moments at the end time (they include the growth of g1, g2 with E).
    const auto fp = analysis::fokker_planck_moments(c->C * scene.time, scene.energy, c->dimension);
    j["fp_mean_dE"] = fp.mean - scene.energy;
    j["fp_var_dE"] = fp.variance;
    j["mean_dE_fp_deviation_se"] = (j["mean_dE"].get<double>() - j["fp_mean_dE"].get<double>()) / j["se_mean_dE"].get<double>();
    j["var_dE_fp_deviation_se"] = (j["var_dE"].get<double>() - fp.variance) / j["se_var_dE"].get<double>();
  }
  return j;
}

/// η(E, t) of the analytic Fokker–Planck solution at every record time (a column E, then one
/// column per record time), on a grid uniform in E^{1/4} up to the largest simulated energy:
/// dense at low energy, where early distributions are narrow.
std::string fokker_planck_table(const Scene& scene, const analysis::Coefficients& c, const EnsembleResult& r) {
  double hi = scene.energy;
  for (double e : r.energies)
    if (std::isfinite(e)) hi = std::max(hi, e);
  std::string csv = "E";
  for (double t : scene.record_times) csv += fmt::format(",eta(t={})", t);
  csv += "\n";
  constexpr int points = 3000;
  const double top = std::pow(1.05 * hi, 0.25);
  for (int i = 1; i <= points; ++i) {
    const double u = top * i / points, E = u * u * u * u;
    csv += fmt::format("{:.9g}", E);
    for (double t : scene.record_times)
      csv += fmt::format(",{:.9g}", t > 0 ? analysis::fokker_planck_eta(E, c.C * t, scene.energy, c.dimension) : 0.0);
    csv += "\n";
  }
  return csv;
}

void write_outputs(const Scene& scene, const EnsembleResult& r, const nlohmann::json& summary) {
  OutputDir out(scene.output_dir);
  const std::size_t n = scene.particles, m = scene.record_times.size();
  std::string csv = "particle";
  for (double t : scene.record_times) csv += fmt::format(",E(t={})", t);
  csv += ",collisions,escaped\n";
  for (std::size_t i = 0; i < n; ++i) {
    csv += std::to_string(i);
    for (std::size_t k = 0; k < m; ++k) csv += fmt::format(",{:.17g}", r.energies[i * m + k]);
    csv += fmt::format(",{},{}\n", r.logs[i].collisions, int(r.logs[i].escaped));
  }
  out.write_text("energies.csv", csv);
  out.write_npy("energies.npy", r.energies, n, m);
  out.write_json("summary.json", summary);
  if (const auto c = prediction_of(scene)) out.write_text("fokker-planck.csv", fokker_planck_table(scene, *c, r));
  out.commit();
}

void run(RunArgs args) {
  args.overrides.set = parse_overrides(args.set);
  const Scene scene = dynamics::load_scene(args.scene, args.overrides);
  if (args.threads <= 0) args.threads = omp_get_max_threads();
  fmt::print("scene {}: {} particles on '{}', force {}, t = 0 .. {}\n", scene.file, scene.particles,
             scene.shape.region.name, scene.force.name(), scene.time);
  const auto prediction = prediction_of(scene);
  if (prediction) print_prediction(*prediction, scene.time);
  double seconds = 0;
  EnsembleResult result;
  const dynamics::Vec2 force_accel = scene.force.amplitude / scene.mass;
  try {
    switch (scene.force.kind) {
      case dynamics::Force::Kind::none: result = execute(scene, dynamics::FreeFlight{}, args, seconds); break;
      case dynamics::Force::Kind::constant:
        result = execute(scene, dynamics::ConstantForceFlight{force_accel}, args, seconds);
        break;
      case dynamics::Force::Kind::periodic:
        result = execute(scene, dynamics::PeriodicDriveFlight{force_accel, scene.force.omega, scene.force.phase},
                         args, seconds);
        break;
    }
  } catch (const Interrupted&) {
    fmt::print("stopped after {} new chunk(s); the same command resumes from {}.partial/\n", args.max_chunks,
               scene.output_dir);
    return;
  }
  const auto summary = summarize(scene, result, seconds, args);
  write_outputs(scene, result, summary);
  fmt::print("measured  <dE> = {:.6g} ± {:.2g}   Var(dE) = {:.6g} ± {:.2g}\n", summary["mean_dE"].get<double>(),
             summary["se_mean_dE"].get<double>(), summary["var_dE"].get<double>(), summary["se_var_dE"].get<double>());
  if (prediction)
    fmt::print("deviation from g1 dt: {:+.2f} SE, from g2 dt: {:+.2f} SE; from the exact Fokker-Planck moments "
               "({:.6g}, {:.6g}): {:+.2f} SE, {:+.2f} SE\n",
               summary["mean_dE_deviation_se"].get<double>(), summary["var_dE_deviation_se"].get<double>(),
               summary["fp_mean_dE"].get<double>(), summary["fp_var_dE"].get<double>(),
               summary["mean_dE_fp_deviation_se"].get<double>(), summary["var_dE_fp_deviation_se"].get<double>());
  fmt::print("{} collisions in {:.3g} s ({:.3g} collisions/s), {} escapes; results in {}/\n",
             result.collisions(), seconds, double(result.collisions()) / seconds, result.escapes(), scene.output_dir);
  if (result.escapes() > 0) {
    fmt::print(stderr, "billiard: error: {} particle(s) escaped the region (see 'escaped' in energies.csv)\n",
               result.escapes());
    throw CLI::RuntimeError(3);
  }
}

}  // namespace

void add_run(CLI::App& app) {
  auto* cmd = app.add_subcommand("run", "Run an ensemble of particles in a scene");
  auto args = std::make_shared<RunArgs>();
  cmd->add_option("scene", args->scene, "scene file (YAML)")->required();
  cmd->add_option("--particles", args->overrides.particles, "number of particles");
  cmd->add_option("--time", args->overrides.time, "end time of the run");
  cmd->add_option("--omega", args->overrides.omega, "drive frequency (periodic force)");
  cmd->add_option("--record", args->overrides.record, "record times t1,t2,... (0 and the end time are added)")
      ->delimiter(',');
  cmd->add_option("--seed", args->overrides.seed, "random seed");
  cmd->add_option("--out", args->overrides.output_dir, "output directory");
  cmd->add_option("--threads", args->threads, "threads (default: all cores)");
  cmd->add_flag("--verify", args->verify, "also test the midpoint of every flight against the region");
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->add_option("--max-chunks", args->max_chunks,
                  "run at most K new chunks of particles, then stop; the same command resumes");
  add_set_option(cmd, args->set);
  cmd->callback([args] { run(*args); });
}

}  // namespace billiards::cli
