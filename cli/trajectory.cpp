// billiard trajectory SHAPE|SCENE: one particle's collision sequence, and with --dt its states
// sampled along the true flight between the collisions, streamed to disk in chunks of .npy files
// (dynamics::follow: no row is kept once written), so a run of 10⁹ collisions needs the memory
// of one chunk.  The directory appears complete or not at all (OutputDir).
#include "commands.hpp"
#include "output.hpp"
#include "phase_space.hpp"
#include "progress.hpp"

#include "billiards/dynamics/follow.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>

namespace billiards::cli {

namespace {

namespace fs = std::filesystem;

struct TrajectoryArgs {
  std::string source, out;
  std::optional<std::size_t> collisions;
  std::optional<double> time, dt;
  std::optional<std::uint64_t> seed;
  std::size_t particle = 0, chunk = 65536;
  std::vector<std::string> set;
  bool quiet = false;
};

/// Row kinds in the `wall` column besides a wall's index.
constexpr double start_row = -1, sample_row = -2;

/// The scene of a scene file (particle I must be one of its particles), or a free particle in a
/// shape: microcanonical at speed 1 (E = 1/2, m = 1) from `--seed`, as Python's trajectory(shape).
dynamics::Scene scene_of(const TrajectoryArgs& args) {
  dynamics::SceneOverrides ov;
  ov.set = parse_overrides(args.set);
  ov.seed = args.seed;
  if (is_scene_file(args.source)) {
    auto scene = dynamics::load_scene(args.source, ov);
    if (args.particle >= scene.particles)
      throw InputError("--particle", 0,
                       fmt::format("particle {} is not in the scene, which has particles 0 to {}", args.particle,
                                   scene.particles - 1));
    return scene;
  }
  geometry3::shape_dimension(args.source);  // (a missing or unreadable shape file is reported as one)
  ov.particles = std::max<std::size_t>(args.particle + 1, 2);
  // (The scene's run time is not this command's: --time and --collisions end the trajectory.)
  const std::string text =
      fmt::format("shape: {}\ninitial:\n  microcanonical: {{energy: 1/2}}\nrun:\n  particles: {}\n  time: 1\n",
                  nlohmann::json(fs::absolute(args.source).string()).dump(), *ov.particles);
  auto scene = dynamics::parse_scene(text, args.source, ".", ov);
  scene.output_dir = "out/" + fs::path(args.source).stem().string();
  return scene;
}

std::vector<std::string> columns(int dimension) {
  if (dimension == 3) return {"t", "x", "y", "z", "vx", "vy", "vz", "wall", "energy"};
  return {"t", "x", "y", "vx", "vy", "wall", "energy"};
}

/// Rows collected up to `chunk` at a time, each full chunk written as chunk-NNNNNN.npy.
class ChunkWriter {
 public:
  ChunkWriter(const OutputDir& out, std::size_t columns, std::size_t chunk) : out_(out), columns_(columns), chunk_(chunk) {
    rows_.reserve(chunk_ * columns_);
  }
  template <class State>
  void add(const State& s, double wall, double energy) {
    rows_.push_back(s.t);
    rows_.insert(rows_.end(), s.x.data(), s.x.data() + s.x.size());
    rows_.insert(rows_.end(), s.v.data(), s.v.data() + s.v.size());
    rows_.push_back(wall);
    rows_.push_back(energy);
    if (rows_.size() == chunk_ * columns_) flush();
  }
  void flush() {
    if (rows_.empty()) return;
    const std::string name = fmt::format("chunk-{:06d}.npy", files_.size());
    const std::size_t n = rows_.size() / columns_;
    out_.write_npy(name, rows_, n, columns_);
    files_.push_back({{"file", name}, {"rows", n}});
    total_ += n;
    rows_.clear();
  }
  const nlohmann::json& files() const { return files_; }
  std::size_t rows() const { return total_; }

