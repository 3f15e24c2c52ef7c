// billiard run SCENE: an ensemble run with the prediction before and the measurement after.
#include "run.hpp"

#include "commands.hpp"
#include "interrupt.hpp"
#include "progress.hpp"
#include "ranks.hpp"

#include "billiards/analysis/fokker_planck.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/dynamics/scene_run.hpp"

#include <fmt/core.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <omp.h>

#include <charconv>
#include <filesystem>
#include <fstream>

#include <sys/resource.h>
#include <unistd.h>

namespace billiards::cli {

namespace {

namespace fs = std::filesystem;
using dynamics::EnsembleResult;
using dynamics::Scene;

/// Thrown when --max-chunks stops a run early; the checkpoint stays for the next run.
struct Interrupted {};

/// Particles run in chunks; each finished chunk is saved under <out>.partial so that an
/// interrupted run resumes where it stopped.  Particles are independent and each depends on
/// (seed, index) only, so a resumed run is identical to an uninterrupted one.
class Checkpoint {
 public:
  Checkpoint(const fs::path& out, std::string fingerprint)
      : dir_(fs::path(out.string() + ".partial")), fingerprint_(std::move(fingerprint)),
        note_(fmt::format("the same command resumes from {}/", dir_.string())) {
    if (ranks().root()) {
      std::ifstream in(dir_ / "fingerprint.json");
      std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (old != fingerprint_) start_afresh();  // another scene or other parameters
    }
    ranks().barrier();  // the other ranks find the directory ready
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
  void start_afresh() const {
    try {
      fs::remove_all(dir_);
      fs::create_directories(dir_);
    } catch (const fs::filesystem_error& e) {
      throw InputError(dir_.string(), 0, "cannot create the checkpoint directory: " + e.code().message());
    }
    // The fingerprint is written last: a directory without it is started afresh next time.
    const fs::path tmp = dir_ / "fingerprint.json.tmp";
    std::ofstream(tmp) << fingerprint_;
    fs::rename(tmp, dir_ / "fingerprint.json");
  }

  fs::path dir_;
  std::string fingerprint_;
  InterruptNote note_;
};

/// Refuses a run whose arrays (or threads' stacks) would not fit in memory, before allocating:
/// per particle its log, its state, its energies at the m record times twice (as run, and by
/// record time for the statistics), and on each thread one double (compare's fit at one record
/// time: the KS search's grouped copy).
void require_memory(const Scene& scene, int threads) {
  const double n = double(scene.particles), m = double(scene.record_times.size());
  const double per_particle = 2 * m * sizeof(double) + threads * sizeof(double) + sizeof(dynamics::ParticleLog) +
                              sizeof(dynamics::State3);
  const double table = 3000 * m * 24;  // fokker-planck.csv, built in memory
  rlimit stack{}, space{};
  getrlimit(RLIMIT_STACK, &stack);
  getrlimit(RLIMIT_AS, &space);
  const double stack_size = stack.rlim_cur == RLIM_INFINITY ? 8 << 20 : double(stack.rlim_cur);
  const double need = n * per_particle + table + threads * stack_size;
  double have = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE));
  if (space.rlim_cur != RLIM_INFINITY) have = std::min(have, double(space.rlim_cur));
  if (need > 0.8 * have)
    throw InputError(scene.file, 0,
                     fmt::format("{:.0f} particles x {:.0f} record times on {} threads need about {:.3g} GB of memory, "
                                 "more than the {:.3g} GB available (physical memory or ulimit -v): use fewer "
                                 "particles, record times or threads",
                                 n, m, threads, need / 1e9, have / 1e9));
}

/// Mean and variance of ΔE with their standard errors.
nlohmann::json delta_stats(const analysis::SampleMoments& m) {
  return {{"mean_dE", m.mean}, {"var_dE", m.variance}, {"se_mean_dE", m.se_mean}, {"se_var_dE", m.se_variance}};
}

nlohmann::json fingerprint_of(const Scene& scene) {
  return {{"scene_text", scene.text}, {"shape_parameters", scene.shape_parameters()},
          {"particles", scene.particles}, {"record_times", scene.record_times},
          {"seed", scene.seed}, {"omega", scene.force.omega}, {"mass", scene.mass}};
}

template <class Flight>
EnsembleResult execute(const Scene& scene, const Flight& flight, const RunArgs& args, double& seconds) {
  const auto table = dynamics::table_of<Flight>(scene);
  const auto opt = dynamics::run_options<Flight>(scene, args.verify);
  const auto initial = dynamics::initial_states(scene, table, flight);
  const std::size_t n = scene.particles, m = opt.record_times.size();
  EnsembleResult result;
  result.energies.resize(n * m);
  result.logs.resize(n);
  const Checkpoint checkpoint(scene.output_dir, fingerprint_of(scene).dump());
  // Chunk c belongs to rank c mod K; the others leave its entries zero for the combination.
  const Ranks& procs = ranks();
  Progress progress("run", n, !args.quiet && procs.root());
  const std::size_t chunk = std::max<std::size_t>(1024, n / 64);
  Lap lap;
  std::size_t new_chunks = 0;
  bool interrupted = false;
  for (std::size_t first = 0; first < n && !interrupted; first += chunk) {
    if ((first / chunk) % std::size_t(procs.size()) != std::size_t(procs.rank())) continue;
    const std::size_t last = std::min(n, first + chunk);
    if (!checkpoint.load(first, last, m, result)) {
      if (args.max_chunks && new_chunks++ == args.max_chunks) {
        interrupted = true;
        break;
      }
      try {
        dynamics::run_particles(table, flight, initial, opt, first, last, args.threads, result,
                                [&](std::size_t done) { progress.update(first + done); });
      } catch (const dynamics::ParticleError& e) {
        // The same scene and seed fail the same way: nothing to resume, so no checkpoint stays.
        if (procs.root()) checkpoint.remove();
        throw std::runtime_error(fmt::format("{}: {}", scene.file, e.what()));
      }
      checkpoint.save(first, last, m, result);
    }
    progress.update(last);
  }
  if (procs.any(interrupted)) throw Interrupted{};
  procs.combine(result.energies.data(), result.energies.size() * sizeof(double));
  procs.combine(result.logs.data(), result.logs.size() * sizeof(dynamics::ParticleLog));
  progress.finish();
  seconds = lap();
  if (procs.root()) checkpoint.remove();
  return result;
}

nlohmann::json summarize(const Scene& scene, const std::optional<analysis::Coefficients>& prediction,
                         const EnsembleResult& r, const std::vector<analysis::SampleMoments>& changes, double seconds,
                         const RunArgs& args) {
  const std::size_t m = scene.record_times.size();
  nlohmann::json per_time = nlohmann::json::array();
  for (std::size_t k = 0; k < m; ++k) {
    const double t = scene.record_times[k];
    nlohmann::json s = delta_stats(changes[k]);
    s["t"] = t;
    if (prediction) {
      s["g1_t"] = prediction->g1 * t;
      s["g2_t"] = prediction->g2 * t;
    }
    if (prediction && prediction->closed_form) {  // the exact Fokker–Planck moments, for the figures
      const auto fp = t > 0 ? analysis::fokker_planck_exact_moments(prediction->C * t, scene.energy, prediction->dimension)
                            : analysis::EnergyMoments{scene.energy, 0, 0};
      s["fp_mean_dE"] = fp.mean - scene.energy;
      s["fp_var_dE"] = fp.variance;
    }
    per_time.push_back(s);
  }
  nlohmann::json j = per_time.back();  // the end time's moments, and its fp_* keys
  for (const char* key : {"t", "g1_t", "g2_t"}) j.erase(key);
  j.update({{"scene", scene.file}, {"scene_text", scene.text}, {"command", command_line()},
            {"dimension", scene.dimension()}, {"shape", scene.shape_name()},
            {"shape_parameters", scene.shape_parameters()}, {"force", scene.force.name()},
            {"F", std::vector<double>(scene.force.amplitude.begin(), scene.force.amplitude.end())},
            {"omega", scene.force.omega}, {"mass", scene.mass}, {"E0", scene.energy},
            {"particles", scene.particles}, {"time", scene.time}, {"record_times", scene.record_times},
            {"seed", scene.seed}, {"threads", args.threads}, {"ranks", ranks().size()}, {"collisions", r.collisions()},
            {"escapes", r.escapes()}, {"wall_seconds", seconds},
            {"collisions_per_second", double(r.collisions()) / seconds}, {"per_time", per_time}});
  if (prediction) {
    const auto& c = *prediction;
    j["prediction"] = c;
    // Deviation of the measurement from g1 Δt and g2 Δt, in standard errors.
    j["mean_dE_deviation_se"] = (j["mean_dE"].get<double>() - c.g1 * scene.time) / j["se_mean_dE"].get<double>();
    j["var_dE_deviation_se"] = (j["var_dE"].get<double>() - c.g2 * scene.time) / j["se_var_dE"].get<double>();
  }
  if (prediction && prediction->closed_form) {
    // From the exact Fokker–Planck moments at the end time (they include the growth of g1, g2 with E).
    j["mean_dE_fp_deviation_se"] = (j["mean_dE"].get<double>() - j["fp_mean_dE"].get<double>()) / j["se_mean_dE"].get<double>();
    j["var_dE_fp_deviation_se"] = (j["var_dE"].get<double>() - j["fp_var_dE"].get<double>()) / j["se_var_dE"].get<double>();
  }
  return j;
}

/// η(E, t) of the analytic Fokker–Planck solution at every record time (a column E, then one
/// column per record time), on a grid uniform in E^{1/4} up to the largest simulated energy:
/// dense at low energy, where early distributions are narrow.  Rows are computed on `threads`
/// threads; numbers are written as fmt's {:.9g} writes them, by std::to_chars (the same
/// characters, about half the instructions).
std::string fokker_planck_table(const Scene& scene, const analysis::Coefficients& c, const EnsembleResult& r,
                                int threads) {
  double hi = scene.energy;
  for (double e : r.energies)
    if (std::isfinite(e)) hi = std::max(hi, e);
  constexpr int points = 3000;
  const double top = std::pow(1.05 * hi, 0.25);
  std::vector<std::string> rows(points);
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
  for (int i = 1; i <= points; ++i) {
    std::string& row = rows[i - 1];
    auto write = [&row](double x) {
      char text[32];
      row.append(text, std::to_chars(text, text + sizeof text, x, std::chars_format::general, 9).ptr);
    };
    const double u = top * i / points, E = u * u * u * u;
    write(E);
    for (double t : scene.record_times) {
      row += ',';
      write(t > 0 ? analysis::fokker_planck_eta(E, c.C * t, scene.energy, c.dimension) : 0.0);
    }
    row += '\n';
  }
  std::string csv = "E";
  for (double t : scene.record_times) csv += fmt::format(",eta(t={})", t);
  csv += "\n";
  for (const auto& row : rows) csv += row;
  return csv;
}

/// energies.csv, a row per particle, streamed: 10⁶ particles make ~0.4 GB of text.
void write_energies_csv(std::ostream& out, const Scene& scene, const EnsembleResult& r) {
  const std::size_t n = scene.particles, m = scene.record_times.size();
  out << "particle";
  for (double t : scene.record_times) out << fmt::format(",E(t={})", t);
  out << ",collisions,escaped\n";
  fmt::memory_buffer row;
  for (std::size_t i = 0; i < n; ++i) {
    row.clear();
    fmt::format_to(std::back_inserter(row), "{}", i);
    for (std::size_t k = 0; k < m; ++k) fmt::format_to(std::back_inserter(row), ",{:.17g}", r.energies[i * m + k]);
    fmt::format_to(std::back_inserter(row), ",{},{}\n", r.logs[i].collisions, int(r.logs[i].escaped));
    out.write(row.data(), std::streamsize(row.size()));
  }
}

}  // namespace

