// billiard compare SCENE: an ensemble run set against the Fokker–Planck prediction at every
// recorded time — moments with their standard errors, and two goodness-of-fit distances of the
// whole distribution, each beside the value sampling noise alone would give.  The prediction is
// the analytic solution, or with a potential the numerical one.
#include "commands.hpp"
#include "phase_space.hpp"
#include "python.hpp"
#include "ranks.hpp"
#include "run.hpp"

#include "billiards/analysis/coefficients.hpp"
#include "billiards/analysis/fokker_planck.hpp"
#include "billiards/analysis/statistics.hpp"

#include <fmt/core.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

namespace billiards::cli {

namespace {

/// The Fokker–Planck law of E at one time: exact (closed forms, U = 0) or numerical (a potential).
struct Law {
  double mean = 0, variance = 0;
  std::function<double(double)> cdf;
};

/// The law at every record time t > 0, and with a potential the numerical solution behind it.
struct Prediction {
  std::vector<Law> laws;
  std::optional<analysis::FokkerPlanckSolution> numerical;
};

/// With a potential there is no analytic solution: the numerical one (solved once for all the
/// times, on `cells` cells) gives the moments and the piecewise-linear CDF of its cell averages.
Prediction prediction_at_record_times(const dynamics::Scene& scene, const analysis::Coefficients& c, int cells) {
  const std::vector<double> times(scene.record_times.begin() + 1, scene.record_times.end());
  const double E0 = scene.energy;
  const int d = c.dimension;
  Prediction p;
  if (c.closed_form) {
    for (double t : times) {
      const double s = c.C * t;
      const auto m = analysis::fokker_planck_exact_moments(s, E0, d);
      p.laws.push_back({m.mean, m.variance, [=](double e) { return analysis::fokker_planck_cdf(e, s, E0, d); }});
    }
    return p;
  }
  p.numerical = analysis::fokker_planck_of(scene, times, cells);
  const auto& grid = p.numerical->grid;
  warn_if_coarse(*p.numerical);
  fmt::print("Fokker-Planck law: numerical (U != 0, no analytic solution), {} cells on E = {:.6g} .. {:.6g}, {} "
             "evaluations of g1, g2\n",
             grid.cells(), grid.edges.front(), grid.edges.back(), p.numerical->evaluations);
  for (const auto& eta : p.numerical->eta) {
    const auto m = analysis::moments_of(grid, eta);
    p.laws.push_back({m.mean, m.variance, analysis::cdf_of(grid, eta)});
  }
  return p;
}

/// fokker-planck.csv of a numerical solution, in `run`'s layout: E (the cell centres), then η
/// at every record time (0 at t = 0, where η is the δ at E0).
std::string numerical_table(const analysis::FokkerPlanckSolution& s) {
  std::string csv = "E,eta(t=0)";
  for (double t : s.times) csv += fmt::format(",eta(t={})", t);
  csv += "\n";
  for (std::size_t i = 0; i < s.grid.cells(); ++i) {
    csv += fmt::format("{:.9g},0", s.grid.center(i));
    for (const auto& eta : s.eta) csv += fmt::format(",{:.9g}", eta[i]);
    csv += "\n";
  }
  return csv;
}

/// The simulation against the theory at one recorded time t.
struct Fit {
  double t = 0;
  analysis::SampleMoments dE;              // measured ΔE = E(t) − E0
  double g1_t = 0, g2_t = 0;               // the short-time prediction g1 t, g2 t
  Law fp;                                  // the Fokker–Planck law at t
  double ks = 0, ks_p = 0;                 // Kolmogorov–Smirnov distance and its p-value
  analysis::Histogram histogram;           // of E(t), on the sample's range
  analysis::HistogramL1 l1;                // Σ|p̂ − p| over its bins, and its noise level
};

/// The fit at record time k from the run's energies and moments at every record time.
Fit fit_at(const RunOutcome& run, std::size_t k, const Law& law, std::size_t bins) {
  const auto& c = *run.prediction;
  const double t = run.scene.record_times[k];
  Fit f;
  f.t = t;
  f.dE = run.changes[k];
  f.g1_t = c.g1 * t;
  f.g2_t = c.g2 * t;
  f.fp = law;
  const auto E = run.by_time[k];
  f.ks = analysis::ks_distance(E, law.cdf);
  f.ks_p = analysis::ks_p_value(f.ks, E.size());
  const auto [lo, hi] = analysis::sample_range(E);
  f.histogram = analysis::histogram(E, lo, std::nextafter(hi, INFINITY), bins);
  f.l1 = analysis::histogram_l1_cdf(f.histogram, law.cdf);
  return f;
}

nlohmann::json to_json(const Fit& f, double E0) {
  return {{"t", f.t},
          {"n", f.dE.count},
          {"mean_dE", f.dE.mean},
          {"se_mean_dE", f.dE.se_mean},
          {"var_dE", f.dE.variance},
          {"se_var_dE", f.dE.se_variance},
          {"g1_t", f.g1_t},
          {"g2_t", f.g2_t},
          {"fp_mean_dE", f.fp.mean - E0},
          {"fp_var_dE", f.fp.variance},
          {"mean_dE_fp_deviation_se", (f.dE.mean - (f.fp.mean - E0)) / f.dE.se_mean},
          {"var_dE_fp_deviation_se", (f.dE.variance - f.fp.variance) / f.dE.se_variance},
          {"ks_distance", f.ks},
          {"ks_p_value", f.ks_p},
          {"l1_distance", f.l1.distance},
          {"l1_expected_from_noise", f.l1.expected_from_noise}};
}

/// Every histogram with η's average over each bin: t, E_lo, E_hi, density, fp_density.
std::string histogram_csv(const std::vector<Fit>& fits) {
  std::string csv = "t,E_lo,E_hi,density,fp_density\n";
  for (const auto& f : fits) {
    const auto& cdf = f.fp.cdf;
    for (std::size_t i = 0; i < f.histogram.counts.size(); ++i) {
      const double a = f.histogram.edge(i), b = f.histogram.edge(i + 1);
      csv += fmt::format("{},{:.9g},{:.9g},{:.9g},{:.9g}\n", f.t, a, b, f.histogram.density(i),
                         (cdf(b) - cdf(a)) / (b - a));
    }
  }
  return csv;
}

void print_fits(const std::vector<Fit>& fits, double E0) {
  fmt::print("{:>8} {:>22} {:>10} {:>10} {:>22} {:>10} {:>10} {:>9} {:>8} {:>17}\n", "t", "<dE> (sim)", "g1 t",
             "FP", "Var dE (sim)", "g2 t", "FP", "KS D", "KS p", "L1 (noise)");
  for (const auto& f : fits)
    fmt::print("{:>8.4g} {:>11.5g} ± {:<8.2g} {:>10.5g} {:>10.5g} {:>11.5g} ± {:<8.2g} {:>10.5g} {:>10.5g} {:>9.3g} "
               "{:>8.3g} {:>8.3g} ({:.3g})\n",
               f.t, f.dE.mean, f.dE.se_mean, f.g1_t, f.fp.mean - E0, f.dE.variance, f.dE.se_variance, f.g2_t,
               f.fp.variance, f.ks, f.ks_p, f.l1.distance, f.l1.expected_from_noise);
}

struct CompareArgs : RunArgs {
  bool plot = true;  // comparison.png
  std::size_t bins = 60;
  int cells = 1000;  // of the numerical Fokker–Planck solution (a potential)
};

void compare(const CompareArgs& args) {
  const auto scene = load_scene(args);
  const auto prediction = analysis::prediction_of(scene);
  if (!prediction)
    throw InputError(scene.file, 0,
                     "compare needs a scene with a Fokker-Planck prediction: a periodic or field force and a "
                     "microcanonical initial energy");
  // Before the run, so that its errors come first.
  const auto fp = prediction_at_record_times(scene, *prediction, args.cells);
  if (ranks().root()) OutputDir::require_creatable(scene.output_dir);
  // The theory assumes a chaotic, ergodic undriven table: its verdict beside the prediction.
  const auto chaos = scene.dimension() == 2 ? ergodicity_check(scene.shape<2>().region) : nlohmann::json();
  if (!chaos.is_null() && ranks().root()) print_ergodicity(chaos);
  const auto run = run_ensemble(scene, args);
  if (!run || !ranks().root()) return;
  Lap lap;
  // One record time per thread: each fit reads the shared result and writes its own entry.
  std::vector<Fit> fits(scene.record_times.size() - 1);
  const int threads = args.threads > 0 ? args.threads : std::min(omp_get_max_threads(), max_threads);
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (std::size_t k = 1; k < scene.record_times.size(); ++k) fits[k - 1] = fit_at(*run, k, fp.laws[k - 1], args.bins);
  nlohmann::json times = nlohmann::json::array();
  for (const auto& f : fits) times.push_back(to_json(f, scene.energy));
  const double fitting = lap();

  OutputDir out(scene.output_dir);
  write_run_files(out, *run, args);
  if (fp.numerical) out.write_text("fokker-planck.csv", numerical_table(*fp.numerical));
  out.write_json("comparison.json", {{"scene", scene.file}, {"command", command_line()},
                                     {"prediction", *run->prediction}, {"chaos_check", chaos}, {"bins", args.bins},
                                     {"times", times}});
  out.write_text("comparison.csv", histogram_csv(fits));
  const double writing = lap();
  if (args.plot) run_python(script_path("plot_compare.py"), {out.path("").string()});
  const double drawing = lap();
  out.commit();
  print_fits(fits, scene.energy);
  report(*run);
  fmt::print("after the simulation: statistics {:.3g} s, files {:.3g} s, figure {:.3g} s (wall clock)\n",
             run->statistics_seconds + fitting, writing, drawing);
}

}  // namespace

void add_compare(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "compare", "Run an ensemble and set it against the Fokker-Planck prediction at every recorded time");
  auto args = std::make_shared<CompareArgs>();
  add_run_options(cmd, *args);
  cmd->add_flag("!--no-plot", args->plot,
                "no comparison.png (scripts/plot_compare.py OUT draws it later from the files written)");
  cmd->add_option("--bins", args->bins, "histogram bins per recorded time")->check(CLI::Range(2, 100000));
  cmd->add_option("--cells", args->cells,
                  "energy cells of the numerical Fokker-Planck solution, used with a potential (default 1000)")
      ->check(CLI::Range(10, 10000000));
  cmd->callback([args] { compare(*args); });
}

}  // namespace billiards::cli
