// The paper's drift and diffusion coefficients for a standard billiard (U = 0) under a uniform
// periodic drive F cos(ωt), in any dimension d, from the table's exact measures alone.
#pragma once

#include "billiards/analysis/fokker_planck.hpp"
#include "billiards/geometry/measures.hpp"

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace billiards::dynamics {
struct Scene;
}

namespace billiards::analysis {

struct Drive {
  Eigen::VectorXd F;  // force amplitude (uniform)
  double omega = 0;
  double mass = 1;
};

/// Everything the theory predicts at energy E, before any dynamics.
struct Coefficients {
  int dimension = 2;
  double energy = 0;                 // E
  double speed = 0;                  // v_E = √(2E/m)
  double volume = 0, surface = 0;    // V, S
  double mean_free_path = 0;         // λ = d B_d/B_{d−1} V/S
  double wall_integral = 0;          // ∫ (F·n)² dS
  double wall_integral_error = 0;    // its quadrature error estimate (0: closed form, uniform F)
  double density_of_states = 0;      // Σ(E) = d B_d V v^{d−2}/m
  double collision_rate_density = 0; // γ_E = B_{d−1}/(d B_d) v/V, uniform on the wall
  double collision_rate = 0;         // γ_E S = v/λ
  double C = 0;                      // g1 = C √E, g2 = 4 C E^{3/2}/(d+1)
  double g1 = 0, g2 = 0;
  double g1_error = 0, g2_error = 0; // quadrature error estimates (0: closed forms)
  // False with a potential U(x): g1, g2 are then not of the form C√E, 4C E^{3/2}/(d+1), so there
  // is no constant C (left 0, `null` in JSON) and no analytic Fokker–Planck solution.
  bool closed_form = true;
  double force_ratio = 0;            // F/(m ω v_E): must be ≪ 1 (the paper's condition 1)
  // v_E/(ω l): must be ≪ 1 (condition 2), with l taken as the mean free path λ.  The paper's l
  // is the SHORTEST length of the problem: a wall feature, or a scale on which F varies, that is
  // shorter than λ makes the true condition stricter than this ratio.
  double length_ratio = 0;
  // In a magnetic field (0 without one): the cyclotron radius r_c = m v_E/|qB|, the table's
  // inradius in 2-D (every orbit meets the wall when r_c is at least that; 0 in 3-D, where every
  // orbit with a velocity component along B drifts to the wall), and ω/|Ω| (must be ≫ 1).
  double cyclotron_radius = 0, inradius = 0, drive_over_cyclotron = 0;
  std::vector<std::string> warnings; // one per ratio above validity_threshold
};

/// nlohmann::json conversion (`nlohmann::json j = c;`), keys: dimension, E, v_E, V, S,
/// mean_free_path, wall_integral, wall_integral_error, Sigma, gamma_E, collision_rate, C, g1, g2,
/// g1_error, g2_error, closed_form, validity_force_ratio, validity_length_ratio, warnings; in a
/// magnetic field also cyclotron_radius, inradius, omega_over_cyclotron.
void to_json(nlohmann::json& j, const Coefficients& c);

/// Validity ratios above this are reported as warnings.
inline constexpr double validity_threshold = 0.1;

double density_of_states(const geometry::Measures& m, double mass, double E);
double collision_rate_density(const geometry::Measures& m, double mass, double E);
/// g1(E, ω) = 2 ω⁻² v_E/(m λ) · (1/S) ∫ (F·n)² dS  (the paper's eq. g1noU).
double drift_g1(const geometry::Measures& m, const Drive& drive, double E);
/// g2(E, ω) = 4 ω⁻² v_E³/((d+1) λ) · (1/S) ∫ (F·n)² dS  (eq. g2noU).
double diffusion_g2(const geometry::Measures& m, const Drive& drive, double E);
/// C = (2/m)^{3/2} ω⁻²/λ · (1/S) ∫ (F·n)² dS  (eq. B5).
double constant_C(const geometry::Measures& m, const Drive& drive);

Coefficients coefficients(const geometry::Measures& m, const Drive& drive, double E);

/// The same for a drive F(x) cos(ωt) whose amplitude depends on the position, in a 2-D table
/// with U = 0: ∮(F·n)² dS by adaptive Gauss–Kronrod along each piece (wall.hpp, with its error
/// estimate), g1 and g2 by wall.hpp's drift_g1 and diffusion_g2 with the uniform γ_E and v_E
/// (so g1 = C√E and g2 = 4C E^{3/2}/3 still hold, with C = g1/√E).  The force ratio uses the
/// largest |F| on the wall (sampled).
Coefficients coefficients(const geometry::Region2& region, const std::function<geometry::Vec2(const geometry::Vec2&)>& F,
                          double omega, double mass, double E);

/// The prediction for a scene: its coefficients at its initial energy, if the theory covers it
/// (a periodic or field drive, with or without a potential, and a microcanonical start).
std::optional<Coefficients> prediction_of(const dynamics::Scene& scene);

/// The Fokker–Planck distribution η(E, t_k) of a scene at times t_k, numerically
/// (solve_fokker_planck): with the closed forms in s = C t when prediction_of's `closed_form`,
/// otherwise (a potential) with energy_coefficients' quadratures over {U < E} (each ~ms, so
/// `cells` + ~50 of them) and the floor at the lowest U on the wall (sampled at 257 points a
/// piece, less 1e-3 of U's range on the wall), under which no particle reaches the wall.  nullopt where prediction_of has no prediction; an
/// InputError naming the scene if no particle reaches the wall at E0 (g2(E0) = 0).
std::optional<FokkerPlanckSolution> fokker_planck_of(const dynamics::Scene& scene, const std::vector<double>& times,
                                                     int cells, int steps = 2000);

}  // namespace billiards::analysis
