#include "billiards/dynamics/walls.hpp"

#include <algorithm>

namespace billiards::dynamics {

SegmentWall::SegmentWall(const geometry::Segment& s) : a(s.a), b(s.b) {
  const Vec2 d = b - a;
  normal = Vec2(d.y(), -d.x()).normalized();  // right of travel = out of the region
  dir = d / d.squaredNorm();
  slack = span_slack_ulps * std::max({a.lpNorm<Eigen::Infinity>(), b.lpNorm<Eigen::Infinity>(), d.norm()});
}

ArcWall::ArcWall(const geometry::Arc& arc)
    : center(arc.center), radius(arc.radius), radius2(arc.radius * arc.radius),
      focusing(arc.sweep > 0), full(std::abs(arc.sweep) >= 2 * geometry::pi) {
  // Store the endpoints in counter-clockwise order so one span test serves both senses.
  const Vec2 s = arc.source - center, t = arc.target - center;
  from = focusing ? s : t;
  to = focusing ? t : s;
  ccw_extent = std::abs(arc.sweep);
  slack = span_slack_ulps * std::max(radius, center.lpNorm<Eigen::Infinity>());
}

}  // namespace billiards::dynamics
