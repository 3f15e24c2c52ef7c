// Where two ellipses (circles included) meet, for the joints of shape files.  Internal to
// shape_file.cpp.
#pragma once

#include "billiards/geometry/pieces.hpp"

#include <vector>

namespace billiards::geometry {

/// The common points of two distinct ellipses (only `center`, `semi_axes` and `angle` of each
/// are used): `touching` where they are tangent (a double root, the curves within `tol` of each
/// other), `crossing` where they cross.
struct Meetings {
  std::vector<Vec2> touching, crossing;
};
Meetings meetings(const EllipticArc& a, const EllipticArc& b, double tol);

/// Distance from p to the ellipse to first order: |g(p)|/|∇g(p)| with g = |q|² − 1, q the
/// preimage of p on the unit circle.  Exact for circles; off by O(d²·curvature) otherwise.
double distance_estimate(const EllipticArc& e, const Vec2& p);

}  // namespace billiards::geometry
