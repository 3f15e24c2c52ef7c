#include "billiards/analysis/coefficients.hpp"

#include "billiards/analysis/potential.hpp"
#include "billiards/analysis/wall.hpp"
#include "billiards/dynamics/scene.hpp"
#include "billiards/dynamics/table.hpp"
#include "billiards/geometry/input_error.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
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

namespace {

/// Everything that depends on the table and E only.
Coefficients table_part(const geometry::Measures& m, double mass, double E) {
  Coefficients c;
  c.dimension = m.dimension;
  c.energy = E;
  c.speed = speed_at(mass, E);
  c.volume = m.volume;
  c.surface = m.surface;
  c.mean_free_path = geometry::mean_free_path(m);
  c.density_of_states = density_of_states(m, mass, E);
  c.collision_rate_density = collision_rate_density(m, mass, E);
  c.collision_rate = c.collision_rate_density * m.surface;
  return c;
}

/// The validity ratios and their warnings, for a force of size at most F.
void check_validity(Coefficients& c, double F, double omega, double mass) {
  c.force_ratio = F / (mass * omega * c.speed);
  c.length_ratio = c.speed / (omega * c.mean_free_path);
  if (c.force_ratio > validity_threshold)
    c.warnings.push_back(fmt::format("F/(m omega v_E) = {:.3g} is not small: the drive is not a weak perturbation "
                                     "(the paper's condition 1)", c.force_ratio));
  if (c.length_ratio > validity_threshold)
    c.warnings.push_back(fmt::format("v_E/(omega lambda) = {:.3g} is not small: a period is not short against a "
                                     "free flight (the paper's condition 2)", c.length_ratio));
}

/// The largest |F(x)| over the wall (sampled).
double largest_force_on_wall(const geometry::Region2& region, const ForceField& F) {
  return wall_maximum(region, [&](const geometry::Vec2& x) { return F(x).norm(); });
}

}  // namespace

Coefficients coefficients(const geometry::Measures& m, const Drive& drive, double E) {
  Coefficients c = table_part(m, drive.mass, E);
  c.wall_integral = geometry::wall_integral(m, drive.F);
  c.C = constant_C(m, drive);
  c.g1 = drift_g1(m, drive, E);
  c.g2 = diffusion_g2(m, drive, E);
  check_validity(c, drive.F.norm(), drive.omega, drive.mass);
  return c;
}

Coefficients coefficients(const geometry::Region2& region, const std::function<geometry::Vec2(const geometry::Vec2&)>& F,
                          double omega, double mass, double E) {
  Coefficients c = table_part(geometry::measures_of(region), mass, E);
  const Quadrature W = wall_integral(region, F);
  c.wall_integral = W.value;
  c.wall_integral_error = W.error;
  auto gamma_E = [&](const geometry::Vec2&) { return c.collision_rate_density; };
  auto v_E = [&](const geometry::Vec2&) { return c.speed; };
  c.g1 = drift_g1(region, F, gamma_E, omega, mass).value;
  c.g2 = diffusion_g2(region, F, gamma_E, v_E, omega).value;
  c.C = c.g1 / std::sqrt(E);
  check_validity(c, largest_force_on_wall(region, F), omega, mass);
  return c;
}

Coefficients coefficients(const geometry::Region2& region, const Potential& U, const ForceField& F, double omega,
                          double mass, double E) {
  Coefficients c = table_part(geometry::measures_of(region), mass, E);
  c.closed_form = false;
  c.C = 0;
  const PotentialCoefficients p = potential_coefficients(region, U, F, E, omega, mass);
  c.density_of_states = p.Sigma.value;
  c.g1 = p.g1.value;
  c.g1_error = p.g1.error;
  c.g2 = p.g2.value;
  c.g2_error = p.g2.error;
  const Quadrature W = wall_integral(region, F);
  c.wall_integral = W.value;
  c.wall_integral_error = W.error;
  c.speed = 0;
  if (p.Sigma.value > 0) {
    const ScalarField gamma = collision_rate_field(U, E, mass, p.Sigma.value);
    const ScalarField v = speed_field(U, E, mass);
    c.collision_rate = wall_quadrature(region, [&](const geometry::Vec2& x, const geometry::Vec2&) { return gamma(x); }).value;
    const double flux = wall_quadrature(region, [&](const geometry::Vec2& x, const geometry::Vec2&) {
                          return gamma(x) * v(x);
                        }).value;
    if (c.collision_rate > 0) c.speed = flux / c.collision_rate;
  }
  c.collision_rate_density = c.collision_rate / c.surface;
  if (c.speed > 0) check_validity(c, largest_force_on_wall(region, F), omega, mass);
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
       {"wall_integral_error", c.wall_integral_error},
       {"Sigma", c.density_of_states},
       {"gamma_E", c.collision_rate_density},
       {"collision_rate", c.collision_rate},
       {"C", c.closed_form ? nlohmann::json(c.C) : nlohmann::json(nullptr)},
       {"g1", c.g1},
       {"g2", c.g2},
       {"g1_error", c.g1_error},
       {"g2_error", c.g2_error},
       {"closed_form", c.closed_form},
       {"validity_force_ratio", c.force_ratio},
       {"validity_length_ratio", c.length_ratio},
       {"warnings", c.warnings}};
  if (c.cyclotron_radius > 0) {
    j["cyclotron_radius"] = c.cyclotron_radius;
    j["inradius"] = c.inradius;
    j["omega_over_cyclotron"] = c.drive_over_cyclotron;
  }
}

