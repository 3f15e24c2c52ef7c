// billiard animate SHAPE|SCENE -o movie.mp4|movie.gif: the particles of a scene (or free
// particles in a shape) moving in the table.  Their states at the frame times are computed here
// (dynamics::fill_frames, along each flight's true path), and the Fokker–Planck density of a
// driven scene beside them; matplotlib (scripts/plot_animate.py, with billiardkit's movie.py)
// only draws what it is given, and ffmpeg or Pillow encodes it.
#include "commands.hpp"
#include "options.hpp"
#include "output.hpp"
#include "phase_space.hpp"
#include "progress.hpp"
#include "python.hpp"
#include "run.hpp"

#include "billiards/analysis/coefficients.hpp"
#include "billiards/dynamics/scene_frames.hpp"
#include "billiards/geometry.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <algorithm>
#include <filesystem>
#include <optional>

#include <unistd.h>

namespace billiards::cli {

namespace {

namespace fs = std::filesystem;

struct AnimateArgs {
  std::string file, output;
  std::optional<std::size_t> particles;
  std::optional<double> time;
  std::size_t frames = 250;
  double fps = 25;
  std::size_t trail = 0;
  bool histogram = false, no_histogram = false;  // neither: when the theory covers the scene
  std::optional<std::uint64_t> seed;
  std::vector<std::string> set;
  int threads = 0;
  bool quiet = false;
};

/// Particles shown when --particles is not given (more would hide the table).
constexpr std::size_t default_particles = 100;
/// A shape's free particles: speed 1 (E = 1/2, m = 1), for this long by default.
constexpr double shape_time = 10;

/// The scene to animate: the file's, or free particles in the shape from a microcanonical start.
dynamics::Scene scene_of(const AnimateArgs& args) {
  dynamics::SceneOverrides ov;
  ov.set = parse_overrides(args.set);
  ov.time = args.time;
  ov.seed = args.seed;
  // (A scene has at least two particles, for its statistics; one of them may be shown.)
  if (args.particles) ov.particles = std::max<std::size_t>(*args.particles, 2);
  if (is_scene_file(args.file)) return dynamics::load_scene(args.file, ov);
  ov.particles = std::max<std::size_t>(args.particles.value_or(default_particles), 2);
  const std::string text = fmt::format(
      "shape: {}\ninitial:\n  microcanonical: {{energy: 1/2}}\nrun:\n  particles: {}\n  time: {}\n",
      nlohmann::json(fs::absolute(args.file).string()).dump(), *ov.particles, args.time.value_or(shape_time));
  return dynamics::parse_scene(text, args.file, ".", ov);
}

/// The movie's format follows its extension.
void require_movie_format(const fs::path& output) {
  const std::string ext = output.extension().string();
  if (ext != ".mp4" && ext != ".gif")
    throw InputError("-o " + output.string(), 0, "the movie's format follows its extension: .mp4 or .gif");
}

/// The particles' frames, a chunk of particles at a time so that the progress bar moves.
dynamics::SceneFrames frames_of(const dynamics::Scene& scene, const AnimateArgs& args, std::size_t particles) {
  auto f = dynamics::empty_frames(scene, particles, args.frames, scene.time);
  const int threads = args.threads > 0 ? args.threads : omp_get_max_threads();
  Progress progress("animate", particles, !args.quiet);
  for (std::size_t first = 0; first < particles;) {
    const std::size_t last = std::min(particles, first + 4 * std::size_t(threads));
    dynamics::fill_frames(scene, f, first, last, threads);
    progress.update(first = last);
  }
  progress.finish();
  return f;
}

/// The files plot_animate.py reads: movie.json (the table's outline, title, fps, trail, panel)
/// and the frames as .npy matrices.
void write_movie_input(const OutputDir& dir, const dynamics::Scene& scene, const dynamics::SceneFrames& f,
                       const AnimateArgs& args) {
  const std::size_t K = f.times.size(), N = f.particles;
  nlohmann::json meta = {{"fps", args.fps}, {"trail", args.trail}, {"outline", nlohmann::json::array()},
                         {"title", fmt::format("{}: N = {}", fs::path(args.file).stem().string(), N)}};
  for (const auto* loop : scene.shape<2>().region.loops()) {
    nlohmann::json pts = nlohmann::json::array();
    for (const auto& q : geometry::outline_of(*loop, geometry::pi / 360)) pts.push_back({q.x(), q.y()});
    meta["outline"].push_back(pts);
  }
  dir.write_npy("times.npy", f.times, K, 1);
  dir.write_npy("positions.npy", f.positions, K, N * 2);
  dir.write_npy("energies.npy", f.energies, K, N);
  const std::vector<double> later(f.times.begin() + 1, f.times.end());
  if (const auto fp = args.no_histogram ? std::nullopt : analysis::fokker_planck_of(scene, later, 400)) {
    std::vector<double> centers, density;
    for (std::size_t i = 0; i < fp->grid.cells(); ++i) centers.push_back(fp->grid.center(i));
    for (const auto& row : fp->eta) density.insert(density.end(), row.begin(), row.end());
    dir.write_npy("fp_energies.npy", centers, centers.size(), 1);
    dir.write_npy("fp_density.npy", density, K - 1, centers.size());
  }
  dir.write_json("movie.json", meta);
}

void animate(const AnimateArgs& args) {
  require_movie_format(args.output);
  const auto scene = scene_of(args);
  if (scene.dimension() != 2) throw InputError(args.file, 0, "animate draws 2-D scenes; this one is 3-D");
  if (!(scene.time > 0)) throw InputError(args.file, 0, "the animation needs a positive time (--time)");
  if (args.histogram && !analysis::prediction_of(scene))
    throw InputError(args.file, 0, "--histogram needs a driven scene the theory covers (a Fokker–Planck density)");
  const std::size_t particles = args.particles.value_or(std::min(scene.particles, default_particles));
  const auto f = frames_of(scene, args, particles);
  const OutputDir input(fs::temp_directory_path() / fmt::format("billiard-animate-{}", getpid()));
  write_movie_input(input, scene, f, args);
  std::vector<std::string> extra;
  if (!args.quiet && isatty(STDERR_FILENO)) extra.push_back("--progress");
  draw_into(script_path("plot_animate.py"), input.path(""), args.output, extra);
  const auto escaped = std::count(f.escaped.begin(), f.escaped.end(), 1);
  fmt::print("wrote {}: {} frames of {} particles, t = 0 .. {}{}\n", args.output, args.frames, particles, scene.time,
             escaped ? fmt::format(" ({} escaped)", escaped) : "");
}

}  // namespace

void add_animate(CLI::App& app) {
  auto* cmd = app.add_subcommand("animate", "Write a movie (MP4 or GIF) of particles moving in a shape or a scene");
  auto args = std::make_shared<AnimateArgs>();
  cmd->add_option("file", args->file, "shape or scene file (YAML)")->required();
  cmd->add_option("-o,--output", args->output, "movie to write (.mp4 or .gif)")->required();
  cmd->add_option("--particles", args->particles, "particles shown (default: up to 100)")
      ->transform(whole_number(1, 1e5));
  cmd->add_option("--time", args->time, "the movie shows t = 0 .. T (default: the scene's end time; 10 for a shape)")
      ->transform(expression_value);
  cmd->add_option("--frames", args->frames, "frames, at uniform times from 0 to T")->transform(whole_number(2, 1e5));
  cmd->add_option("--fps", args->fps, "frames per second of the movie")->transform(expression_value)
      ->check(CLI::Range(1e-3, 1e3));
  cmd->add_option("--trail", args->trail, "frames of path drawn behind each particle")
      ->transform(whole_number(0, 1e5));
  auto* histogram = cmd->add_flag("--histogram", args->histogram,
                                  "the energy histogram against the Fokker–Planck density beside the table (default: "
                                  "when the theory covers the scene)");
  cmd->add_flag("--no-histogram", args->no_histogram, "no histogram panel")->excludes(histogram);
  cmd->add_option("--seed", args->seed, "random seed of the initial conditions")->check(seed_value);
  cmd->add_option("--threads", args->threads, "threads (default: all cores)")->transform(whole_number(1, max_threads));
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  add_set_option(cmd, args->set);
  cmd->callback([args] { animate(*args); });
}

}  // namespace billiards::cli
