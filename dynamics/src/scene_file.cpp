#include "billiards/dynamics/scene.hpp"

#include "billiards/dynamics/field_flight.hpp"
#include "billiards/dynamics/table.hpp"
#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/yaml_reader.hpp"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace billiards::dynamics {

const char* Force::name() const {
  switch (kind) {
    case Kind::none: return "none";
    case Kind::constant: return "constant";
    case Kind::periodic: return quivering_walls ? "periodic (quivering walls)" : "periodic";
    case Kind::field: return "field";
  }
  return "?";
}

namespace {

namespace fs = std::filesystem;

using SceneReader = YamlReader;

/// Seeds in a file are numbers, exact up to 2^53 (--seed takes any 64-bit value).
constexpr double max_seed = 9007199254740992.0;

/// Where `key` of the mapping n is written (the key's own line: a block value starts below it).
geometry::SourceRef key_ref(const SceneReader& r, const YAML::Node& n, const std::string& key) {
  for (const auto& kv : n)
    if (kv.first.Scalar() == key) return r.ref(kv.first);
  return r.ref(n);
}

/// A function of x, y from a scalar node.
CoordinateFunction coordinate_function(const SceneReader& r, const Expressions& expr, const YAML::Node& n) {
  if (!n.IsScalar()) r.fail(n, "expected an expression of x and y");
  return CoordinateFunction(n.Scalar(), expr, r.file(), r.line(n));
}

/// A vector of two functions of x, y: [f_x, f_y].
std::array<CoordinateFunction, 2> coordinate_vector(const SceneReader& r, const Expressions& expr,
                                                    const YAML::Node& n, const std::string& what) {
  if (!n.IsSequence() || n.size() != 2) r.fail(n, what + " must be a list of two expressions [f_x, f_y]");
  return {coordinate_function(r, expr, n[0]), coordinate_function(r, expr, n[1])};
}

Force read_force(const SceneReader& r, const Expressions& expr, const YAML::Node& n, int dimension) {
  Force f;
  f.amplitude = Eigen::VectorXd::Zero(dimension);
  if (!n || (n.IsScalar() && n.Scalar() == "none")) return f;
  r.expect_keys(n, {"constant", "periodic", "field"}, "'force'");
  if (n.size() != 1) r.fail(n, "'force' is one of: none, constant, periodic, field");
  if (const YAML::Node field = n["field"]) {
    r.expect_keys(field, {"amplitude", "omega", "phase"}, "a field force");
    if (dimension == 3) r.fail(field, "a field force is implemented in 2-D only");
    f.kind = Force::Kind::field;
    f.field = coordinate_vector(r, expr, r.required(field, "amplitude", "a field force"), "a field amplitude");
    f.field_source = key_ref(r, n, "field");
    f.omega = r.positive(r.required(field, "omega", "a field force"), "omega");
    f.phase = field["phase"] ? r.number(field["phase"]) : 0.0;
    return f;
  }
  if (const YAML::Node c = n["constant"]) {
    r.expect_keys(c, {"amplitude"}, "a constant force");
    f.kind = Force::Kind::constant;
    f.amplitude = r.vector(r.required(c, "amplitude", "a constant force"), dimension);
    return f;
  }
  const YAML::Node p = n["periodic"];
  r.expect_keys(p, {"amplitude", "omega", "phase", "picture"}, "a periodic force");
  f.kind = Force::Kind::periodic;
  f.amplitude = r.vector(r.required(p, "amplitude", "a periodic force"), dimension);
  f.omega = r.positive(r.required(p, "omega", "a periodic force"), "omega");
  f.phase = p["phase"] ? r.number(p["phase"]) : 0.0;
  if (const YAML::Node picture = p["picture"]) {
    if (!picture.IsScalar() || (picture.Scalar() != "lab" && picture.Scalar() != "quivering-walls"))
      r.fail(picture, "'picture' is one of: lab, quivering-walls");
    f.quivering_walls = picture.Scalar() == "quivering-walls";
    if (f.quivering_walls && dimension == 3) r.fail(picture, "the quivering-walls picture is not implemented in 3-D");
  }
  return f;
}

/// magnetic: {B: value}, the field perpendicular to the plane, in 2-D (returned as (0, 0, B));
/// {B: [Bx, By, Bz]} in 3-D.
Eigen::Vector3d read_magnetic(const SceneReader& r, const YAML::Node& n, int dimension) {
  r.expect_keys(n, {"B"}, "'magnetic'");
  const YAML::Node b = r.required(n, "B", "'magnetic'");
  if (dimension == 2) {
    if (!b.IsScalar()) r.fail(b, "in 2-D the magnetic field is perpendicular to the plane: B is a number, not a vector");
    return {0, 0, r.number(b)};
  }
  if (b.IsScalar()) r.fail(b, "in 3-D the magnetic field is a vector [Bx, By, Bz], not a number");
  return r.vector(b, 3);
}

/// potential: {expression: U, gradient: [dU/dx, dU/dy]}, the gradient optional: when it is
/// missing it is the exact derivative of U; when given, it must agree with that derivative on
/// a grid over the table's bounding box (so a typo cannot make a non-conservative force).
Potential read_potential(const SceneReader& r, const Expressions& expr, const YAML::Node& n, const Table& table) {
  r.expect_keys(n, {"expression", "gradient"}, "'potential'");
  Potential p;
  p.U = coordinate_function(r, expr, r.required(n, "expression", "'potential'"));
  p.gradient = {p.U.derivative(0), p.U.derivative(1)};
  if (const YAML::Node g = n["gradient"]) {
    const auto given = coordinate_vector(r, expr, g, "a potential's gradient");
    const Vec2 lo = table.lo(), size = table.hi() - table.lo();
    constexpr int k = 6;
    for (int axis = 0; axis < 2; ++axis)
      for (int i = 0; i <= k; ++i)
        for (int j = 0; j <= k; ++j) {
          const Vec2 x = lo + Vec2(size.x() * i / k, size.y() * j / k);
          const double want = p.gradient[axis](x), got = given[axis](x);
          if (!(std::abs(got - want) <= 1e-8 * (1 + std::abs(want))))
            r.fail(g[axis], fmt::format("gradient[{}] is not the derivative of the potential along {} (at ({:g}, "
                                        "{:g}): {:.10g}, the derivative is {:.10g})",
                                        axis, axis ? 'y' : 'x', x.x(), x.y(), got, want));
        }
    p.gradient = given;
  }
  return p;
}

/// More record times than this are a typo (and their table would not fit in memory).
constexpr std::size_t max_record_times = 10000;

/// Record times: a list, {every: dt} or {count: n} (evenly from 0 to the end time).  The start
/// and the end time are always recorded.
std::vector<double> read_record(const SceneReader& r, const YAML::Node& n, double time) {
  std::vector<double> t = {0.0};
  if (!n) {
  } else if (n.IsSequence()) {
    for (const auto& x : n) {
      const double v = r.number(x);
      if (v < 0 || (v <= t.back() && !(v == 0 && t.size() == 1))) r.fail(x, "record times must be ≥ 0 and increasing");
      if (v > 0 && v < time) t.push_back(v);
    }
  } else {
    r.expect_keys(n, {"every", "count"}, "'record'");
    if (n["every"]) {
      const double dt = r.positive(n["every"], "record.every");
      if (time / dt > max_record_times)
        r.fail(n["every"], fmt::format("record.every gives {:.3g} record times; at most {} are allowed", time / dt,
                                       max_record_times));
      for (double k = 1; k * dt < time * (1 - 1e-12); ++k) t.push_back(k * dt);
    } else {
      const std::size_t m = r.count(n["count"], "record.count");
      if (m > max_record_times) r.fail(n["count"], fmt::format("record.count is at most {}", max_record_times));
      for (std::size_t k = 1; k + 1 < m; ++k) t.push_back(time * double(k) / double(m - 1));
    }
  }
  t.push_back(time);
  return t;
}

/// One particle per line: x, y, vx, vy in 2-D; x, y, z, vx, vy, vz in 3-D (`S` is the state
/// type of the dimension, `inside` the table's point-in-region test).
template <class S, class Inside>
std::vector<S> read_initial_csv(const std::string& path, Inside inside) {
  constexpr int d = decltype(S::x)::RowsAtCompileTime;
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open initial-condition file");
  std::vector<S> states;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#' || (number == 1 && line.find_first_of("xXvV") == 0)) continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    S s;
    std::string extra;
    bool read = true;
    for (int k = 0; k < 2 * d && read; ++k) read = bool(fields >> (k < d ? s.x[k] : s.v[k - d]));
    if (!read || (fields >> extra))
      throw InputError(path, number, d == 2 ? "expected four numbers: x, y, vx, vy"
                                            : "expected six numbers: x, y, z, vx, vy, vz");
    if (!(s.x.cwiseAbs().maxCoeff() <= Expressions::max_magnitude && s.v.cwiseAbs().maxCoeff() <= Expressions::max_magnitude))
      throw InputError(path, number, fmt::format("a number is out of range: numbers lie within ±{:g}", Expressions::max_magnitude));
    if (!inside(s.x)) throw InputError(path, number, "particle is outside the region");
    if (!(s.v.squaredNorm() > 0)) throw InputError(path, number, "particle has zero velocity");
    states.push_back(s);
  }
  if (states.size() < 2) throw InputError(path, 0, "fewer than two particles in the initial-condition file (the statistics need two)");
  return states;
}