void add_run_options(CLI::App* cmd, RunArgs& args) {
  cmd->add_option("scene", args.scene, "scene file (YAML)")->required();
  cmd->add_option("--particles", args.overrides.particles, "number of particles")->transform(whole_number(2, 1e12));
  cmd->add_option("--time", args.overrides.time, "end time of the run")->transform(expression_value);
  cmd->add_option("--omega", args.overrides.omega, "drive frequency (an expression: 320*pi)")->transform(expression_value);
  cmd->add_option("--record", args.overrides.record, "record times t1,t2,... (0 and the end time are added)")
      ->delimiter(',')
      ->transform(expression_value);
  cmd->add_option("--seed", args.overrides.seed, "random seed")->check(seed_value);
  cmd->add_option("--out", args.overrides.output_dir, "output directory");
  cmd->add_option("--threads", args.threads, "threads (default: all cores)")->transform(whole_number(1, max_threads));
  cmd->add_flag("--verify", args.verify, "also test the midpoint of every flight against the region");
  cmd->add_flag("--quiet", args.quiet, "no progress bar");
  cmd->add_flag("!--no-csv", args.csv, "write energies.npy only (energies.csv is ~0.4 kB per particle)");
  cmd->add_option("--npy", args.npy,
                  "energies.npy as float64 (default), float32 (half the size, 7 significant digits) or none")
      ->check(CLI::IsMember({"float64", "float32", "none"}));
  cmd->add_option("--max-chunks", args.max_chunks,
                  "run at most K new chunks of particles, then stop; the same command resumes")
      ->transform(whole_number(1, 1e12));
  add_set_option(cmd, args.set);
}

