// billiardkit._core, the compiled part of the Python package billiardkit (pybind11): 2-D and 3-D shapes and scenes from files or dicts,
// their exact geometry and the theory's coefficients, the Fokker–Planck solutions, ensemble runs
// and single trajectories.  It calls the same library functions as the `billiard` program, so the same
// scene and seed give the same numbers, bit for bit.  Arrays come out as numpy arrays that own
// the C++ buffers (no copies); runs release the GIL.
#include "billiards/analysis/coefficients.hpp"
#include "billiards/analysis/fokker_planck.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/dynamics/follow.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/dynamics/scene_frames.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/shape_file.hpp"
#include "billiards/geometry/shape_info.hpp"
#include "billiards/geometry3/shape3_info.hpp"
#include "billiards/version.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <memory>
#include <optional>

namespace py = pybind11;
using namespace pybind11::literals;

namespace billiards::python {

void def_phase_space(py::module_& m);  // phase_space.cpp

namespace {

using geometry::Shape;
using geometry3::Shape3;
using dynamics::Scene;

// --- conversions ---------------------------------------------------------------------------

/// A numpy array that owns `v`: the vector moves to the heap and a capsule frees it with the
/// array, so nothing is copied.
template <class T>
py::array_t<T> adopt(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
  auto* owner = new std::vector<T>(std::move(v));
  const py::capsule free(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(std::move(shape), owner->data(), free);
}

/// JSON as Python objects, through the json module: the same keys and numbers as the CLI's
/// --json output (nlohmann writes each double in its shortest round-trip form).
py::object to_python(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

/// A dict as YAML text for the file parsers: JSON is YAML, and one key per line lets errors
/// name a line.  numpy scalars and arrays become lists and numbers.
std::string yaml_text_of(const py::dict& d) {
  const auto plain = py::cpp_function([](const py::object& o) { return o.attr("tolist")(); });
  return py::str(py::module_::import("json").attr("dumps")(d, "indent"_a = 1, "default"_a = plain));
}

/// Python's set={"R2": 3, "a": "2*R1"}: NAME=VALUE overrides; numbers are written in full.
Overrides overrides_of(const std::optional<py::dict>& set) {
  Overrides out;
  if (!set) return out;
  for (const auto& [key, value] : *set) {
    const std::string text = py::isinstance<py::str>(value) ? value.cast<std::string>()
                                                             : fmt::format("{:.17g}", value.cast<double>());
    add_override(out, py::str(key).cast<std::string>() + "=" + text);
  }
  return out;
}

std::string path_of(const py::object& source) { return py::str(py::module_::import("os").attr("fspath")(source)); }

py::array_t<double> vector_array(const Eigen::VectorXd& v) {
  return adopt(std::vector<double>(v.data(), v.data() + v.size()), {v.size()});
}

// --- shapes and scenes ---------------------------------------------------------------------

/// A Shape or a Shape3, as the file or dict's `dimension` says.
py::object load_shape(const py::object& source, const std::optional<py::dict>& set,
                      const std::optional<py::object>& base_dir, const std::string& name) {
  const auto ov = overrides_of(set);
  if (py::isinstance<py::dict>(source)) {
    const std::string text = yaml_text_of(source);
    if (geometry3::parse_shape_dimension(text, name) == 3)
      return py::cast(std::make_shared<Shape3>(
          geometry3::parse_shape3(text, name, ov, base_dir ? path_of(*base_dir) : ".")));
    return py::cast(std::make_shared<Shape>(geometry::parse_shape(text, name, ov)));
  }
  const std::string path = path_of(source);
  if (geometry3::shape_dimension(path) == 3) return py::cast(std::make_shared<Shape3>(geometry3::load_shape3(path, ov)));
  return py::cast(std::make_shared<Shape>(geometry::load_shape(path, ov)));
}

std::shared_ptr<Scene> load_scene(const py::object& source, std::optional<std::size_t> particles,
                                  std::optional<double> time, std::optional<double> omega,
                                  std::optional<std::vector<double>> record, std::optional<std::uint64_t> seed,
                                  const std::optional<py::dict>& set, const std::optional<py::object>& base_dir,
                                  const std::string& name) {
  dynamics::SceneOverrides ov;
  ov.set = overrides_of(set);
  ov.particles = particles;
  ov.time = time;
  ov.omega = omega;
  ov.record = std::move(record);
  ov.seed = seed;
  if (py::isinstance<py::dict>(source)) {
    const std::string base = base_dir ? path_of(*base_dir) : ".";
    return std::make_shared<Scene>(dynamics::parse_scene(yaml_text_of(source), name, base, ov));
  }
  return std::make_shared<Scene>(dynamics::load_scene(path_of(source), ov));
}

/// The keys of `billiard info --json` (geometry::shape_info or geometry3::shape_info), with the
/// tensor and the box as arrays (the JSON's shortest round-trip doubles: the same numbers).
template <class S>
py::dict info(const S& shape) {
  py::dict d = to_python(shape_info(shape));
  const auto array = py::module_::import("numpy").attr("array");
  d["boundary_tensor"] = array(d["boundary_tensor"], "dtype"_a = "float64");
  d["bbox"] = array(d["bbox"], "dtype"_a = "float64");
  d["description"] = shape.description;
  return d;
}

py::dict info_of(const py::object& shape) {
  if (py::isinstance<Shape3>(shape)) return info(shape.cast<const Shape3&>());
  return info(shape.cast<const Shape&>());
}

/// A convex face's corners: clipping leaves a corner where more than three planes meet once per
/// plane, and those repeats would make triangles of zero area.
std::vector<geometry3::Vec3> corners_of(const std::vector<geometry3::Vec3>& face) {
  std::vector<geometry3::Vec3> out;
  for (const auto& v : face)
    if (out.empty() || v != out.back()) out.push_back(v);
  while (out.size() > 1 && out.back() == out.front()) out.pop_back();
  return out;
}

/// The flat walls of a 3-D shape for drawing: vertices (n, 3) and triangles (m, 3) of vertex
/// indices, counter-clockwise seen from outside (a mesh's own; a polyhedron's faces fanned from
/// their first corner, each face with its own vertices; none for a sphere).
py::tuple mesh_of(const Shape3& shape) {
  using namespace geometry3;
  std::vector<double> xyz;
  std::vector<int> triangles;
  const auto add_vertex = [&](const Vec3& p) { xyz.insert(xyz.end(), {p.x(), p.y(), p.z()}); };
  if (const auto* p = std::get_if<ConvexPolyhedron>(&shape.region.outer)) {
    for (const auto& face : p->faces) {
      const int first = int(xyz.size() / 3);
      const auto corners = corners_of(face);
      for (const auto& v : corners) add_vertex(v);
      for (int k = 1; k + 1 < int(corners.size()); ++k)
        triangles.insert(triangles.end(), {first, first + k, first + k + 1});
    }
  } else if (const auto* m = std::get_if<TriangleMesh>(&shape.region.outer)) {
    for (const auto& v : m->vertices) add_vertex(v);
    for (const auto& t : m->triangles) triangles.insert(triangles.end(), t.begin(), t.end());
  }
  const auto n = py::ssize_t(xyz.size() / 3), k = py::ssize_t(triangles.size() / 3);
  return py::make_tuple(adopt(std::move(xyz), {n, 3}), adopt(std::move(triangles), {k, 3}));
}

/// The spherical walls of a 3-D shape: the outer sphere (outer = True) and the balls.
py::list spheres_of(const Shape3& shape) {
  py::list out;
  const auto add = [&](const geometry3::Ball& b, bool outer) {
    out.append(py::dict("center"_a = adopt(std::vector<double>{b.center.x(), b.center.y(), b.center.z()}, {3}),
                        "radius"_a = b.radius, "outer"_a = outer));
  };
  if (const auto* b = std::get_if<geometry3::Ball>(&shape.region.outer)) add(*b, true);
  for (const auto& b : shape.region.holes) add(b, false);
  return out;
}

py::dict force_of(const Scene& scene) {
  const auto& f = scene.force;
  return py::dict("kind"_a = f.name(), "amplitude"_a = vector_array(f.amplitude), "omega"_a = f.omega,
                  "phase"_a = f.phase);
}

// --- theory --------------------------------------------------------------------------------

py::object coefficients_of_scene(const Scene& scene) {
  const auto c = analysis::prediction_of(scene);
  if (!c)
    throw InputError(scene.file, 0,
                     "the theory's coefficients need a periodic force and a microcanonical initial energy");
  return to_python(nlohmann::json(*c));
}

/// For a Shape or a Shape3 (measures_of of its region's dimension).
template <class S>
py::object coefficients_of_shape(const S& shape, const std::vector<double>& F, double omega, double E, double mass) {
  const auto m = measures_of(shape.region);
  if (F.size() != std::size_t(m.dimension)) throw py::value_error(fmt::format("F must have {} components", m.dimension));
  if (!(omega > 0) || !(E > 0) || !(mass > 0)) throw py::value_error("omega, E and mass must be positive");
  analysis::Drive drive;
  drive.F = Eigen::Map<const Eigen::VectorXd>(F.data(), Eigen::Index(F.size()));
  drive.omega = omega;
  drive.mass = mass;
  return to_python(nlohmann::json(analysis::coefficients(m, drive, E)));
}

py::tuple fokker_planck_numerical(const std::vector<double>& s, double E0, int dimension, int cells, int steps) {
  if (cells < 10 || steps < 1) throw py::value_error("need cells >= 10 and steps >= 1");
  analysis::FokkerPlanckSolution sol;
  {
    py::gil_scoped_release unlocked;
    sol = analysis::solve_fokker_planck(s, E0, dimension, cells, steps);
  }
  const std::size_t n = sol.grid.cells();
  std::vector<double> centers(n), eta;
  eta.reserve(s.size() * n);
  for (std::size_t i = 0; i < n; ++i) centers[i] = sol.grid.center(i);
  for (const auto& row : sol.eta) eta.insert(eta.end(), row.begin(), row.end());
  return py::make_tuple(adopt(std::move(centers), {py::ssize_t(n)}),
                        adopt(std::move(eta), {py::ssize_t(s.size()), py::ssize_t(n)}),
                        adopt(std::move(sol.grid.edges), {py::ssize_t(n + 1)}));
}

// --- dynamics ------------------------------------------------------------------------------

/// Runs particles [0, n) in chunks of about a quarter of a second, so that between chunks Ctrl-C
/// raises KeyboardInterrupt and progress(done, n) is called.  The chunks do not change the
/// numbers: each particle has its own random stream and its own arithmetic.
template <class Flight>
void run_in_chunks(const Scene& scene, const Flight& flight, bool verify, int threads,
                   dynamics::EnsembleResult& result, const py::object& progress) {
  const auto table = dynamics::table_of<Flight>(scene);
  auto opt = dynamics::run_options<Flight>(scene, verify);
  // A single particle may run for minutes: Ctrl-C is checked within the chunks too.
  opt.keep_going = [] {
    py::gil_scoped_acquire locked;
    return PyErr_CheckSignals() == 0;
  };
  const auto initial = dynamics::initial_states(scene, table, flight);
  const std::size_t n = scene.particles;
  std::size_t chunk = 16 * std::size_t(threads);
  for (std::size_t first = 0; first < n;) {
    const std::size_t last = std::min(n, first + chunk);
    const auto start = std::chrono::steady_clock::now();
    {
      py::gil_scoped_release unlocked;
      dynamics::run_particles(table, flight, initial, opt, first, last, threads, result);
    }
    if (PyErr_Occurred()) throw py::error_already_set();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    first = last;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!progress.is_none()) progress(first, n);
    if (seconds < 0.1) chunk *= 2;
    else if (seconds > 0.4) chunk = std::max(std::size_t(threads), chunk / 2);
  }
}

py::dict run(const std::shared_ptr<Scene>& scene_ptr, int threads, bool verify, const py::object& progress) {
  const Scene& scene = *scene_ptr;
  if (threads <= 0) threads = omp_get_max_threads();
  const std::size_t n = scene.particles, m = scene.record_times.size();
  dynamics::EnsembleResult result;
  result.energies.resize(n * m);
  result.logs.resize(n);
  const auto start = std::chrono::steady_clock::now();
  dynamics::with_flight(scene, [&](const auto& flight) { run_in_chunks(scene, flight, verify, threads, result, progress); });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double collisions = double(result.collisions());
  // collisions and escaped are strided views into the particle logs, which one capsule owns.
  auto* logs = new std::vector<dynamics::ParticleLog>(std::move(result.logs));
  const py::capsule free_logs(logs, [](void* p) { delete static_cast<std::vector<dynamics::ParticleLog>*>(p); });
  const auto stride = py::ssize_t(sizeof(dynamics::ParticleLog));
  py::array_t<std::uint64_t> counts({py::ssize_t(n)}, {stride}, &(*logs)[0].collisions, free_logs);
  py::array_t<bool> escaped({py::ssize_t(n)}, {stride}, &(*logs)[0].escaped, free_logs);
  const auto prediction = analysis::prediction_of(scene);
  return py::dict("record_times"_a = adopt(std::vector<double>(scene.record_times), {py::ssize_t(m)}),
                  "energies"_a = adopt(std::move(result.energies), {py::ssize_t(n), py::ssize_t(m)}),
                  "collisions"_a = counts, "escaped"_a = escaped, "seconds"_a = seconds,
                  "collisions_per_second"_a = collisions / seconds, "threads"_a = threads,
                  "prediction"_a = prediction ? to_python(nlohmann::json(*prediction)) : py::none());
}

/// Raised inside a run with the GIL released when Python has an error to raise (Ctrl-C, or an
/// exception in a callback): the error indicator is set, and the caller raises it with the GIL.
struct PythonErrorPending {};

/// Runs `f` with the GIL held from code that released it; a Python error it raises is kept in
/// the error indicator and becomes PythonErrorPending.
template <class F>
void with_gil(F&& f) {
  py::gil_scoped_acquire locked;
  try {
    f();
  } catch (py::error_already_set& e) {
    e.restore();
    throw PythonErrorPending{};
  }
}

/// Lets a long run with the GIL released answer Ctrl-C and show progress: about every tenth of
/// a second it takes the GIL, checks for signals and calls progress(collisions, t).
class Heartbeat {
 public:
  explicit Heartbeat(py::object progress) : progress_(std::move(progress)) {}
  void operator()(std::size_t collisions, double t) {
    if (++calls_ % 1024 != 0) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    with_gil([&] {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (!progress_.is_none()) progress_(collisions, t);
    });
  }

 private:
  py::object progress_;
  std::size_t calls_ = 0;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

/// A trajectory's rows as they come: the start and the state just after each bounce (times,
/// positions, velocities, walls; the start has wall −1), and the samples between bounces (times,
/// positions, velocities, energies).
struct TrajectoryRows {
  TrajectoryRows(py::ssize_t d, bool sampled) : d(d), sampled(sampled) {}
  py::ssize_t d;
  bool sampled;
  std::vector<double> t, x, v, st, sx, sv, se;
  std::vector<int> walls;

  template <class State>
  void add_bounce(const State& s, int wall) {
    add(t, x, v, s);
    walls.push_back(wall);
  }
  template <class State>
  void add_sample(const State& s, double energy) {
    add(st, sx, sv, s);
    se.push_back(energy);
  }
  template <class State>
  static void add(std::vector<double>& times, std::vector<double>& xs, std::vector<double>& vs, const State& s) {
    times.push_back(s.t);
    xs.insert(xs.end(), s.x.data(), s.x.data() + s.x.size());
    vs.insert(vs.end(), s.v.data(), s.v.data() + s.v.size());
  }
  std::size_t rows() const { return std::max(t.size(), st.size()); }
  /// The rows as numpy arrays (samples: None when not sampled); the rows are emptied.
  py::dict take() {
    const auto n = py::ssize_t(t.size()), m = py::ssize_t(st.size());
    py::object samples = py::none();
    if (sampled)
      samples = py::dict("times"_a = adopt(std::exchange(st, {}), {m}), "positions"_a = adopt(std::exchange(sx, {}), {m, d}),
                         "velocities"_a = adopt(std::exchange(sv, {}), {m, d}), "energies"_a = adopt(std::exchange(se, {}), {m}));
    return py::dict("times"_a = adopt(std::exchange(t, {}), {n}), "positions"_a = adopt(std::exchange(x, {}), {n, d}),
                    "velocities"_a = adopt(std::exchange(v, {}), {n, d}), "walls"_a = adopt(std::exchange(walls, {}), {n}),
                    "samples"_a = samples);
  }
};

/// How far to follow a trajectory and what to do with its rows.
struct TraceOptions {
  dynamics::FollowLimits limits;
  double dt = 0;                 // sample spacing (0: bounces only)
  double mass = 1;
  py::object on_chunk;           // None: collect every row and return them
  std::size_t chunk = 65536;
  py::object progress;
};

/// Follows the particle from `s` (dynamics::follow) with the GIL released.  Collecting: a dict of
/// the rows, `escaped` and `trapped`.  Streaming (on_chunk): on_chunk(rows) with at most `chunk`
/// rows at a time, none kept, and a dict of `collisions`, `escaped` and `trapped`.
template <class Table, class Flight>
py::dict trace(const Table& table, const Flight& flight, typename Flight::State s, const TraceOptions& opt) {
  if (!(opt.dt >= 0) || !std::isfinite(opt.dt)) throw py::value_error("dt must be a finite number >= 0");
  if (opt.chunk == 0) throw py::value_error("chunk must be positive");
  const bool streaming = !opt.on_chunk.is_none();
  TrajectoryRows rows(py::ssize_t(s.x.size()), opt.dt > 0);
  rows.add_bounce(s, -1);
  const auto flush = [&](bool last) {
    if (!streaming || (!last && rows.rows() < opt.chunk)) return;
    with_gil([&] { opt.on_chunk(rows.take()); });
  };
  Heartbeat heartbeat(opt.progress);
  dynamics::FollowResult made;
  try {
    py::gil_scoped_release unlocked;
    const auto on_bounce = [&](const auto& hit, const auto& after) {
      // 2-D: the wall's position in the shape file (pieces counted loop by loop).
      rows.add_bounce(after, table.piece_of(hit.wall));
      flush(false);
      heartbeat(rows.t.size(), after.t);
    };
    const auto on_sample = [&](const auto& state) {
      rows.add_sample(state, dynamics::energy_of(flight, state, opt.mass));
      flush(false);
      heartbeat(rows.t.size(), state.t);
    };
    made = dynamics::follow(table, flight, s, opt.limits, dynamics::SampleClock{s.t, opt.dt}, on_bounce, on_sample);
    flush(true);
  } catch (const PythonErrorPending&) {
    throw py::error_already_set();
  }
  if (streaming) return py::dict("collisions"_a = made.collisions, "escaped"_a = made.escaped, "trapped"_a = made.trapped);
  auto out = rows.take();
  out["escaped"] = made.escaped;
  out["trapped"] = made.trapped;
  return out;
}

TraceOptions trace_options(std::size_t collisions, double dt, double time, double mass, py::object on_chunk,
                           std::size_t chunk, py::object progress) {
  return {{.collisions = collisions, .t_end = time}, dt, mass, std::move(on_chunk), chunk, std::move(progress)};
}

py::dict scene_trajectory(const Scene& scene, std::size_t collisions, std::size_t particle, double dt, double time,
                          py::object on_chunk, std::size_t chunk, py::object progress) {
  if (particle >= scene.particles) throw py::index_error("particle index beyond the scene's particles");
  if (!std::isfinite(time) && scene.magnetic() && scene.force.kind != dynamics::Force::Kind::none)
    throw py::value_error("a magnetic field with a force is followed to a time: give time=");
  const auto opt = trace_options(collisions, dt, time, scene.mass, std::move(on_chunk), chunk, std::move(progress));
  return dynamics::with_flight(scene, [&](const auto& flight) {
    const auto table = dynamics::table_of<std::decay_t<decltype(flight)>>(scene);
    return trace(table, flight, dynamics::initial_states(scene, table, flight)(particle), opt);
  });
}

/// A free trajectory in a Shape (Flight = FreeFlight) or a Shape3 (FreeFlight3).
template <class Flight, class S>
py::dict shape_trajectory(const S& shape, std::size_t collisions, std::uint64_t seed, std::size_t particle,
                          double speed, double dt, double time, py::object on_chunk, std::size_t chunk,
                          py::object progress) {
  if (!(speed > 0)) throw py::value_error("speed must be positive");
  const dynamics::TableFor<Flight> table(shape.region);
  dynamics::ParticleRng rng(seed, particle);
  return trace(table, Flight{}, sample_microcanonical(table, speed, rng),
               trace_options(collisions, dt, time, 1.0, std::move(on_chunk), chunk, std::move(progress)));
}

/// The frames of an animation (dynamics::fill_frames), computed in chunks of particles so that
/// Ctrl-C raises KeyboardInterrupt between them: times (K,), positions (K, N, d), energies (K, N),
/// escaped (N,), and the Fokker–Planck density at each frame time after the first when the
/// theory covers the scene (fp_energies (cells,), fp_density (K − 1, cells)), else None.
py::dict scene_frames(const Scene& scene, std::size_t particles, std::size_t frames, double time, int threads,
                      const py::object& progress) {
  if (particles == 0 || particles > scene.particles)
    throw py::value_error(fmt::format("particles must be from 1 to the scene's {}", scene.particles));
  if (threads <= 0) threads = omp_get_max_threads();
  dynamics::SceneFrames f;
  try {
    f = dynamics::empty_frames(scene, particles, frames, time);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  for (std::size_t first = 0; first < particles;) {
    const std::size_t last = std::min(particles, first + 4 * std::size_t(threads));
    {
      py::gil_scoped_release unlocked;
      dynamics::fill_frames(scene, f, first, last, threads);
    }
    first = last;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!progress.is_none()) progress(first, particles);
  }
  const auto K = py::ssize_t(frames), N = py::ssize_t(particles), d = py::ssize_t(f.dimension);
  const std::vector<double> scene_times = f.times;
  py::dict out("times"_a = adopt(std::move(f.times), {K}), "positions"_a = adopt(std::move(f.positions), {K, N, d}),
               "energies"_a = adopt(std::move(f.energies), {K, N}), "escaped"_a = adopt(std::move(f.escaped), {N}),
               "fp_energies"_a = py::none(), "fp_density"_a = py::none());
  const std::vector<double> later(scene_times.begin() + 1, scene_times.end());
  if (const auto fp = analysis::fokker_planck_of(scene, later, 400)) {
    std::vector<double> centers, density;
    for (std::size_t i = 0; i < fp->grid.cells(); ++i) centers.push_back(fp->grid.center(i));
    for (const auto& row : fp->eta) density.insert(density.end(), row.begin(), row.end());
    const auto cells = py::ssize_t(centers.size());
    out["fp_energies"] = adopt(std::move(centers), {cells});
    out["fp_density"] = adopt(std::move(density), {K - 1, cells});
  }
  return out;
}

/// What Shape and Shape3 have in common.
template <class S>
void def_shape_properties(py::class_<S, std::shared_ptr<S>>& c, int dimension, const char* type) {
  c.def_property_readonly("name", [](const S& s) { return s.region.name; })
      .def_property_readonly("file", [](const S& s) { return s.region.origin.file; })
      .def_property_readonly("dimension", [dimension](const S&) { return dimension; })
      .def_property_readonly("description", [](const S& s) { return s.description; },
                             "The leading comment block of the shape file.")
      .def_property_readonly("parameters", [](const S& s) { return s.parameters; },
                             "Parameter values after overrides.")
      .def("info", &info<S>, "Same as billiardkit.info(shape).")
      .def("__repr__", [type](const S& s) { return fmt::format("<billiardkit.{} '{}'>", type, s.region.name); });
}

}  // namespace

}  // namespace billiards::python

PYBIND11_MODULE(_core, m) {
  using namespace billiards;
  using namespace billiards::python;
  m.doc() = "Billiards: exact geometry of 2-D tables and 3-D regions, deterministic ensembles of driven particles, "
            "and the energy-diffusion theory of Hodson & Jarzynski (the library behind the `billiard` program).";
  m.attr("__version__") = billiards::version;
  def_phase_space(m);
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  m.def("sample_moments", [](const std::vector<double>& x) {
          const auto mo = analysis::sample_moments(x);
          return py::make_tuple(mo.mean, mo.variance, mo.se_mean, mo.se_variance);
        }, "x"_a, "(mean, unbiased variance, their standard errors) of a sample, as `billiard run` computes them.");

  // dynamic_attr: billiardkit.load_shape notes where a shape came from, for Scene(shape, ...).
  py::class_<Shape, std::shared_ptr<Shape>> shape2_class(m, "Shape", py::dynamic_attr(), "A validated 2-D table (see load_shape).");
  def_shape_properties(shape2_class, 2, "Shape");
  shape2_class.def("outline", [](const Shape& s, double arc_step) {
             py::list loops;
             for (const auto* loop : s.region.loops()) {
               const auto pts = geometry::outline_of(*loop, arc_step);
               std::vector<double> xy;
               for (const auto& p : pts) xy.insert(xy.end(), {p.x(), p.y()});
               loops.append(adopt(std::move(xy), {py::ssize_t(pts.size()), 2}));
             }
             return loops;
           }, py::kw_only(), "arc_step"_a = geometry::pi / 360,
           "The boundary for drawing: a closed polyline (n, 2) per loop, outer first (the vertices of "
           "`billiard plot`; arcs get one every arc_step radians).");

  py::class_<Shape3, std::shared_ptr<Shape3>> shape3_class(
      m, "Shape3", py::dynamic_attr(), "A validated 3-D region: a polyhedron, a triangle mesh or a sphere, minus balls (see load_shape).");
  def_shape_properties(shape3_class, 3, "Shape3");
  shape3_class.def("mesh", &mesh_of,
             R"(The flat walls for drawing: (vertices (n, 3), triangles (m, 3) of vertex indices, counter-clockwise
seen from outside).  A mesh's own triangles; a polyhedron's faces fanned into triangles (each face
with its own vertices); empty arrays for a sphere.)")
      .def("spheres", &spheres_of,
           "The spherical walls: a list of {center (3,), radius, outer}; outer is True for the sphere the region "
           "is inside, False for a ball (a hole).");