namespace {

/// The scene's drive amplitude F(x), uniform or its field's expressions (2-D); refers to the scene.
ForceField amplitude_of(const dynamics::Scene& scene) {
  if (scene.force.kind == dynamics::Force::Kind::field) {
    const auto* field = &scene.force.field;
    return [field](const geometry::Vec2& x) { return geometry::Vec2((*field)[0](x), (*field)[1](x)); };
  }
  const geometry::Vec2 F(scene.force.amplitude);
  return [F](const geometry::Vec2&) { return F; };
}

/// The scene's U(x); refers to the scene.
Potential potential_of(const dynamics::Scene& scene) {
  const auto* p = &*scene.potential;
  return [p](const geometry::Vec2& x) { return p->U(x); };
}

/// The radius of the largest disk in the region, from below: the best of a 64 × 64 grid of
/// centres, refined by a pattern search (steps halving down to 1e-4 of the table's size).
double inradius(const geometry::Region2& region) {
  const dynamics::Table table(region);
  const geometry::Vec2 lo = table.lo(), size = table.hi() - table.lo();
  auto radius = [&](const geometry::Vec2& x) { return table.contains(x, 0) ? table.wall_distance(x) : 0.0; };
  geometry::Vec2 best = lo + size / 2;
  double r = radius(best);
  constexpr int k = 64;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      const geometry::Vec2 x = lo + geometry::Vec2(size.x() * (i + 0.5) / k, size.y() * (j + 0.5) / k);
      if (const double d = radius(x); d > r) r = d, best = x;
    }
  for (double step = size.maxCoeff() / k; step > 1e-4 * size.maxCoeff(); step /= 2)
    for (bool moved = true; moved;) {
      moved = false;
      for (const geometry::Vec2& dx : {geometry::Vec2(step, 0), geometry::Vec2(-step, 0), geometry::Vec2(0, step), geometry::Vec2(0, -step)})
        if (const double d = radius(best + dx); d > r) r = d, best += dx, moved = true;
    }
  return r;
}

/// The magnetic field's validity statement: Santaló's formula (the collision rate, hence λ,
/// γ_E, the wall integral's weight) holds for the magnetic flow, and Σ(E) does not depend on B;
/// but in 2-D orbits with r_c below the inradius can circle without meeting the wall (in 3-D
/// only those with no velocity along B, a set of measure zero: every other helix drifts to the
/// wall), and the averaging over the drive's period needs ω ≫ |Ω|.
void check_magnetic(Coefficients& c, const dynamics::Scene& scene) {
  const double cyclotron = scene.cyclotron_vector().norm();
  c.cyclotron_radius = c.speed / cyclotron;
  c.drive_over_cyclotron = scene.force.omega / cyclotron;
  if (scene.dimension() == 2) {
    c.inradius = inradius(scene.shape<2>().region);
    if (c.cyclotron_radius < c.inradius)
      c.warnings.push_back(fmt::format("the cyclotron radius r_c = {:.3g} is below the table's inradius {:.3g}: some "
                                       "orbits circle without ever meeting the wall, and those particles never diffuse "
                                       "(the ensemble's mean collision rate is still v/lambda)",
                                       c.cyclotron_radius, c.inradius));
  }
  if (c.drive_over_cyclotron * validity_threshold < 1)
    c.warnings.push_back(fmt::format("omega/|Omega| = {:.3g} is not large: the drive must be fast against the "
                                     "cyclotron frequency Omega = qB/m for the theory's averaging",
                                     c.drive_over_cyclotron));
}

}  // namespace

std::optional<Coefficients> prediction_of(const dynamics::Scene& scene) {
  using Kind = dynamics::Force::Kind;
  const Kind kind = scene.force.kind;
  if (scene.energy <= 0 || (kind != Kind::periodic && kind != Kind::field)) return std::nullopt;
  if (kind == Kind::periodic && !scene.potential) {
    Drive drive;
    drive.F = scene.force.amplitude;
    drive.omega = scene.force.omega;
    drive.mass = scene.mass;
    auto c = coefficients(scene.measures(), drive, scene.energy);
    if (scene.magnetic()) check_magnetic(c, scene);
    return c;
  }
  // A field amplitude or a potential: quadrature along the wall (2-D scenes only).
  const auto& region = scene.shape<2>().region;
  const ForceField F = amplitude_of(scene);
  if (!scene.potential) return coefficients(region, F, scene.force.omega, scene.mass, scene.energy);
  return coefficients(region, potential_of(scene), F, scene.force.omega, scene.mass, scene.energy);
}

std::optional<FokkerPlanckSolution> fokker_planck_of(const dynamics::Scene& scene, const std::vector<double>& times,
                                                     int cells, int steps) {
  const auto c = prediction_of(scene);
  if (!c) return std::nullopt;
  if (!(c->g2 > 0))
    throw InputError(scene.file, 0,
                     fmt::format("g2 = 0 at E0 = {}: the energy does not diffuse (no drive on the wall a particle reaches)",
                                 scene.energy));
  if (c->closed_form) {
    std::vector<double> s;
    for (double t : times) s.push_back(c->C * t);
    auto solution = solve_fokker_planck(s, scene.energy, c->dimension, cells, steps);
    solution.times = times;
    return solution;
  }
  const auto& region = scene.shape<2>().region;
  const Potential U = potential_of(scene);
  const double lowest = -wall_maximum(region, [&](const geometry::Vec2& x) { return -U(x); });
  const double highest = wall_maximum(region, U);
  // The sampled minimum may lie a little above the true one: keep a margin below it.
  const double floor = lowest - 1e-3 * (highest - lowest);
  const auto g = energy_coefficients(region, U, amplitude_of(scene), scene.force.omega, scene.mass, 1e-10);
  return solve_fokker_planck(times, scene.energy, floor, g, cells, steps);
}

}  // namespace billiards::analysis