dynamics::Scene load_scene(const RunArgs& args) {
  auto overrides = args.overrides;
  overrides.set = parse_overrides(args.set);
  return dynamics::load_scene(args.scene, overrides);
}

namespace {

/// E(t_k) of every particle that did not escape, a column per record time k (m of them), in
/// particle order: the particles' rows are swept once, by `threads` threads, where
/// EnsembleResult::energies_at reads the whole table once per record time (a cache line per
/// particle each time: at N = 10⁶ and 21 record times, more than the statistics themselves).
EnergyColumns energies_by_time(const EnsembleResult& r, std::size_t m, int threads) {
  const std::size_t n = r.logs.size();
  std::vector<std::size_t> place(n);  // a kept particle's row in the columns
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) place[i] = kept, kept += !r.logs[i].escaped;
  if (kept < 2)
    throw std::runtime_error(fmt::format("{} of {} particles escaped the region: too few left for statistics",
                                         n - kept, n));
  EnergyColumns E(kept, m);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t i = 0; i < n; ++i)
    if (!r.logs[i].escaped)
      for (std::size_t k = 0; k < m; ++k) E[k][place[i]] = r.energies[i * m + k];
  return E;
}

/// The moments of ΔE = E(t_k) − E(t_0) at every record time, a record time per thread:
/// EnsembleResult::energy_changes's differences, to the bit.
std::vector<analysis::SampleMoments> change_moments(const EnergyColumns& by_time, std::size_t m, int threads) {
  std::vector<analysis::SampleMoments> moments(m);
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (std::size_t k = 0; k < m; ++k) moments[k] = analysis::sample_moments_of_differences(by_time[k], by_time[0]);
  return moments;
}

}  // namespace