 private:
  const OutputDir& out_;
  std::size_t columns_, chunk_, total_ = 0;
  std::vector<double> rows_;
  nlohmann::json files_ = nlohmann::json::array();
};

/// How far the progress bar has come: collisions, or time in thousandths of the end time.
struct TrajectoryProgress {
  Progress bar;
  bool by_time;
  double t_end;
  void operator()(std::size_t collisions, double t) {
    bar.update(by_time ? std::size_t(1000 * std::min(1.0, t / t_end)) : collisions);
  }
};

template <class Flight>
dynamics::FollowResult write_rows(const dynamics::Scene& scene, const Flight& flight, const TrajectoryArgs& args,
                                  const dynamics::FollowLimits& limits, ChunkWriter& rows, TrajectoryProgress& progress) {
  const auto table = dynamics::table_of<Flight>(scene);
  const auto s = dynamics::initial_states(scene, table, flight)(args.particle);
  const auto energy = [&](const auto& state) { return dynamics::energy_of(flight, state, scene.mass); };
  rows.add(s, start_row, energy(s));
  std::size_t collisions = 0;
  const auto on_bounce = [&](const auto& hit, const auto& after) {
    rows.add(after, table.piece_of(hit.wall), energy(after));
    if (++collisions % 4096 == 0) progress(collisions, after.t);
  };
  const auto on_sample = [&](const auto& state) { rows.add(state, sample_row, energy(state)); };
  return dynamics::follow(table, flight, s, limits, dynamics::SampleClock{s.t, args.dt.value_or(0)}, on_bounce,
                          on_sample);
}

void run_trajectory(const TrajectoryArgs& args) {
  const auto scene = scene_of(args);
  // Such a flight's collision search runs to a horizon: under a drive an orbit may circle
  // away from every wall for ever.
  if (!args.time && scene.magnetic() && scene.force.kind != dynamics::Force::Kind::none)
    throw InputError(scene.file, 0, "a magnetic field with a force is followed to a time: give --time");
  const dynamics::FollowLimits limits{
      .collisions = args.collisions.value_or(args.time ? std::numeric_limits<std::size_t>::max() : 100),
      .t_end = args.time.value_or(dynamics::never)};
  const std::string out_dir = !args.out.empty() ? args.out : scene.output_dir + "-trajectory";
  const auto names = columns(scene.dimension());
  OutputDir out(out_dir);
  ChunkWriter rows(out, names.size(), args.chunk);
  TrajectoryProgress progress{Progress("trajectory", args.time ? 1000 : limits.collisions, !args.quiet),
                              args.time.has_value(), limits.t_end};
  const auto made = dynamics::with_flight(
      scene, [&](const auto& flight) { return write_rows(scene, flight, args, limits, rows, progress); });
  rows.flush();
  progress.bar.finish();
  const nlohmann::json index = {
      {"table", scene.file}, {"shape", scene.shape_name()}, {"force", scene.force.name()},
      {"dimension", scene.dimension()}, {"mass", scene.mass}, {"seed", scene.seed}, {"particle", args.particle},
      {"dt", args.dt.value_or(0)}, {"time", args.time ? nlohmann::json(*args.time) : nlohmann::json()},
      {"collisions", made.collisions}, {"escaped", made.escaped}, {"trapped", made.trapped},
      {"columns", names},
      {"units", {{"t", "time"}, {"position", "length"}, {"velocity", "length/time"},
                 {"wall", "piece index (-1 the start, -2 a sample between collisions)"},
                 {"energy", "mass length^2/time^2"}}},
      {"rows", rows.rows()}, {"chunks", rows.files()}};
  out.write_json("trajectory.json", index);
  out.commit();
  fmt::print("trajectory: {} collisions, {} rows of particle {} in '{}' (force {}){}; results in {}/\n",
             made.collisions, rows.rows(), args.particle, scene.shape_name(), scene.force.name(),
             made.trapped ? ", trapped" : "", out_dir);
  if (made.escaped) {
    fmt::print(stderr, "billiard: error: the particle escaped the region after {} collisions\n", made.collisions);
    throw CLI::RuntimeError(3);
  }
}

/// A positive, finite number.
const CLI::Validator positive_value(
    [](std::string& text) {
      std::string error = expression_value(text);
      if (!error.empty()) return error;
      const double v = std::stod(text);
      return v > 0 && std::isfinite(v) ? std::string() : "must be a positive finite number, not " + text;
    },
    "EXPR");

}  // namespace

void add_trajectory(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "trajectory", "One particle's collisions (and states between them with --dt), streamed to chunked .npy files");
  auto args = std::make_shared<TrajectoryArgs>();
  cmd->add_option("table", args->source, "shape file (a free particle at speed 1) or scene file (YAML)")->required();
  cmd->add_option("--collisions", args->collisions, "stop after this many collisions (default: 100 without --time)")
      ->transform(whole_number(1, 1e15));
  cmd->add_option("--time", args->time, "stop at this time")->transform(positive_value);
  cmd->add_option("--dt", args->dt, "also sample the state at times 0, DT, 2 DT, ... along the flight")
      ->transform(positive_value);
  cmd->add_option("--particle", args->particle, "which particle of the scene (from 0; for a shape, its random stream)")
      ->transform(whole_number(0, 1e6))
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "random seed of the initial state (default: the scene's, or 1)")->check(seed_value);
  cmd->add_option("--chunk", args->chunk, "rows in each chunk file")->transform(whole_number(1, 1e6))->capture_default_str();
  cmd->add_option("--out", args->out, "output directory (default: out/NAME-trajectory)");
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  add_set_option(cmd, args->set);
  cmd->callback([args] { run_trajectory(*args); });
}

}  // namespace billiards::cli
