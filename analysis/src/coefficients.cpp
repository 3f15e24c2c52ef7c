#include "billiards/analysis/coefficients.hpp"

#include "billiards/dynamics/scene.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace billiards::analysis {

using geometry::unit_ball_volume;

namespace {
double speed_at(double mass, double E) { return std::sqrt(2 * E / mass); }
/// (1/S) ∫ (F·n)² dS
double mean_wall_force2(const geometry::Measures& m, const Drive& drive) {
  return geometry::wall_integral(m, drive.F) / m.surface;
}
}  // namespace

double density_of_states(const geometry::Measures& m, double mass, double E) {
  const int d = m.dimension;
  return d * unit_ball_volume(d) * m.volume * std::pow(speed_at(mass, E), d - 2) / mass;
}

double collision_rate_density(const geometry::Measures& m, double mass, double E) {
  const int d = m.dimension;
  return unit_ball_volume(d - 1) / (d * unit_ball_volume(d)) * speed_at(mass, E) / m.volume;
}

double drift_g1(const geometry::Measures& m, const Drive& drive, double E) {
  const double w2 = drive.omega * drive.omega;
  return 2 * speed_at(drive.mass, E) / (w2 * drive.mass * geometry::mean_free_path(m)) * mean_wall_force2(m, drive);
}

double diffusion_g2(const geometry::Measures& m, const Drive& drive, double E) {
  const double v = speed_at(drive.mass, E), w2 = drive.omega * drive.omega;
  return 4 * v * v * v / (w2 * (m.dimension + 1) * geometry::mean_free_path(m)) * mean_wall_force2(m, drive);
}

double constant_C(const geometry::Measures& m, const Drive& drive) {
  return std::pow(2 / drive.mass, 1.5) * mean_wall_force2(m, drive) /
         (drive.omega * drive.omega * geometry::mean_free_path(m));
}

Coefficients coefficients(const geometry::Measures& m, const Drive& drive, double E) {
  Coefficients c;
  c.dimension = m.dimension;
  c.energy = E;
  c.speed = speed_at(drive.mass, E);
  c.volume = m.volume;
  c.surface = m.surface;
  c.mean_free_path = geometry::mean_free_path(m);
  c.wall_integral = geometry::wall_integral(m, drive.F);
  c.density_of_states = density_of_states(m, drive.mass, E);
  c.collision_rate_density = collision_rate_density(m, drive.mass, E);
  c.collision_rate = c.collision_rate_density * m.surface;
  c.C = constant_C(m, drive);
  c.g1 = drift_g1(m, drive, E);
  c.g2 = diffusion_g2(m, drive, E);
  c.force_ratio = drive.F.norm() / (drive.mass * drive.omega * c.speed);
  c.length_ratio = c.speed / (drive.omega * c.mean_free_path);
  if (c.force_ratio > validity_threshold)
    c.warnings.push_back(fmt::format("F/(m omega v_E) = {:.3g} is not small: the drive is not a weak perturbation "
                                     "(the paper's condition 1)", c.force_ratio));
  if (c.length_ratio > validity_threshold)
    c.warnings.push_back(fmt::format("v_E/(omega lambda) = {:.3g} is not small: a period is not short against a "
                                     "free flight (the paper's condition 2)", c.length_ratio));
  return c;
}

void to_json(nlohmann::json& j, const Coefficients& c) {
  j = {{"dimension", c.dimension},
       {"E", c.energy},
       {"v_E", c.speed},
       {"V", c.volume},
       {"S", c.surface},
       {"mean_free_path", c.mean_free_path},
       {"wall_integral", c.wall_integral},
       {"Sigma", c.density_of_states},
       {"gamma_E", c.collision_rate_density},
       {"collision_rate", c.collision_rate},
       {"C", c.C},
       {"g1", c.g1},
       {"g2", c.g2},
       {"validity_force_ratio", c.force_ratio},
       {"validity_length_ratio", c.length_ratio},
       {"warnings", c.warnings}};
}

std::optional<Coefficients> prediction_of(const dynamics::Scene& scene) {
  if (scene.force.kind != dynamics::Force::Kind::periodic || scene.energy <= 0) return std::nullopt;
  Drive drive;
  drive.F = scene.force.amplitude;
  drive.omega = scene.force.omega;
  drive.mass = scene.mass;
  return coefficients(scene.measures(), drive, scene.energy);
}

}  // namespace billiards::analysis