  py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", "A shape, a force, particles and what to run (see load_scene).")
      .def(py::init(&load_scene), "source"_a, py::kw_only(), "particles"_a = py::none(), "time"_a = py::none(),
           "omega"_a = py::none(), "record"_a = py::none(), "seed"_a = py::none(), "set"_a = py::none(),
           "base_dir"_a = py::none(), "name"_a = "scene dict", "Same as load_scene(source, ...).")
      .def_property_readonly("file", [](const Scene& s) { return s.file; })
      .def_property_readonly("text", [](const Scene& s) { return s.text; }, "The scene's YAML text.")
      .def_property_readonly("dimension", [](const Scene& s) { return s.dimension(); })
      .def_property_readonly("shape", [](const std::shared_ptr<Scene>& s) {
        // Views into the scene (it stays alive with them): a large mesh is not copied.
        if (s->dimension() == 3) return py::cast(std::shared_ptr<Shape3>(s, &s->shape<3>()));
        return py::cast(std::shared_ptr<Shape>(s, &s->shape<2>()));
      }, "The scene's Shape (2-D) or Shape3 (3-D).")
      .def_property_readonly("mass", [](const Scene& s) { return s.mass; })
      .def_property_readonly("energy", [](const Scene& s) { return s.energy; },
                             "Initial energy of the microcanonical ensemble (0 with an initial-condition file).")
      .def_property_readonly("particles", [](const Scene& s) { return s.particles; })
      .def_property_readonly("time", [](const Scene& s) { return s.time; }, "End time of the run.")
      .def_property_readonly("record_times", [](const Scene& s) {
        return adopt(std::vector<double>(s.record_times), {py::ssize_t(s.record_times.size())});
      })
      .def_property_readonly("seed", [](const Scene& s) { return s.seed; })
      .def_property_readonly("force", &force_of, "dict: kind (none, constant, periodic), amplitude, omega, phase.")
      .def_property_readonly("output_dir", [](const Scene& s) { return s.output_dir; })
      .def("__repr__", [](const Scene& s) {
        return fmt::format("<billiardkit.Scene '{}': {} particles on '{}', force {}, t = 0 .. {}>", s.file, s.particles,
                           s.shape_name(), s.force.name(), s.time);
      });