/// The drive in the range where runs are resolved: its phase ω t to 1e-6 rad at the end time
/// (ω T ≤ 4.5e9 in doubles), and a periodic force's displacement amplitude |F|/(m ω²) at most
/// 1000 mean free paths (beyond, the drive is no perturbation and flights are not resolved).
void check_drive(const Scene& scene, const SceneReader& r, const YAML::Node& force, const YAML::Node& time,
                 const SceneOverrides& ov) {
  if (scene.force.kind != Force::Kind::periodic && scene.force.kind != Force::Kind::field) return;
  const auto refuse = [&](bool from_command_line, const YAML::Node& n, const std::string& option,
                          const std::string& why) {
    if (from_command_line) throw InputError(option, 0, why);
    r.fail(n, why);
  };
  const double omega = scene.force.omega, phase_limit = 1e-6 / std::numeric_limits<double>::epsilon();
  if (omega * scene.time > phase_limit)
    refuse(ov.time.has_value(), time, "--time",
           fmt::format("the run time {:g} is too long for omega = {:g}: the drive's phase omega*t must stay below "
                       "{:.2g} to be resolved to 1e-6 rad",
                       scene.time, omega, phase_limit));
  if (scene.force.kind != Force::Kind::periodic) return;
  const double lambda = geometry::mean_free_path(scene.measures());
  const double displacement = scene.force.amplitude.norm() / (scene.mass * omega * omega);
  if (displacement > 1000 * lambda)
    refuse(ov.omega.has_value(), force, "--omega",
           fmt::format("omega = {:g} is too small for this force: the drive's displacement amplitude |F|/(m omega^2) "
                       "= {:.3g} exceeds 1000 mean free paths ({:.3g})",
                       omega, displacement, 1000 * lambda));
}

