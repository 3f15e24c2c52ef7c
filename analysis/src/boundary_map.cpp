#include "billiards/analysis/boundary_map.hpp"

#include <algorithm>

namespace billiards::analysis {

namespace {

/// The angle from `start` to `angle` in the direction of `sweep`, in [0, |sweep|]: a point
/// rounded just past either end of the arc is put at that end (the nearer across the gap).
double angle_along(double angle, double start, double sweep) {
  const double two_pi = 2 * geometry::pi, extent = std::abs(sweep);
  double d = std::fmod(sweep > 0 ? angle - start : start - angle, two_pi);
  if (d < 0) d += two_pi;
  if (d > extent) d = d - extent < (two_pi - extent) / 2 ? extent : 0;
  return d;
}

/// Arc length from the piece's source to the point of the piece nearest x.
double length_along(const geometry::Piece& piece, const Vec2& x) {
  return std::visit(
      geometry::overloaded{
          [&](const geometry::Segment& s) {
            const Vec2 d = s.b - s.a;
            return std::clamp((x - s.a).dot(d) / d.norm(), 0.0, d.norm());
          },
          [&](const geometry::Arc& a) {
            const Vec2 u = x - a.center;
            return a.radius * angle_along(std::atan2(u.y(), u.x()), a.start, a.sweep);
          },
          [&](const geometry::EllipticArc& e) {
            // The incomplete elliptic integral of the second kind between the anomalies.
            const double phi = e.start + std::copysign(angle_along(e.anomaly_of(x), e.start, e.sweep), e.sweep);
            return std::abs(e.length_to(phi) - e.length_to(e.start));
          }},
      piece);
}

}  // namespace

BoundaryCoordinates::BoundaryCoordinates(const geometry::Region2& region) {
  starts_.push_back(0);
  for (const auto* loop : region.loops()) {
    loop_firsts_.push_back(int(pieces_.size()));
    for (const auto& piece : loop->pieces) {
      pieces_.push_back(piece);
      starts_.push_back(starts_.back() + geometry::length_of(piece));
    }
  }
}

double BoundaryCoordinates::s_at(int piece, const Vec2& x) const {
  return starts_[std::size_t(piece)] + length_along(pieces_[std::size_t(piece)], x);
}

}  // namespace billiards::analysis