  m.def("load_shape", &load_shape, "source"_a, py::kw_only(), "set"_a = py::none(), "base_dir"_a = py::none(),
        "name"_a = "shape dict",
        R"(Reads and validates a shape: a Shape (2-D), or a Shape3 when the file or dict has `dimension: 3`.

source: a shape file's path, or a dict with the file's keys ({"boundary": {"circle": ...}, ...}).
set: parameter overrides {NAME: value or expression}, like `--set NAME=VALUE`.
base_dir: the folder a dict's `mesh:` file is relative to (default: the current directory).
name: stands for the file in error messages when source is a dict.
Raises billiardkit.InputError (a ValueError) naming file, line and problem.)");

  m.def("load_scene", &load_scene, "source"_a, py::kw_only(), "particles"_a = py::none(), "time"_a = py::none(),
        "omega"_a = py::none(), "record"_a = py::none(), "seed"_a = py::none(), "set"_a = py::none(),
        "base_dir"_a = py::none(), "name"_a = "scene dict",
        R"(Reads a scene: its shape, force, particles and record times.

source: a scene file's path, or a dict with the file's keys; a dict's `shape` path (and `initial.csv`)
is relative to base_dir (default: the current directory).
particles, time, omega, record, seed, set: the overrides of `billiard run` (--particles, ...; record
times get 0 and the end time added).
Raises billiardkit.InputError naming file, line and problem.)");

