// billiard plot SHAPE -o shape.png [--trajectory K]: draws a shape and a free trajectory.
// The geometry and the trajectory are computed here; matplotlib (scripts/plot_shape.py, run
// with Debian's /usr/bin/python3) only draws them.
#include "commands.hpp"
#include "options.hpp"

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/geometry.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace billiards::cli {

namespace {

namespace fs = std::filesystem;

nlohmann::json loop_points(const geometry::Loop& loop) {
  nlohmann::json pts = nlohmann::json::array();
  for (const auto& p : loop.pieces) {
    const int n = std::holds_alternative<geometry::Segment>(p) ? 1 : 96;
    for (int i = 0; i < n; ++i) {
      const auto q = geometry::point_along(p, double(i) / n);
      pts.push_back({q.x(), q.y()});
    }
  }
  return pts;
}

nlohmann::json free_trajectory(const geometry::Region2& region, int collisions, std::uint64_t seed) {
  const dynamics::Table table(region);
  dynamics::ParticleRng rng(seed, 0);
  auto s = dynamics::sample_microcanonical(table, 1.0, rng);
  nlohmann::json pts = nlohmann::json::array({{s.x.x(), s.x.y()}});
  for (int k = 0; k < collisions; ++k) {
    const auto hit = dynamics::collision(table, dynamics::FreeFlight{}, s);
    if (!hit.found()) throw std::runtime_error("the trajectory escaped the region");
    dynamics::bounce(dynamics::FreeFlight{}, s, hit);
    pts.push_back({s.x.x(), s.x.y()});
  }
  return pts;
}

std::string scripts_dir() {
  const char* env = std::getenv("BILLIARDS_SCRIPTS");
  return env ? env : BILLIARDS_SOURCE_DIR "/scripts";
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
  cmd->add_option("--trajectory", args->trajectory, "draw a free trajectory of K collisions")->check(CLI::NonNegativeNumber);
  cmd->add_option("--seed", args->seed, "seed of the trajectory's initial condition");
  add_set_option(cmd, args->set);
  cmd->callback([args] {
    const auto shape = geometry::load_shape(args->shape, parse_overrides(args->set));
    const auto m = geometry::measures_of(shape.region);
    nlohmann::json data;
    data["title"] = fmt::format("{}: V = {:.6g}, S = {:.6g}, mean free path = {:.6g}", shape.region.name, m.volume,
                                m.surface, geometry::mean_free_path(m));
    data["loops"] = nlohmann::json::array();
    for (const auto* loop : shape.region.loops()) data["loops"].push_back(loop_points(*loop));
    data["trajectory"] = args->trajectory > 0 ? free_trajectory(shape.region, args->trajectory, args->seed)
                                              : nlohmann::json::array();
    const fs::path json = fs::temp_directory_path() / fmt::format("billiard-plot-{}.json", getpid());
    std::ofstream(json) << data.dump();
    const std::string cmdline =
        fmt::format("/usr/bin/python3 '{}/plot_shape.py' '{}' '{}'", scripts_dir(), json.string(), args->output);
    const int status = std::system(cmdline.c_str());
    fs::remove(json);
    if (status != 0)
      throw std::runtime_error(fmt::format("drawing failed ({}): is python3-matplotlib installed?", cmdline));
  });
}

}  // namespace billiards::cli