/// Does the shape file list exits (a non-empty `exits:` list; the phase-space code reads and
/// checks them)?
bool lists_exits(const std::string& shape_path) {
  const YAML::Node exits = load_yaml(read_input_file(shape_path, "shape file"), shape_path)["exits"];
  return exits && exits.IsSequence() && exits.size() > 0;
}

}  // namespace

geometry::Measures Scene::measures() const {
  return visit_shape([](const auto& shape) { return measures_of(shape.region); });
}

Scene load_scene(const std::string& path, const SceneOverrides& ov) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open scene file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_scene(buffer.str(), path, fs::path(path).parent_path().string(), ov);
}

Scene parse_scene(const std::string& text, const std::string& path, const std::string& base_dir,
                  const SceneOverrides& ov) {
  Scene scene;
  scene.file = path;
  scene.text = text;
  const YAML::Node doc = load_yaml(scene.text, path);
  Expressions expr;
  const SceneReader r(path, expr);
  if (!doc.IsMap()) throw InputError(path, 1, "a scene file is a YAML mapping");
  r.expect_keys(doc, {"shape", "set", "parameters", "mass", "initial", "force", "potential", "integrator", "run", "output",
                     "magnetic", "charge"},
                "a scene file");

  // Scene parameters take the --set values that name them; the rest go to the shape, after
  // the scene's own `set:` block.
  Overrides shape_set;
  if (const YAML::Node s = doc["set"]) {
    if (!s.IsMap()) r.fail(s, "'set' must be a mapping NAME: value of shape parameters");
    for (const auto& kv : s) {
      if (!kv.second.IsScalar()) r.fail(kv.second, "a shape parameter's value must be a number or expression");
      shape_set[kv.first.Scalar()] = kv.second.Scalar();
    }
  }
  if (const YAML::Node params = doc["parameters"]) r.define_parameters(params, ov.set);
  for (const auto& [name, value] : ov.set)
    if (!expr.values().count(name)) shape_set[name] = value;

  const YAML::Node shape_node = r.required(doc, "shape", "a scene file");
  if (!shape_node.IsScalar()) r.fail(shape_node, "'shape' is the path of a shape file");
  const std::string shape_path = (fs::path(base_dir) / shape_node.Scalar()).lexically_normal().string();
  if (geometry3::shape_dimension(shape_path) == 3)
    scene.table = SceneTable<3>{geometry3::load_shape3(shape_path, shape_set), {}};
  else
    scene.table = SceneTable<2>{geometry::load_shape(shape_path, shape_set), {}};

  scene.mass = doc["mass"] ? r.positive(doc["mass"], "mass") : 1.0;
  scene.force = read_force(r, expr, doc["force"], scene.dimension());
  if (const YAML::Node u = doc["potential"]) {
    if (scene.dimension() == 3) r.fail(u, "a potential is implemented in 2-D only");
    scene.potential = read_potential(r, expr, u, Table(scene.shape<2>().region));
    scene.potential->source = key_ref(r, doc, "potential");
  }
  if (const YAML::Node m = doc["magnetic"]) {
    scene.magnetic_field = read_magnetic(r, m, scene.dimension());
    if (doc["charge"]) scene.charge = r.number(doc["charge"]);
    if (scene.magnetic() && scene.charge == 0)
      r.fail(doc["charge"], "the charge must not be 0 in a magnetic field (with q = 0 the field does nothing: remove it)");
    if (scene.magnetic() && (scene.potential || scene.force.kind == Force::Kind::field || scene.force.quivering_walls))
      r.fail(m, fmt::format("a magnetic field is implemented with a uniform force only (constant or periodic, lab "
                            "picture), not with {}",
                            scene.potential ? "a potential" : scene.force.quivering_walls ? "quivering walls" : "a field force"));
  } else if (const YAML::Node q = doc["charge"]) {
    r.fail(q, "'charge' is the charge in a magnetic field: the scene has no 'magnetic'");
  }
  if (scene.dimension() == 3 && scene.force.kind == Force::Kind::constant && !scene.magnetic())
    r.fail(doc["force"]["constant"], "a constant force is implemented in 3-D only with a magnetic field (periodic and "
                                     "none are implemented without one)");
  if (const YAML::Node integ = doc["integrator"]) {
    r.expect_keys(integ, {"tolerance"}, "'integrator'");
    scene.integrator_tolerance = r.positive(r.required(integ, "tolerance", "'integrator'"), "integrator.tolerance");
    if (scene.integrator_tolerance < 1e-14 || scene.integrator_tolerance > 1e-2)
      r.fail(integ["tolerance"], "integrator.tolerance must lie in [1e-14, 1e-2]");
  }
  // Its flight refuses a field or potential that is not finite somewhere in the table's bounding
  // box (and walls it cannot scan): made here, that is bad input before any command prints or
  // writes.
  if (scene.integrated())
    FieldFlight(scene.force, scene.potential, scene.mass, Table(scene.shape<2>().region), scene.integrator_tolerance);
  if (ov.omega) {
    if (scene.force.kind != Force::Kind::periodic && scene.force.kind != Force::Kind::field)
      throw InputError(path, 0, "--omega needs a periodic force in the scene");
    if (!(*ov.omega > 0)) throw InputError("--omega", 0, "omega must be positive");
    scene.force.omega = *ov.omega;
  }

  const YAML::Node run = r.required(doc, "run", "a scene file");
  r.expect_keys(run, {"particles", "time", "record", "seed"}, "'run'");
  scene.time = ov.time ? *ov.time : r.positive(r.required(run, "time", "'run'"), "run.time");
  if (!(scene.time > 0)) throw InputError("--time", 0, "the run time must be positive");
  check_drive(scene, r, doc["force"], run["time"], ov);
  if (!ov.record) {
    scene.record_times = read_record(r, run["record"], scene.time);
  } else {  // (the file's record times are not read: for the overridden time they may be too many)
    scene.record_times = {0.0};
    for (double t : *ov.record) {
      if (!(t > scene.record_times.back())) throw InputError("--record", 0, "record times must be positive and increasing");
      if (t < scene.time) scene.record_times.push_back(t);
    }
    scene.record_times.push_back(scene.time);
  }
  scene.seed = ov.seed ? *ov.seed : run["seed"] ? r.whole(run["seed"], "run.seed", 0, max_seed) : 1;

  const YAML::Node init = r.required(doc, "initial", "a scene file");
  r.expect_keys(init, {"microcanonical", "csv", "through_exit"}, "'initial'");
  if (init.IsMap() && init.size() > 1) r.fail(init, "'initial' takes one of 'microcanonical', 'through_exit' and 'csv'");
  if (const YAML::Node csv = init["csv"]) {
    if (!csv.IsScalar()) r.fail(csv, "'csv' is the path of an initial-condition file");
    scene.initial_csv = (fs::path(base_dir) / csv.Scalar()).lexically_normal().string();
    std::visit([&]<int D>(SceneTable<D>& t) {
      const BasicTable<double, D> table(t.shape.region);
      t.initial_states = read_initial_csv<BasicState<double, D>>(scene.initial_csv,
                                                                 [&](const auto& x) { return table.contains(x); });
      scene.particles = t.initial_states.size();
    }, scene.table);
  } else {
    const char* kind = init["through_exit"] ? "through_exit" : "microcanonical";
    const YAML::Node ensemble = r.required(init, kind, "'initial'");
    r.expect_keys(ensemble, {"energy"}, fmt::format("'{}'", kind));
    scene.energy = r.positive(r.required(ensemble, "energy", fmt::format("'{}'", kind)), "energy");
    if (init["through_exit"]) {
      if (!lists_exits(shape_path))
        r.fail(ensemble, fmt::format("'through_exit' needs exits, and the shape file {} lists none (exits: [...], "
                                     "docs/shapes.md)",
                                     shape_path));
      scene.through_exit = r.ref(ensemble);
    }
    scene.particles = r.whole(r.required(run, "particles", "'run'"), "run.particles", 2, 1e12);
  }
  if (ov.particles) {
    if (!scene.initial_csv.empty() && *ov.particles > scene.particles)
      throw InputError("--particles", 0, "more particles than the initial-condition file holds");
    if (*ov.particles < 2) throw InputError("--particles", 0, "the statistics need at least two particles");
    scene.particles = *ov.particles;
  }
  if (const YAML::Node out = doc["output"]; out && (!out.IsScalar() || out.Scalar().empty()))
    r.fail(out, "'output' is the path of the output directory");
  scene.output_dir = ov.output_dir ? *ov.output_dir
                     : doc["output"]   ? doc["output"].Scalar()
                                       : "out/" + fs::path(path).stem().string();
  return scene;
}

}  // namespace billiards::dynamics
