// billiard plot SHAPE -o shape.png|.pdf|.svg [--trajectory K]: draws a shape and a free trajectory.
// The geometry and the trajectory are computed here, so the picture shows exactly the walls
// the dynamics uses; matplotlib (scripts/plot_shape.py) only draws the points it is given.
#include "commands.hpp"
#include "interrupt.hpp"
#include "options.hpp"
#include "python.hpp"

#include "billiards/dynamics/random.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/geometry.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <unistd.h>

namespace billiards::cli {

namespace {

namespace fs = std::filesystem;

/// Arcs get a vertex every half degree: smooth at any figure size, and a polygon with
/// thousands of edges is still drawn edge for edge.
constexpr double arc_step = geometry::pi / 360;

/// A longer trajectory would only paint the region solid (and its JSON takes ~50 bytes a point).
constexpr double max_collisions = 1e6;

/// The loop's outline (geometry::outline_of) as a JSON list of points.
nlohmann::json loop_points(const geometry::Loop& loop) {
  nlohmann::json pts = nlohmann::json::array();
  for (const auto& q : geometry::outline_of(loop, arc_step)) pts.push_back({q.x(), q.y()});
  return pts;
}

/// A point as a JSON list of its coordinates (2-D or 3-D).
template <class V>
nlohmann::json point_json(const V& p) {
  return std::vector<double>(p.data(), p.data() + p.size());
}

/// The start point and the K collision points of one free trajectory, 2-D (`Flight` =
/// FreeFlight) or 3-D (FreeFlight3): the walk of `billiards.trajectory` in Python.
template <class Flight, class Region>
nlohmann::json free_trajectory(const Region& region, int collisions, std::uint64_t seed) {
  const dynamics::TableFor<Flight> table(region);
  dynamics::ParticleRng rng(seed, 0);
  const auto s = sample_microcanonical(table, 1.0, rng);
  nlohmann::json pts = nlohmann::json::array({point_json(s.x)});
  const std::size_t made = dynamics::evolve(table, Flight{}, s, collisions,
                                            [&](const auto&, const auto& after) { pts.push_back(point_json(after.x)); });
  if (made < std::size_t(collisions))
    throw std::runtime_error(fmt::format("the trajectory escaped the region after {} collisions", made));
  return pts;
}

std::string title_of(const geometry::Shape& shape, int collisions, std::uint64_t seed) {
  const auto m = geometry::measures_of(shape.region);
  std::string title = fmt::format("{}:  V = {:.6g},  S = {:.6g},  mean free path = {:.6g}", shape.region.name,
                                  m.volume, m.surface, geometry::mean_free_path(m));
  if (collisions > 0) title += fmt::format("\nfree trajectory: {} collisions, seed {}", collisions, seed);
  return title;
}

/// A 3-D shape as faces (polygons; a mesh's triangles, at most `max_faces` of them evenly
/// picked so that the picture stays drawable), spheres and a free trajectory.
nlohmann::json shape3_data(const std::string& path, const Overrides& set, int collisions, std::uint64_t seed) {
  using namespace geometry3;
  constexpr std::size_t max_faces = 20000;
  const auto shape = load_shape3(path, set);
  const auto& region = shape.region;
  nlohmann::json faces = nlohmann::json::array(), spheres = nlohmann::json::array();
  const auto sphere = [&](const Ball& b, bool outer) {
    spheres.push_back({{"center", point_json(b.center)}, {"radius", b.radius}, {"outer", outer}});
  };
  if (const auto* p = std::get_if<ConvexPolyhedron>(&region.outer)) {
    for (const auto& face : p->faces) {
      nlohmann::json f = nlohmann::json::array();
      for (const auto& v : face) f.push_back(point_json(v));
      faces.push_back(f);
    }
  } else if (const auto* m = std::get_if<TriangleMesh>(&region.outer)) {
    const std::size_t step = (m->triangles.size() + max_faces - 1) / max_faces;
    for (std::size_t i = 0; i < m->triangles.size(); i += step) {
      const auto& t = m->triangles[i];
      faces.push_back({point_json(m->vertices[t[0]]), point_json(m->vertices[t[1]]), point_json(m->vertices[t[2]])});
    }
  } else {
    sphere(std::get<Ball>(region.outer), true);
  }
  for (const Ball& b : region.holes) sphere(b, false);

  const auto trajectory = collisions > 0 ? free_trajectory<dynamics::FreeFlight3>(region, collisions, seed)
                                          : nlohmann::json::array();
  const auto m = measures_of(region);
  std::string title = fmt::format("{}:  V = {:.6g},  S = {:.6g},  mean free path = {:.6g}", region.name, m.volume,
                                  m.surface, geometry::mean_free_path(m));
  if (collisions > 0) title += fmt::format("\nfree trajectory: {} collisions, seed {}", collisions, seed);
  return {{"dimension", 3}, {"title", title}, {"faces", faces}, {"spheres", spheres}, {"trajectory", trajectory}};
}

/// The formats matplotlib writes without extra libraries; the output's extension picks one.
void require_picture_format(const fs::path& output) {
  const std::string ext = output.extension().string();
  if (ext != ".png" && ext != ".pdf" && ext != ".svg")
    throw InputError("-o " + output.string(), 0, "the picture's format follows its extension: .png, .pdf or .svg");
}

/// Draws `data` into `output` (draw_into: complete or untouched).
void draw(const nlohmann::json& data, const fs::path& output) {
  const fs::path script = script_path(data.value("dimension", 2) == 3 ? "plot_shape3.py" : "plot_shape.py");
  const TempFile json{fs::temp_directory_path() / fmt::format("billiard-plot-{}.json", getpid())};
  std::ofstream out(json.path);
  out << data.dump();
  out.close();
  if (!out) throw std::runtime_error("cannot write " + json.path.string());
  draw_into(script, json.path, output);
}

}  // namespace

void add_plot(CLI::App& app) {
  auto* cmd = app.add_subcommand("plot", "Draw a shape (PNG, PDF or SVG), optionally with a free trajectory");
  struct Args {
    std::string shape, output;
    int trajectory = 0;
    std::uint64_t seed = 1;
    std::vector<std::string> set;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("shape", args->shape, "shape file (YAML)")->required();
  cmd->add_option("-o,--output", args->output, "picture to write (.png, .pdf or .svg)")->required();
  cmd->add_option("--trajectory", args->trajectory, "draw a free trajectory of K collisions")
      ->transform(whole_number(0, max_collisions));
  cmd->add_option("--seed", args->seed, "seed of the trajectory's initial condition")->check(seed_value);
  add_set_option(cmd, args->set);
  cmd->callback([args] {
    require_picture_format(args->output);
    if (geometry3::shape_dimension(args->shape) == 3) {
      draw(shape3_data(args->shape, parse_overrides(args->set), args->trajectory, args->seed), args->output);
      fmt::print("wrote {}\n", args->output);
      return;
    }
    const auto shape = geometry::load_shape(args->shape, parse_overrides(args->set));
    nlohmann::json data;
    data["title"] = title_of(shape, args->trajectory, args->seed);
    data["loops"] = nlohmann::json::array();
    for (const auto* loop : shape.region.loops()) data["loops"].push_back(loop_points(*loop));
    data["trajectory"] = args->trajectory > 0 ? free_trajectory<dynamics::FreeFlight>(shape.region, args->trajectory, args->seed)
                                              : nlohmann::json::array();
    draw(data, args->output);
    fmt::print("wrote {}\n", args->output);
  });
}

}  // namespace billiards::cli
