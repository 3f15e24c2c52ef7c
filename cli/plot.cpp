// billiard plot SHAPE -o shape.png [--trajectory K]: draws a shape and a free trajectory.
// The geometry and the trajectory are computed here, so the picture shows exactly the walls
// the dynamics uses; matplotlib (scripts/plot_shape.py) only draws the points it is given.
#include "commands.hpp"
#include "options.hpp"
#include "output.hpp"

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/geometry.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace billiards::cli {

namespace {

namespace fs = std::filesystem;

/// Arcs get a vertex every half degree: smooth at any figure size, and a polygon with
/// thousands of edges is still drawn edge for edge.
constexpr double arc_step = geometry::pi / 360;

/// The loop as a closed polyline: each piece contributes its vertices up to, not including,
/// its target, which is the next piece's source.
nlohmann::json loop_points(const geometry::Loop& loop) {
  nlohmann::json pts = nlohmann::json::array();
  for (const auto& p : loop.pieces) {
    const auto* arc = std::get_if<geometry::Arc>(&p);
    const int n = arc ? std::max(4, int(std::ceil(std::abs(arc->sweep) / arc_step))) : 1;
    for (int i = 0; i < n; ++i) {
      const auto q = geometry::point_along(p, double(i) / n);
      pts.push_back({q.x(), q.y()});
    }
  }
  return pts;
}

/// The start point and the K collision points of one free trajectory.
nlohmann::json free_trajectory(const geometry::Region2& region, int collisions, std::uint64_t seed) {
  const dynamics::Table table(region);
  dynamics::ParticleRng rng(seed, 0);
  auto s = dynamics::sample_microcanonical(table, 1.0, rng);
  nlohmann::json pts = nlohmann::json::array({{s.x.x(), s.x.y()}});
  for (int k = 0; k < collisions; ++k) {
    const auto hit = dynamics::collision(table, dynamics::FreeFlight{}, s);
    if (!hit.found())
      throw std::runtime_error(fmt::format("the trajectory escaped the region after {} collisions", k));
    dynamics::bounce(dynamics::FreeFlight{}, s, hit);
    pts.push_back({s.x.x(), s.x.y()});
  }
  return pts;
}

std::string title_of(const geometry::Shape& shape, int collisions, std::uint64_t seed) {
  const auto m = geometry::measures_of(shape.region);
  std::string title = fmt::format("{}:  V = {:.6g},  S = {:.6g},  mean free path = {:.6g}", shape.region.name,
                                  m.volume, m.surface, geometry::mean_free_path(m));
  if (collisions > 0) title += fmt::format("\nfree trajectory: {} collisions, seed {}", collisions, seed);
  return title;
}

/// Removes its file when it goes out of scope, so no exit path leaves temporaries behind.
struct TempFile {
  fs::path path;
  ~TempFile() {
    std::error_code ignored;
    fs::remove(path, ignored);
  }
};

}  // namespace

// Scripts are found in $BILLIARDS_SCRIPTS, else in the source tree this program was built from.
fs::path script_path(const std::string& name) {
  const char* env = std::getenv("BILLIARDS_SCRIPTS");
  const fs::path script = fs::path(env ? env : BILLIARDS_SOURCE_DIR "/scripts") / name;
  if (!fs::is_regular_file(script))
    throw std::runtime_error(fmt::format("{} not found (set BILLIARDS_SCRIPTS to the directory that holds it)",
                                         script.string()));
  return script;
}

namespace {

/// Debian's interpreter, which has python3-matplotlib; $BILLIARDS_PYTHON overrides it.
std::string python() {
  const char* env = std::getenv("BILLIARDS_PYTHON");
  return env ? env : "/usr/bin/python3";
}

}  // namespace

void run_python(const fs::path& script, const std::vector<std::string>& args) {
  std::vector<std::string> argv_s = {python(), script.string()};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (const int err = posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ))
    throw std::runtime_error(fmt::format("cannot run {}: {} (set BILLIARDS_PYTHON to a python3 with matplotlib)",
                                         argv_s[0], std::strerror(err)));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  const std::string how = WIFEXITED(status) ? fmt::format("exit status {}", WEXITSTATUS(status))
                                            : fmt::format("signal {}", WTERMSIG(status));
  throw std::runtime_error(fmt::format("drawing failed: {} {} ended with {}", argv_s[0], script.string(), how));
}

namespace {

/// Draws `data` into `output`.  The script draws into a temporary file next to `output` that
/// is renamed into place only on success, so `output` is either the complete picture or
/// untouched.
void draw(const nlohmann::json& data, const fs::path& output) {
  const fs::path script = script_path("plot_shape.py");
  const TempFile json{fs::temp_directory_path() / fmt::format("billiard-plot-{}.json", getpid())};
  std::ofstream out(json.path);
  out << data.dump();
  out.close();
  if (!out) throw std::runtime_error("cannot write " + json.path.string());
  if (output.has_parent_path()) fs::create_directories(output.parent_path());
  const TempFile png{fs::path(output.string() + fmt::format(".tmp-{}.png", getpid()))};
  run_python(script, {json.path.string(), png.path.string()});
  fs::rename(png.path, output);
}

}  // namespace

void add_plot(CLI::App& app) {
  auto* cmd = app.add_subcommand("plot", "Draw a shape (PNG), optionally with a free trajectory");
  struct Args {
    std::string shape, output;
    int trajectory = 0;
    std::uint64_t seed = 1;
    std::vector<std::string> set;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("shape", args->shape, "shape file (YAML)")->required();
  cmd->add_option("-o,--output", args->output, "PNG file to write")->required();
  cmd->add_option("--trajectory", args->trajectory, "draw a free trajectory of K collisions")
      ->check(CLI::Range(0, std::numeric_limits<int>::max()));
  cmd->add_option("--seed", args->seed, "seed of the trajectory's initial condition");
  add_set_option(cmd, args->set);
  cmd->callback([args] {
    const auto shape = geometry::load_shape(args->shape, parse_overrides(args->set));
    nlohmann::json data;
    data["title"] = title_of(shape, args->trajectory, args->seed);
    data["loops"] = nlohmann::json::array();
    for (const auto* loop : shape.region.loops()) data["loops"].push_back(loop_points(*loop));
    data["trajectory"] = args->trajectory > 0 ? free_trajectory(shape.region, args->trajectory, args->seed)
                                              : nlohmann::json::array();
    draw(data, args->output);
    fmt::print("wrote {}\n", args->output);
  });
}

}  // namespace billiards::cli
