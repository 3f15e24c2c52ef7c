// Exact geometric measures of a billiard table, dimension-generic so that the analysis layer
// serves d = 2 and d = 3 alike.
#pragma once

#include "billiards/geometry/pieces.hpp"

#include <Eigen/Core>

namespace billiards::geometry {

struct Measures {
  int dimension = 2;
  double volume = 0;    // V: area in 2-D
  double surface = 0;   // S: perimeter in 2-D
  /// ∫ n nᵀ dS over the whole wall (d×d, symmetric, trace = S).  For a uniform force F the
  /// wall integral ∫ (F·n)² dS is Fᵀ · boundary_tensor · F.
  Eigen::MatrixXd boundary_tensor;
  Eigen::VectorXd bbox_lo, bbox_hi;
};

/// Volume of the unit ball in n dimensions, B_n = π^{n/2} / Γ(n/2 + 1).
double unit_ball_volume(int n);
/// Santaló's mean free path λ = d·B_d/B_{d-1}·V/S (π V / S in 2-D, 4 V / S in 3-D).
double mean_free_path(const Measures& m);
/// ∫ (F·n)² dS for a uniform F (length = dimension).
double wall_integral(const Measures& m, const Eigen::VectorXd& F);

/// Closed forms per piece: Green's theorem for the area, exact arc length, exact ∫ n nᵀ ds.
Measures measures_of(const Region2& region);
/// Signed area enclosed by one loop (> 0 counter-clockwise).
double signed_area(const Loop& loop);
/// Contribution of one piece to ∫ n nᵀ ds.
Eigen::Matrix2d boundary_tensor_of(const Piece& p);
/// Exact axis-aligned bounding box of one piece (arcs: their endpoints and the axis-extreme
/// points within their range), as (lower corner, upper corner).
std::pair<Vec2, Vec2> bounding_box(const Piece& p);

}  // namespace billiards::geometry
