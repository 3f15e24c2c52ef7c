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

/// Arc length from the piece's source to the point of the piece nearest x; `origin` is an
/// elliptic arc's length_to(start), computed once.
double length_along(const geometry::Piece& piece, double origin, const Vec2& x) {
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
            return std::abs(e.length_to(phi) - origin);
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
      const auto* e = std::get_if<geometry::EllipticArc>(&piece);
      origins_.push_back(e ? e->length_to(e->start) : 0);
      starts_.push_back(starts_.back() + geometry::length_of(piece));
    }
  }
}

double BoundaryCoordinates::s_at(int piece, const Vec2& x) const {
  return starts_[std::size_t(piece)] + length_along(pieces_[std::size_t(piece)], origins_[std::size_t(piece)], x);
}

int BoundaryCoordinates::piece_at(double s) const {
  const auto it = std::upper_bound(starts_.begin(), starts_.end() - 1, s);
  return std::max(0, int(it - starts_.begin()) - 1);
}

Vec2 BoundaryCoordinates::point_at(double s) const {
  const int k = piece_at(s);
  const double length = starts_[k + 1] - starts_[k];
  return geometry::point_along(pieces_[k], std::clamp((s - starts_[k]) / length, 0.0, 1.0));
}

Vec2 BoundaryCoordinates::normal_at(double s) const { return geometry::outward_normal(pieces_[piece_at(s)], point_at(s)); }

int BoundaryCoordinates::loop_at(double s) const {
  const int k = piece_at(s);
  return int(std::upper_bound(loop_firsts_.begin(), loop_firsts_.end(), k) - loop_firsts_.begin()) - 1;
}

std::pair<double, double> BoundaryCoordinates::loop_range(int loop) const {
  const std::size_t next = std::size_t(loop) + 1 < loop_firsts_.size() ? std::size_t(loop_firsts_[loop + 1]) : pieces_.size();
  return {starts_[loop_firsts_[loop]], starts_[next]};
}

std::optional<double> BoundaryCoordinates::locate(const Vec2& x, double tolerance) const {
  for (std::size_t k = 0; k < pieces_.size(); ++k) {
    const double s = s_at(int(k), x);
    if ((point_at(s) - x).norm() <= tolerance) return s;
  }
  return std::nullopt;
}

}  // namespace billiards::analysis
