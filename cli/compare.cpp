// billiard compare SCENE: an ensemble run set against the Fokker–Planck prediction at every
// recorded time — moments with their standard errors, and two goodness-of-fit distances of the
// whole distribution, each beside the value sampling noise alone would give.
#include "commands.hpp"
#include "python.hpp"
#include "ranks.hpp"
#include "run.hpp"

#include "billiards/analysis/fokker_planck.hpp"
#include "billiards/analysis/statistics.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace billiards::cli {

namespace {

/// The simulation against the theory at one recorded time t.
struct Fit {
  double t = 0;
  analysis::SampleMoments dE;              // measured ΔE = E(t) − E0
  double g1_t = 0, g2_t = 0;               // the short-time prediction g1 t, g2 t
  analysis::EnergyMoments fp;              // exact moments of η(E, C t)
  double ks = 0, ks_p = 0;                 // Kolmogorov–Smirnov distance and its p-value
  analysis::Histogram histogram;           // of E(t), on the sample's range
  analysis::HistogramL1 l1;                // Σ|p̂ − p| over its bins, and its noise level
};

Fit fit_at(const RunOutcome& run, std::size_t k, std::size_t bins) {
  const auto& c = *run.prediction;
  const std::size_t m = run.scene.record_times.size();
  const double E0 = run.scene.energy, t = run.scene.record_times[k], s = c.C * t;
  const int d = c.dimension;
  Fit f;
  f.t = t;
  f.dE = analysis::sample_moments(run.result.energy_changes(k, m));
  f.g1_t = c.g1 * t;
  f.g2_t = c.g2 * t;
  f.fp = analysis::fokker_planck_exact_moments(s, E0, d);
  const auto E = run.result.energies_at(k, m);
  f.ks = analysis::ks_distance(E, [&](double e) { return analysis::fokker_planck_cdf(e, s, E0, d); });
  f.ks_p = analysis::ks_p_value(f.ks, E.size());
  const auto [lo, hi] = std::minmax_element(E.begin(), E.end());
  f.histogram = analysis::histogram(E, *lo, std::nextafter(*hi, INFINITY), bins);
  f.l1 = analysis::histogram_l1(f.histogram, [&](double e) { return analysis::fokker_planck_eta(e, s, E0, d); });
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
std::string histogram_csv(const std::vector<Fit>& fits, const RunOutcome& run) {
  const auto& c = *run.prediction;
  std::string csv = "t,E_lo,E_hi,density,fp_density\n";
  for (const auto& f : fits) {
    const auto cdf = [&](double e) { return analysis::fokker_planck_cdf(e, c.C * f.t, run.scene.energy, c.dimension); };
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
  std::size_t bins = 60;
};

void compare(const CompareArgs& args) {
  const auto scene = load_scene(args);
  const auto prediction = analysis::prediction_of(scene);
  if (!prediction || !prediction->closed_form)
    throw InputError(scene.file, 0,
                     "compare needs a scene with an analytic Fokker-Planck prediction: a periodic or field force, no "
                     "potential, and a microcanonical initial energy");
  const auto run = run_ensemble(scene, args);
  if (!run || !ranks().root()) return;
  std::vector<Fit> fits;
  for (std::size_t k = 1; k < scene.record_times.size(); ++k) fits.push_back(fit_at(*run, k, args.bins));
  nlohmann::json times = nlohmann::json::array();
  for (const auto& f : fits) times.push_back(to_json(f, scene.energy));

  OutputDir out(scene.output_dir);
  write_run_files(out, *run, args);
  out.write_json("comparison.json", {{"scene", scene.file}, {"command", command_line()},
                                     {"prediction", *run->prediction}, {"bins", args.bins}, {"times", times}});
  out.write_text("comparison.csv", histogram_csv(fits, *run));
  run_python(script_path("plot_compare.py"), {out.path("").string()});
  out.commit();
  print_fits(fits, scene.energy);
  report(*run);
}

}  // namespace

void add_compare(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "compare", "Run an ensemble and set it against the Fokker-Planck prediction at every recorded time");
  auto args = std::make_shared<CompareArgs>();
  add_run_options(cmd, *args);
  cmd->add_option("--bins", args->bins, "histogram bins per recorded time")->check(CLI::Range(2, 100000));
  cmd->callback([args] { compare(*args); });
}

}  // namespace billiards::cli
