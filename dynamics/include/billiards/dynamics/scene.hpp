// Scene files (YAML): a shape, particles, a force and what to run.  The format is documented
// in README.md ("Scene files").
#pragma once

#include "billiards/dynamics/state.hpp"
#include "billiards/geometry/coordinate_function.hpp"
#include "billiards/geometry/expression.hpp"
#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/shape_file.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace billiards::dynamics {

/// The force between collisions: none, a static uniform force F, the uniform periodic drive
/// F cos(ω t + phase) of the paper, or a drive F(x) cos(ω t + phase) whose amplitude depends on
/// the position (`field`).
struct Force {
  enum class Kind { none, constant, periodic, field };
  Kind kind = Kind::none;
  Eigen::VectorXd amplitude = Eigen::VectorXd::Zero(2);  // F (the scene's dimension; uniform kinds)
  std::array<CoordinateFunction, 2> field;  // F(x) (field only, 2-D)
  geometry::SourceRef field_source;          // the scene file's key `field`, for errors
  double omega = 0;               // ω (periodic and field)
  double phase = 0;               // (periodic and field)
  /// periodic only: simulate the equivalent free particle between walls translating by
  /// F cos(ω t + phase)/(mω²) (`picture: quivering-walls`; QuiveringWallFlight).
  bool quivering_walls = false;
  const char* name() const;
};

/// A potential U(x) with its gradient (given in the scene, or its exact derivatives); 2-D.
struct Potential {
  CoordinateFunction U;
  std::array<CoordinateFunction, 2> gradient;
  geometry::SourceRef source;  // the scene file's key `potential`, for errors
};

/// The shape file's type in dimension D.
template <int D>
using ShapeOf = std::conditional_t<D == 3, geometry3::Shape3, geometry::Shape>;

/// A scene's table in dimension D: its shape, and the particles' initial states when they were
/// read from a CSV file (else empty).
template <int D>
struct SceneTable {
  ShapeOf<D> shape;
  std::vector<BasicState<double, D>> initial_states;
};

/// A scene in 2-D or 3-D: its `table` holds the shape (and initial states) of the one dimension
/// the shape file has.
struct Scene {
  std::string file;            // the scene file
  std::string text;            // its text, copied into summary.json
  std::variant<SceneTable<2>, SceneTable<3>> table;
  double mass = 1;
  /// Microcanonical ensemble at `energy`, unless the initial states were read from a CSV file
  /// or the particles enter through the shape's exits.
  double energy = 0;
  /// `initial: {through_exit: {energy: E}}`: the particles enter through the exits the shape
  /// file lists, at energy E, with the boundary measure cos φ ds dφ (analysis/escape.hpp samples
  /// them: the exits are phase-space objects).  Where the scene file says so, for its errors.
  std::optional<geometry::SourceRef> through_exit;
  std::string initial_csv;
  Force force;
  std::optional<Potential> potential;
  /// A uniform magnetic field B, acting on the charge `charge` (in 2-D (0, 0, B), perpendicular
  /// to the plane); none when absent or zero.
  std::optional<Eigen::Vector3d> magnetic_field;
  double charge = 1;
  /// Relative tolerance of the integrator of flights in a general field (field_flight.hpp).
  double integrator_tolerance = 1e-10;
  std::size_t particles = 0;
  double time = 0;                   // end of the run
  std::vector<double> record_times;  // increasing, last = time
  std::uint64_t seed = 1;
  std::string output_dir;

  /// 2 or 3, the shape file's dimension.
  int dimension() const { return table.index() == 0 ? 2 : 3; }
  /// The shape and the initial states in dimension D; std::bad_variant_access when the scene
  /// has the other dimension.
  template <int D>
  const ShapeOf<D>& shape() const { return std::get<SceneTable<D>>(table).shape; }
  template <int D>
  ShapeOf<D>& shape() { return std::get<SceneTable<D>>(table).shape; }
  template <int D>
  const std::vector<BasicState<double, D>>& initial_states() const { return std::get<SceneTable<D>>(table).initial_states; }
  /// fn(shape) with the shape of the scene's dimension.
  template <class Fn>
  decltype(auto) visit_shape(Fn&& fn) const {
    return std::visit([&fn](const auto& t) -> decltype(auto) { return fn(t.shape); }, table);
  }
  const std::string& shape_name() const {
    return visit_shape([](const auto& shape) -> const std::string& { return shape.region.name; });
  }
  const std::map<std::string, double>& shape_parameters() const {
    return visit_shape([](const auto& shape) -> const std::map<std::string, double>& { return shape.parameters; });
  }
  geometry::Measures measures() const;
  /// Is there a magnetic field?  Then Ω = qB/m is its cyclotron vector, and in 2-D its z
  /// component the signed cyclotron frequency.
  bool magnetic() const { return magnetic_field && *magnetic_field != Eigen::Vector3d::Zero(); }
  Eigen::Vector3d cyclotron_vector() const { return charge * *magnetic_field / mass; }
  double cyclotron_frequency() const { return cyclotron_vector().z(); }
  /// Are its flights integrated (FieldFlight: a position-dependent drive or a potential, 2-D)?
  bool integrated() const { return potential || force.kind == Force::Kind::field; }
  /// Does a particle's collision search need a time horizon?  A magnetic flight under a force
  /// may circle away from every wall for ever (its certified scan has no end without one), so
  /// it is followed to a time, not collision by collision.
  bool searches_to_a_horizon() const { return magnetic() && force.kind != Force::Kind::none; }
};

/// Command-line overrides of a scene.
struct SceneOverrides {
  Overrides set;  // --set NAME=VALUE: scene parameters first, then shape parameters
  std::optional<std::size_t> particles;
  std::optional<double> time, omega;
  std::optional<std::vector<double>> record;  // record times (0 and the end are added)
  std::optional<std::uint64_t> seed;
  std::optional<std::string> output_dir;
};

/// Reads a scene and its shape.  Throws InputError naming file and line.
Scene load_scene(const std::string& path, const SceneOverrides& overrides = {});
/// Same, from text in memory; `name` stands for the file in error messages and `base_dir` is
/// the folder that the shape and initial-condition paths are relative to.
Scene parse_scene(const std::string& yaml_text, const std::string& name, const std::string& base_dir,
                  const SceneOverrides& overrides = {});

}  // namespace billiards::dynamics
