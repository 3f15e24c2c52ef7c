// The ensemble run behind `billiard run` and `billiard compare`: the scene, the particles and
// the files they leave.
#pragma once

#include "options.hpp"
#include "output.hpp"

#include "billiards/analysis/coefficients.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/scene.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace billiards::cli {

/// More threads than this are a typo; each costs a stack (ulimit -s) of address space.
constexpr int max_threads = 1024;

struct RunArgs {
  std::string scene;
  dynamics::SceneOverrides overrides;
  std::vector<std::string> set;
  int threads = 0;
  bool verify = false;
  bool quiet = false;
  bool csv = true;             // energies.csv beside energies.npy
  std::string npy = "float64";  // energies.npy: float64, float32 or none
  std::size_t max_chunks = 0;  // 0: no limit
  std::string sweep;           // NAME=VALUES: one run per value (sweep.cpp)
};

/// The options of `billiard run`, shared by every command that runs an ensemble.
void add_run_options(CLI::App* cmd, RunArgs& args);

/// The scene with the command line's overrides applied.
dynamics::Scene load_scene(const RunArgs& args);

/// Wall-clock seconds since the last call (or the construction).
class Lap {
 public:
  double operator()() {
    const auto now = std::chrono::steady_clock::now();
    return std::chrono::duration<double>(now - std::exchange(last_, now)).count();
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

/// E(t_k) of the particles that did not escape, a column per record time k, in one block left
/// uninitialized until the threads that fill it touch its pages.
class EnergyColumns {
 public:
  EnergyColumns() = default;
  EnergyColumns(std::size_t rows, std::size_t columns) : rows_(rows), data_(new double[rows * columns]) {}
  std::span<double> operator[](std::size_t k) { return {data_.get() + k * rows_, rows_}; }
  std::span<const double> operator[](std::size_t k) const { return {data_.get() + k * rows_, rows_}; }

 private:
  std::size_t rows_ = 0;
  std::unique_ptr<double[]> data_;
};

struct RunOutcome {
  dynamics::Scene scene;
  std::optional<analysis::Coefficients> prediction;
  dynamics::EnsembleResult result;
  EnergyColumns by_time;                         // E(t_k) of every particle that did not escape, by k
  std::vector<analysis::SampleMoments> changes;  // of ΔE = E(t_k) − E(t_0) over by_time, by k
  nlohmann::json summary;                        // summary.json
  double statistics_seconds = 0;                 // wall clock of by_time and changes
};

/// Prints the prediction, runs the ensemble (resuming from a checkpoint) and summarizes it;
/// nothing if --max-chunks stopped it first.
std::optional<RunOutcome> run_ensemble(const dynamics::Scene& scene, const RunArgs& args);

/// Writes energies, summary.json and fokker-planck.csv into `out` (not yet committed).
void write_run_files(const OutputDir& out, const RunOutcome& run, const RunArgs& args);

/// The measurement beside the prediction on stdout; throws (exit status 3) if a particle escaped.
void report(const RunOutcome& run);

/// `run --sweep NAME=VALUES`: a run per value into OUT/NAME=VALUE/, and OUT/sweep.csv, sweep.json.
void run_sweep(const RunArgs& args);

}  // namespace billiards::cli