std::optional<RunOutcome> run_ensemble(const Scene& scene, const RunArgs& args_in) {
  RunArgs args = args_in;
  if (args.threads <= 0) args.threads = std::min(omp_get_max_threads(), max_threads);
  require_memory(scene, args.threads);
  fmt::print("scene {}: {} particles on '{}', force {}, t = 0 .. {}\n", scene.file, scene.particles,
             scene.shape_name(), scene.force.name(), scene.time);
  RunOutcome run{scene, analysis::prediction_of(scene), {}, {}, {}, {}, 0};
  if (run.prediction) print_prediction(*run.prediction, scene.time);
  double seconds = 0;
  try {
    run.result = dynamics::with_flight(scene, [&](const auto& flight) { return execute(scene, flight, args, seconds); });
  } catch (const Interrupted&) {
    fmt::print("stopped after {} new chunk(s); the same command resumes from {}.partial/\n", args.max_chunks,
               scene.output_dir);
    return std::nullopt;
  }
  Lap lap;
  run.by_time = energies_by_time(run.result, scene.record_times.size(), args.threads);
  run.changes = change_moments(run.by_time, scene.record_times.size(), args.threads);
  run.statistics_seconds = lap();
  run.summary = summarize(scene, run.prediction, run.result, run.changes, seconds, args);
  return run;
}

