#include "billiards/geometry/measures.hpp"

#include <cmath>
#include <limits>

namespace billiards::geometry {

double unit_ball_volume(int n) { return std::pow(pi, 0.5 * n) / std::tgamma(0.5 * n + 1); }

double mean_free_path(const Measures& m) {
  const int d = m.dimension;
  return d * unit_ball_volume(d) / unit_ball_volume(d - 1) * m.volume / m.surface;
}

double wall_integral(const Measures& m, const Eigen::VectorXd& F) {
  return F.dot(m.boundary_tensor * F);
}

namespace {

/// ½ ∮ (x dy − y dx) along one piece (Green's theorem).
double area_term(const Piece& p) {
  if (const auto* s = std::get_if<Segment>(&p)) return 0.5 * cross(s->a, s->b);
  const auto& a = std::get<Arc>(p);
  const Vec2 d = a.target - a.source;
  // x = c + r(cos θ, sin θ): ½∫(x dy − y dx) = ½[cₓΔy − c_yΔx + r²Δθ] (the chord terms of
  // the centre integrate exactly to cₓΔy − c_yΔx).
  return 0.5 * (a.center.x() * d.y() - a.center.y() * d.x() + a.radius * a.radius * a.sweep);
}

/// Angular extent of the arc as an increasing interval [lo, lo + |sweep|].
std::pair<double, double> angle_interval(const Arc& a) {
  return a.sweep >= 0 ? std::pair{a.start, a.start + a.sweep}
                      : std::pair{a.start + a.sweep, a.start};
}

void extend_bbox(Vec2& lo, Vec2& hi, const Vec2& p) {
  lo = lo.cwiseMin(p);
  hi = hi.cwiseMax(p);
}

}  // namespace

std::pair<Vec2, Vec2> bounding_box(const Piece& p) {
  Vec2 lo = source_of(p), hi = lo;
  extend_bbox(lo, hi, target_of(p));
  if (const auto* a = std::get_if<Arc>(&p)) {
    // Axis-extreme points of the circle whose angle k·π/2 falls inside the arc.
    const auto [t0, t1] = angle_interval(*a);
    for (double k = std::ceil(t0 / (pi / 2)); k * (pi / 2) <= t1; ++k) extend_bbox(lo, hi, a->point_at(k * (pi / 2)));
  }
  return {lo, hi};
}

Eigen::Matrix2d boundary_tensor_of(const Piece& p) {
  if (const auto* s = std::get_if<Segment>(&p)) {
    const Vec2 n = outward_normal(p, s->a);
    return (s->b - s->a).norm() * n * n.transpose();
  }
  // n = ±(cos θ, sin θ): ∫cos² = θ/2 + sin2θ/4, ∫sin² = θ/2 − sin2θ/4, ∫cos·sin = −cos2θ/4.
  const auto& a = std::get<Arc>(p);
  const auto [t0, t1] = angle_interval(a);
  const double dt = t1 - t0;
  const double ds2 = std::sin(2 * t1) - std::sin(2 * t0);
  const double dc2 = std::cos(2 * t1) - std::cos(2 * t0);
  Eigen::Matrix2d T;
  T << dt / 2 + ds2 / 4, -dc2 / 4, -dc2 / 4, dt / 2 - ds2 / 4;
  return a.radius * T;
}

double signed_area(const Loop& loop) {
  double area = 0;
  for (const Piece& p : loop.pieces) area += area_term(p);
  return area;
}

Measures measures_of(const Region2& region) {
  Measures m;
  m.dimension = 2;
  m.boundary_tensor = Eigen::Matrix2d::Zero();
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 hi = -lo;
  for (const Loop* loop : region.loops()) {
    m.volume += signed_area(*loop);  // holes run clockwise: negative area
    for (const Piece& p : loop->pieces) {
      m.surface += length_of(p);
      m.boundary_tensor += boundary_tensor_of(p);
    }
  }
  for (const Piece& p : region.outer.pieces) {
    const auto [a, b] = bounding_box(p);
    extend_bbox(lo, hi, a);
    extend_bbox(lo, hi, b);
  }
  m.bbox_lo = lo;
  m.bbox_hi = hi;
  return m;
}

}  // namespace billiards::geometry
