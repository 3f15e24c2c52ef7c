#include "phase_space.hpp"

#include "run.hpp"

#include "billiards/geometry/shape_file.hpp"
#include "billiards/geometry/yaml_reader.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <filesystem>

namespace billiards::cli {

bool is_scene_file(const std::string& path) {
  try {
    const YAML::Node doc = load_yaml(read_input_file(path, "a shape or scene file"), path);
    return doc.IsMap() && doc["shape"];
  } catch (const std::exception&) {
    return false;  // (the shape reader reports what is wrong with it)
  }
}

void add_phase_space_options(CLI::App* cmd, PhaseSpaceArgs& args, std::size_t particles, std::size_t collisions) {
  args.particles = particles;
  args.collisions = collisions;
  cmd->add_option("table", args.source, "shape file (free flights at speed 1) or scene file (YAML)")->required();
  cmd->add_option("--particles", args.particles, "number of independent trajectories")
      ->transform(whole_number(2, 1e9))
      ->capture_default_str();
  cmd->add_option("--collisions", args.collisions, "collisions of each trajectory")
      ->transform(whole_number(1, 1e12))
      ->capture_default_str();
  cmd->add_option("--seed", args.seed, "random seed of the initial states (default: the scene's, or 1)")->check(seed_value);
  cmd->add_option("--threads", args.threads, "threads (default: all cores)")->transform(whole_number(1, max_threads));
  cmd->add_flag("--quiet", args.quiet, "no progress bar");
  add_set_option(cmd, args.set);
}

dynamics::Scene load_phase_space_scene(const PhaseSpaceArgs& args) {
  dynamics::SceneOverrides overrides;
  overrides.set = parse_overrides(args.set);
  overrides.particles = args.particles;
  overrides.seed = args.seed;
  if (is_scene_file(args.source)) return dynamics::load_scene(args.source, overrides);
  dynamics::Scene scene;
  scene.file = args.source;
  if (geometry3::shape_dimension(args.source) == 3) {
    scene.table = dynamics::SceneTable<3>{geometry3::load_shape3(args.source, overrides.set), {}};
    scene.force.amplitude = Eigen::VectorXd::Zero(3);
  } else {
    scene.table = dynamics::SceneTable<2>{geometry::load_shape(args.source, overrides.set), {}};
  }
  scene.energy = 0.5;
  scene.particles = args.particles;
  scene.seed = args.seed.value_or(1);
  scene.output_dir = "out/" + std::filesystem::path(args.source).stem().string();
  return scene;
}

void refuse_forced_magnetic(const dynamics::Scene& scene, const std::string& command) {
  if (scene.magnetic() && scene.force.kind != dynamics::Force::Kind::none)
    throw InputError(scene.file, 0,
                     command + " follows particles collision by collision without a time horizon, which a magnetic "
                               "field with a force needs (billiard run follows them to its times)");
}

}  // namespace billiards::cli