  m.def("info", [](const py::object& shape, const std::optional<py::dict>& set, const std::optional<py::object>& base_dir) {
          if (py::isinstance<Shape>(shape) || py::isinstance<Shape3>(shape)) return info_of(shape);
          return info_of(load_shape(shape, set, base_dir, "shape dict"));
        }, "shape"_a, py::kw_only(), "set"_a = py::none(), "base_dir"_a = py::none(),
        R"(Exact geometry of a shape (a Shape, a Shape3, a path or a dict): the keys of `billiard info --json`
(V, S, mean_free_path, boundary_tensor as a d x d array, bbox as a 2 x d array, and pieces in 2-D or
boundary in 3-D, ...) plus description.)");

  m.def("coefficients", &coefficients_of_scene, "scene"_a,
        R"(The theory's prediction for a driven scene at its initial energy: the keys of
`billiard coeffs --json` (mean_free_path, wall_integral, C, g1, g2, validity ratios, warnings, ...).)");
  m.def("coefficients", &coefficients_of_shape<Shape>, "shape"_a, py::kw_only(), "F"_a, "omega"_a, "E"_a,
        "mass"_a = 1.0, "The same for a shape under the drive F cos(omega t) at energy E (F of the shape's dimension).");
  m.def("coefficients", &coefficients_of_shape<Shape3>, "shape"_a, py::kw_only(), "F"_a, "omega"_a, "E"_a,
        "mass"_a = 1.0, "The same for a 3-D shape (F has 3 components; the formulas in d = 3).");

