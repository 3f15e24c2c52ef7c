// Elliptic boundary pieces.  An ellipse is the image of the unit circle under the affine map
//   x = center + R(angle) · diag(a, b) · (cos φ, sin φ),
// φ being the eccentric anomaly.  The map preserves orientation, so the conventions of circular
// arcs (pieces.hpp) carry over: sweep > 0 runs counter-clockwise with the region INSIDE the
// ellipse (a focusing wall); sweep < 0 runs clockwise with the region OUTSIDE (a dispersing
// wall).  A full ellipse has |sweep| = 2π and source == target.
#pragma once

#include <Eigen/Core>

#include <cmath>

namespace billiards::geometry {

struct EllipticArc {
  Eigen::Vector2d center;
  Eigen::Vector2d semi_axes;  // a along the ellipse's first axis, b along its second (both > 0)
  double angle = 0;           // counter-clockwise angle of the first axis from the x axis
  double start = 0;           // eccentric anomaly of `source`
  double sweep = 0;           // signed extent in eccentric anomaly, |sweep| ≤ 2π
  Eigen::Vector2d source, target;

  bool focusing() const { return sweep > 0; }
  /// The point of eccentric anomaly φ.
  Eigen::Vector2d point_at(double phi) const {
    const double c = std::cos(angle), s = std::sin(angle);
    const double u = semi_axes.x() * std::cos(phi), w = semi_axes.y() * std::sin(phi);
    return center + Eigen::Vector2d(c * u - s * w, s * u + c * w);
  }
};

}  // namespace billiards::geometry