void write_run_files(const OutputDir& out, const RunOutcome& run, const RunArgs& args) {
  const auto& scene = run.scene;
  if (args.csv)
    out.write_stream("energies.csv", [&](std::ostream& os) { write_energies_csv(os, scene, run.result); });
  const std::size_t rows = scene.particles, cols = scene.record_times.size();
  if (args.npy == "float64") out.write_npy("energies.npy", run.result.energies, rows, cols);
  if (args.npy == "float32")
    out.write_npy("energies.npy", std::vector<float>(run.result.energies.begin(), run.result.energies.end()), rows, cols);
  out.write_json("summary.json", run.summary);
  if (run.prediction && run.prediction->closed_form)
    out.write_text("fokker-planck.csv", fokker_planck_table(scene, *run.prediction, run.result,
                                                             args.threads > 0 ? args.threads : omp_get_max_threads()));
}

void report(const RunOutcome& run) {
  const auto& j = run.summary;
  const auto get = [&](const char* key) { return j[key].get<double>(); };
  fmt::print("measured  <dE> = {:.6g} ± {:.2g}   Var(dE) = {:.6g} ± {:.2g}\n", get("mean_dE"), get("se_mean_dE"),
             get("var_dE"), get("se_var_dE"));
  if (run.prediction)
    fmt::print("deviation from g1 dt: {:+.2f} SE, from g2 dt: {:+.2f} SE\n", get("mean_dE_deviation_se"),
               get("var_dE_deviation_se"));
  if (run.prediction && run.prediction->closed_form)
    fmt::print("deviation from the exact Fokker-Planck moments ({:.6g}, {:.6g}): {:+.2f} SE, {:+.2f} SE\n",
               get("fp_mean_dE"), get("fp_var_dE"), get("mean_dE_fp_deviation_se"), get("var_dE_fp_deviation_se"));
  const auto& r = run.result;
  fmt::print("{} collisions in {:.3g} s ({:.3g} collisions/s), {} escapes; results in {}/\n", r.collisions(),
             get("wall_seconds"), get("collisions_per_second"), r.escapes(), run.scene.output_dir);
  if (r.escapes() > 0) {
    fmt::print(stderr, "billiard: error: {} particle(s) escaped the region (see 'escaped' in energies.csv)\n",
               r.escapes());
    throw CLI::RuntimeError(3);
  }
}

void add_run(CLI::App& app) {
  auto* cmd = app.add_subcommand("run", "Run an ensemble of particles in a scene");
  auto args = std::make_shared<RunArgs>();
  add_run_options(cmd, *args);
  cmd->add_option("--sweep", args->sweep,
                  "NAME=VALUES: a run per value of omega or of a parameter; VALUES is a,b,c or FROM..TO:xFACTOR "
                  "or FROM..TO:+STEP (expressions), outputs in OUT/NAME=VALUE/ and OUT/sweep.csv");
  cmd->callback([args] {
    if (!args->sweep.empty()) return run_sweep(*args);
    const auto scene = load_scene(*args);
    if (ranks().root()) OutputDir::require_creatable(scene.output_dir);  // before the run, not after
    const auto run = run_ensemble(scene, *args);
    if (!run || !ranks().root()) return;
    OutputDir out(run->scene.output_dir);
    write_run_files(out, *run, *args);
    out.commit();
    report(*run);
  });
}

}  // namespace billiards::cli