  m.def("fokker_planck_eta", py::vectorize(&analysis::fokker_planck_eta), "E"_a, "s"_a, "E0"_a, "dimension"_a = 2,
        R"(The analytic Fokker-Planck density eta(E, s) from delta(E - E0), s = C t (the paper's eq. B4);
broadcasts over arrays.)");
  m.def("fokker_planck_cdf", py::vectorize(&analysis::fokker_planck_cdf), "E"_a, "s"_a, "E0"_a, "dimension"_a = 2,
        "Its exact cumulative distribution (noncentral chi-squared); broadcasts over arrays.");
  m.def("fokker_planck_moments", [](double s, double E0, int dimension) {
          const auto mo = analysis::fokker_planck_exact_moments(s, E0, dimension);
          return py::dict("mean"_a = mo.mean, "variance"_a = mo.variance, "mean_root"_a = mo.mean_root);
        }, "s"_a, "E0"_a, "dimension"_a = 2, "Exact mean, variance of E and mean of sqrt(E) at s = C t.");
  m.def("fokker_planck_numerical", &fokker_planck_numerical, "s"_a, "E0"_a, "dimension"_a = 2, py::kw_only(),
        "cells"_a = 4000, "steps"_a = 2000,
        R"(The Fokker-Planck equation solved numerically (finite volumes, Chang-Cooper fluxes, implicit
Euler), as `billiard fp`: returns (E, eta, edges): the cell centres (cells,), the cell averages
(len(s), cells) at each s = C t (positive, increasing), and the cell edges (cells + 1,).)");

