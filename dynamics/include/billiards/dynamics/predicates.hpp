// Exact predicates for the collision kernels, in rational arithmetic (GMP): what a `_filtered`
// predicate asks when the double value lies within its forward error bound (straight_exit-inl.hpp's
// discriminant_positive_filtered).
#pragma once

#include "billiards/geometry/pieces.hpp"

#include <cmath>
#include <limits>

namespace billiards::dynamics {

using geometry::Vec2;

/// Exact sign of r²|v|² − ((x − c) × v)² for the double inputs (r² = r·r taken exactly).
int circle_discriminant_sign_exact(const Vec2& x, const Vec2& c, const Vec2& v, double r);
/// Exact sign of r²|v|² − |(x − c) × v|² (the ray meets the sphere iff > 0).
int sphere_discriminant_sign_exact(const Eigen::Vector3d& x, const Eigen::Vector3d& c, const Eigen::Vector3d& v, double r);

}  // namespace billiards::dynamics
