// billiardkit's phase-space functions: boundary_map, lyapunov, chaos and escape, on a Shape or a
// Shape3 (free flights at speed 1) or a Scene (its force, energy and seed), with the numbers of
// `billiard bmap`, `billiard lyapunov`, `billiard chaos` and `billiard escape`; like the CLI,
// boundary_map gives a 3-D table's plane sections only (no Birkhoff coordinates on a surface).
#include "billiards/analysis/boundary_map.hpp"
#include "billiards/analysis/chaos.hpp"
#include "billiards/analysis/escape.hpp"
#include "billiards/analysis/lyapunov.hpp"
#include "billiards/dynamics/scene_run.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/core.h>

#include <memory>
#include <optional>
#include <string>
#include <variant>

namespace py = pybind11;
using namespace pybind11::literals;

namespace billiards::python {

namespace {

using dynamics::Scene;

/// Refuses a magnetic field with a force for a function that follows particles collision by
/// collision without a time horizon (as the CLI's refuse_forced_magnetic).
void refuse_forced_magnetic(const Scene& scene) {
  if (scene.searches_to_a_horizon())
    throw py::value_error("a magnetic field with a force needs a time horizon for its collision search; this "
                          "function follows particles collision by collision (bk.run follows them to its times, "
                          "bk.lyapunov to successive horizons)");
}

/// A Shape or Shape3 as a free scene at speed 1 with `particles` microcanonical particles (as
/// the CLI's load_phase_space_scene), or a Scene with its own (particles overriding its count
/// when given).
Scene scene_of(const py::object& table, std::optional<std::size_t> particles, std::optional<std::uint64_t> seed) {
  Scene scene;
  const bool shape = py::isinstance<geometry::Shape>(table), shape3 = py::isinstance<geometry3::Shape3>(table);
  if (shape || shape3) {
    if (shape3) {
      scene.table = dynamics::SceneTable<3>{table.cast<geometry3::Shape3>(), {}};
      scene.force.amplitude = Eigen::VectorXd::Zero(3);
    } else {
      scene.table = dynamics::SceneTable<2>{table.cast<geometry::Shape>(), {}};
    }
    scene.energy = 0.5;
    scene.particles = particles.value_or(10);
    scene.seed = seed.value_or(1);
    return scene;
  }
  scene = table.cast<Scene>();
  if (particles) {
    const std::size_t given = scene.dimension() == 3 ? scene.initial_states<3>().size() : scene.initial_states<2>().size();
    if (given > 0 && *particles > given)
      throw py::value_error("more particles than the scene's initial-condition file holds");
    scene.particles = *particles;
  }
  if (seed) scene.seed = *seed;
  return scene;
}

py::array_t<double> rows_array(const analysis::SectionRows& r) {
  return py::array_t<double>({py::ssize_t(r.row_count()), py::ssize_t(r.columns)}, r.rows.data());
}

/// The boundary map (2-D), or with `section` the Poincaré section on that line (2-D) or plane
/// (3-D), as `billiard bmap [--section]` computes them.
py::array_t<double> boundary_map(const py::object& table, std::optional<std::size_t> particles, std::size_t collisions,
                                 std::optional<std::uint64_t> seed, int threads, std::optional<std::string> section) {
  const Scene scene = scene_of(table, particles, seed);
  refuse_forced_magnetic(scene);
  if (scene.dimension() == 3 && !section)
    throw py::value_error("a 3-D table has no boundary map (Birkhoff coordinates need a curve): give a plane section, "
                          "such as section=\"z = 0\" (`billiard bmap --section`)");
  std::optional<analysis::SectionLine> line;
  std::optional<analysis::SectionPlane> plane;
  if (section && scene.dimension() == 3) plane = analysis::parse_section<3>(*section, "section");
  else if (section) line = analysis::parse_section<2>(*section, "section");
  analysis::SectionRows rows;
  {
    py::gil_scoped_release unlocked;
    rows = dynamics::with_flight(scene, [&](const auto& flight) -> analysis::SectionRows {
      using Flight = std::decay_t<decltype(flight)>;
      const auto t = dynamics::table_of<Flight>(scene);
      const auto initial = dynamics::initial_states(scene, t, flight);
      if (section) {
        if constexpr (analysis::section_flight<Flight>) {
          if constexpr (dynamics::is_3d<Flight>)
            return analysis::line_section(t, flight, *plane, initial, scene.particles, collisions, threads, scene.mass);
          else
            return analysis::line_section(t, flight, *line, initial, scene.particles, collisions, threads, scene.mass);
        } else {
          throw py::value_error(fmt::format("a section is drawn for {}; not for this scene (force {}{})",
                                            analysis::section_flights_named, scene.force.name(),
                                            scene.magnetic() ? ", magnetic" : ""));
        }
      }
      if constexpr (dynamics::is_3d<Flight>) {
        return {};  // (refused above)
      } else {
        const analysis::BoundaryCoordinates coordinates(scene.shape<2>().region);
        return analysis::boundary_map(t, coordinates, flight, initial, scene.particles, collisions, threads,
                                      scene.mass);
      }
    });
  }
  return rows_array(rows);
}

/// A spectrum's numbers as `billiard lyapunov --json` has them, with per-trajectory arrays.
template <int D>
py::dict spectrum_dict(const analysis::BasicLyapunovSpectrum<D>& r) {
  constexpr int m = 2 * D;
  std::vector<double> per_time(r.trajectories.size() * m), per_collision(per_time.size());
  for (std::size_t i = 0; i < r.trajectories.size(); ++i)
    for (int k = 0; k < m; ++k) {
      per_time[i * m + k] = r.exponent(i, k);
      per_collision[i * m + k] = r.trajectories[i].log_stretch[k] / double(r.trajectories[i].collisions);
    }
  const auto n = py::ssize_t(r.trajectories.size());
  std::vector<double> spectrum, spectrum_se;
  for (const auto& e : r.per_time) spectrum.push_back(e.mean), spectrum_se.push_back(e.se);
  return py::dict("lyapunov"_a = r.per_time[0].mean, "lyapunov_se"_a = r.per_time[0].se,
                  "lyapunov_per_collision"_a = r.per_collision[0].mean,
                  "lyapunov_per_collision_se"_a = r.per_collision[0].se,
                  "spectrum"_a = py::array_t<double>(m, spectrum.data()),
                  "spectrum_se"_a = py::array_t<double>(m, spectrum_se.data()),
                  "per_trajectory"_a = py::array_t<double>({n, py::ssize_t(m)}, per_time.data()),
                  "per_trajectory_per_collision"_a = py::array_t<double>({n, py::ssize_t(m)}, per_collision.data()),
                  "escapes"_a = r.escapes(), "trapped"_a = r.trapped(), "dimension"_a = D);
}

py::dict lyapunov(const py::object& table, std::optional<std::size_t> particles, std::size_t collisions,
                  std::optional<std::uint64_t> seed, int threads) {
  const Scene scene = scene_of(table, particles, seed);
  using AnySpectrum = std::variant<analysis::BasicLyapunovSpectrum<2>, analysis::BasicLyapunovSpectrum<3>>;
  AnySpectrum r;
  {
    py::gil_scoped_release unlocked;
    r = dynamics::with_flight(scene, [&](const auto& flight) -> AnySpectrum {
      using Flight = std::decay_t<decltype(flight)>;
      if constexpr (analysis::tangent_flight<Flight>) {
        const auto t = dynamics::table_of<Flight>(scene);
        return analysis::lyapunov_spectrum(t, flight, dynamics::initial_states(scene, t, flight), scene.particles,
                                           collisions, threads);
      } else {
        throw py::value_error(fmt::format("no tangent dynamics for the force '{}'{}: Lyapunov exponents are "
                                          "computed for {}",
                                          scene.force.name(), scene.potential ? " with a potential" : "",
                                          analysis::tangent_flights_named));
        return analysis::LyapunovSpectrum{};
      }
    });
  }
  return std::visit([](const auto& spectrum) { return spectrum_dict(spectrum); }, r);
}

py::dict chaos(const py::object& shape, std::size_t orbits, std::size_t collisions, std::uint64_t seed,
               int threads) {
  analysis::ChaosOptions o;
  o.orbits = orbits;
  o.collisions = collisions;
  o.seed = seed;
  o.threads = threads;
  const auto* shape3 = py::isinstance<geometry3::Shape3>(shape) ? shape.cast<const geometry3::Shape3*>() : nullptr;
  const auto* shape2 = shape3 ? nullptr : shape.cast<const geometry::Shape*>();
  analysis::ChaosVerdict v;
  {
    py::gil_scoped_release unlocked;
    v = shape3 ? analysis::chaos_of(shape3->region, o) : analysis::chaos_of(shape2->region, o);
  }
  std::vector<double> exponents, distances;
  for (const auto& e : v.orbits) exponents.push_back(e.lyapunov_per_collision), distances.push_back(e.distance);
  return py::dict("ergodic"_a = v.ergodic(), "chaotic"_a = v.chaotic, "uniform"_a = v.uniform,
                  "lyapunov"_a = v.lyapunov.mean, "lyapunov_se"_a = v.lyapunov.se,
                  "pooled_distance"_a = v.pooled_distance, "noise_distance"_a = v.noise_distance,
                  "orbit_exponents_per_collision"_a = py::array_t<double>(py::ssize_t(exponents.size()), exponents.data()),
                  "orbit_distances"_a = py::array_t<double>(py::ssize_t(distances.size()), distances.data()));
}

template <class T>
py::array_t<T> array_of(const std::vector<T>& v) {
  return py::array_t<T>(py::ssize_t(v.size()), v.data());
}

py::dict escape(const py::object& table, std::optional<std::size_t> particles, std::size_t collisions,
                std::optional<std::uint64_t> seed, bool entering, int threads) {
  Scene scene = scene_of(table, particles, seed);
  refuse_forced_magnetic(scene);
  if (entering) scene.through_exit = geometry::SourceRef{"entering=True", 0};
  // The exits of the table's dimension: arcs of the boundary (2-D, total length) or discs on
  // faces (3-D, total area), as `billiard escape` reads them.
  std::optional<analysis::BoundaryCoordinates> coordinates;
  std::optional<analysis::Exits> exits;
  std::optional<analysis::Exits3> exits3;
  if (scene.dimension() == 3) {
    exits3.emplace(analysis::read_exits3(scene.shape<3>()));
  } else {
    coordinates.emplace(scene.shape<2>().region);
    exits.emplace(*coordinates, analysis::read_exits(scene.shape<2>(), *coordinates));
  }
  if (exits3 ? exits3->empty() : exits->empty()) throw py::value_error("the shape lists no exits: nothing can escape");
  const double exit_measure = exits3 ? exits3->area() : exits->length();
  std::vector<analysis::EscapeRecord> records;
  {
    py::gil_scoped_release unlocked;
    records = dynamics::with_flight(scene, [&](const auto& flight) {
      using Flight = std::decay_t<decltype(flight)>;
      const auto t = dynamics::table_of<Flight>(scene);
      if constexpr (dynamics::is_3d<Flight>) {
        const auto enter = [&](double speed, auto& rng) { return exits3->entering_state(speed, rng); };
        return analysis::escape_times(t, flight, analysis::open_table_initial_states(scene, t, flight, enter),
                                      [&](const auto& hit) { return exits3->contains(hit.wall, hit.point); },
                                      scene.particles, collisions, threads);
      } else {
        return analysis::escape_times(t, *coordinates, *exits, flight,
                                      analysis::open_table_initial_states(scene, t, flight, *coordinates, *exits),
                                      scene.particles, collisions, threads);
      }
    });
  }
  const auto summary = analysis::summarize(records);
  if (summary.lost > 0) throw std::runtime_error(fmt::format("{} particle(s) escaped the region through a wall", summary.lost));
  std::vector<double> times;
  std::vector<std::uint64_t> counts;
  std::vector<bool> escaped;
  for (const auto& r : records) times.push_back(r.time), counts.push_back(r.collisions), escaped.push_back(r.escaped);
  const auto P = analysis::survival(summary.times, scene.particles);
  const double speed = std::sqrt(2 * scene.energy / scene.mass), V = scene.measures().volume;
  return py::dict("escape_times"_a = array_of(times), "collisions"_a = array_of(counts),
                  "escaped"_a = py::array(py::cast(escaped)).attr("astype")("bool"),
                  "mean_escape_time"_a = summary.mean, "mean_escape_time_se"_a = summary.se,
                  "exit_length"_a = exit_measure,
                  "kac_mean_escape_time"_a = analysis::kac_mean_escape_time(V, exit_measure, speed, scene.dimension()),
                  "survival_t"_a = array_of(P.t), "survival_P"_a = array_of(P.P),
                  "still_inside"_a = summary.still_inside(scene.particles), "speed"_a = speed,
                  "ensemble"_a = scene.through_exit ? "through_exit" : "microcanonical", "dimension"_a = scene.dimension());
}

}  // namespace

void def_phase_space(py::module_& m) {
  m.def("boundary_map", &boundary_map, "table"_a, py::kw_only(), "particles"_a = py::none(), "collisions"_a = 1000,
        "seed"_a = py::none(), "threads"_a = 0, "section"_a = py::none(),
        R"(The boundary map of a Shape (free, speed 1) or a 2-D Scene: an array (particles x collisions, 6) with
columns particle, collision, s, p, t, energy -- `billiard bmap`'s bmap.npy (docs/phase-space.md).  With
section="y = 0" (a line; in 3-D a plane, "z = 0", of a Shape3 or a 3-D Scene) the Poincare section instead:
rows particle, crossing, u, p, t, energy (3-D: particle, crossing, u1, u2, p1, p2, t, energy), `billiard bmap
--section`'s section.npy or section3.npy.)");
  m.def("lyapunov", &lyapunov, "table"_a, py::kw_only(), "particles"_a = py::none(), "collisions"_a = 20000,
        "seed"_a = py::none(), "threads"_a = 0,
        "Lyapunov exponents from tangent dynamics: `billiard lyapunov --json`'s keys, and per_trajectory arrays.");
  m.def("chaos", &chaos, "shape"_a, py::kw_only(), "orbits"_a = 12, "collisions"_a = 50000, "seed"_a = 1,
        "threads"_a = 0, "Is the undriven table chaotic and ergodic? `billiard chaos --json`'s main keys.");
  m.def("escape", &escape, "table"_a, py::kw_only(), "particles"_a = py::none(), "collisions"_a = 1000000,
        "seed"_a = py::none(), "entering"_a = false, "threads"_a = 0,
        R"(Escape times through the exits of a Shape or Shape3 (free, speed 1) or a Scene (its ensemble: inside, or
through_exit): arrays escape_times (NaN if still inside), collisions, escaped; mean_escape_time, its se,
exit_length, kac_mean_escape_time and the survival curve survival_t, survival_P -- `billiard escape`'s numbers.)");
}

}  // namespace billiards::python