  m.def("run", &run, "scene"_a, py::kw_only(), "threads"_a = 0, "verify"_a = false, "progress"_a = py::none(),
        R"(Runs the scene's ensemble, as `billiard run` does (same numbers for the same scene and seed,
and for any number of threads), with the GIL released.  billiardkit.run wraps this in a RunResult.

threads: OpenMP threads (0: all cores).  verify: also check the midpoint of every free flight.
progress: called as progress(done, particles) about every quarter second; Ctrl-C raises
KeyboardInterrupt there.
Returns a dict: record_times (m,), energies (N, m) (NaN after an escape), collisions (N,),
escaped (N,), seconds, collisions_per_second, threads, prediction (coefficients or None).
The arrays own the C++ buffers: nothing is copied.)");

  m.def("trajectory", &scene_trajectory, "scene"_a, py::kw_only(), "collisions"_a = 100, "particle"_a = 0,
        "dt"_a = 0.0, "time"_a = dynamics::never, "on_chunk"_a = py::none(), "chunk"_a = 65536,
        "progress"_a = py::none(),
        R"(One particle of the scene's ensemble (its initial state is the one `run` gives it), bounce by
bounce, up to `collisions` bounces or the time `time`, whichever comes first: a dict with times
(K+1,), positions (K+1, d), velocities (K+1, d) just after each bounce, walls (K+1,) (the start has
-1), escaped, and samples: with dt > 0, the state at t0, t0 + dt, ... between the bounces along the
flight's true path (times, positions, velocities, energies), else None.
on_chunk: streams instead: on_chunk(rows) with a dict of the same keys for at most `chunk` rows at a
time (the rows are not kept), and returns {collisions, escaped}.
progress: called as progress(collisions, t) about every tenth of a second; Ctrl-C raises
KeyboardInterrupt there.)");
  m.def("trajectory", &shape_trajectory<dynamics::FreeFlight, Shape>, "shape"_a, py::kw_only(), "collisions"_a = 100,
        "seed"_a = 1, "particle"_a = 0, "speed"_a = 1.0, "dt"_a = 0.0, "time"_a = dynamics::never,
        "on_chunk"_a = py::none(), "chunk"_a = 65536, "progress"_a = py::none(),
        "A free trajectory in a shape from a uniform random start (for particle 0, the one `billiard plot --trajectory` "
        "draws).");
  m.def("trajectory", &shape_trajectory<dynamics::FreeFlight3, Shape3>, "shape"_a, py::kw_only(),
        "collisions"_a = 100, "seed"_a = 1, "particle"_a = 0, "speed"_a = 1.0, "dt"_a = 0.0,
        "time"_a = dynamics::never, "on_chunk"_a = py::none(), "chunk"_a = 65536, "progress"_a = py::none(),
        "The same in a 3-D shape: positions and velocities are (K+1, 3).");
  m.def("frames", &scene_frames, "scene"_a, py::kw_only(), "particles"_a, "frames"_a, "time"_a, "threads"_a = 0,
        "progress"_a = py::none(),
        R"(The first `particles` particles of the scene at `frames` uniform times from 0 to `time`, as
`billiard animate` draws them: times (K,), positions (K, N, d), energies (K, N) (NaN after an escape),
escaped (N,), and fp_energies (cells,), fp_density (K-1, cells): the Fokker-Planck density at each
frame time after the first, or None where the theory does not cover the scene.  Ctrl-C raises
KeyboardInterrupt between chunks of particles; progress(done, particles) is called after each.)");
}
