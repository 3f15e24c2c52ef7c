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

  /// dx/dφ, the counter-clockwise tangent at anomaly φ (not normalised).
  Eigen::Vector2d tangent_at(double phi) const;
  /// |dx/dφ| = √(a² sin²φ + b² cos²φ): arc length per unit of anomaly.
  double speed_at(double phi) const;
  /// The anomaly of a point on the ellipse (of its preimage's direction, off the ellipse).
  double anomaly_of(const Eigen::Vector2d& p) const;
  /// Signed curvature seen from the region, ab / (a² sin²φ + b² cos²φ)^{3/2}, positive when
  /// focusing (cf. Arc::curvature).
  double curvature_at(double phi) const;

  /// A primitive of the arc length in φ: the length from φ₀ to φ₁ is length_to(φ₁) −
  /// length_to(φ₀) (an incomplete elliptic integral of the second kind, increasing in φ).
  double length_to(double phi) const;
  /// The anomaly φ ∈ [lo, hi] with length_to(φ) = s (Newton's method, bracketed).
  double anomaly_at_length(double s, double lo, double hi) const;
  /// The same arc with semi_axes.x() ≥ semi_axes.y(): axes swapped, the first turned by π/2
  /// and the anomalies shifted by −π/2 (point_at(φ − π/2) of the result is point_at(φ)).
  EllipticArc major_first() const;
};

}  // namespace billiards::geometry
