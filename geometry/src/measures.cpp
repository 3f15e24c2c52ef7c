#include "billiards/geometry/measures.hpp"

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_d.hpp>
#include <Eigen/Geometry>

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
  // x = c + U(cos t, sin t) with U = r·I (a circle) or R(angle)·diag(a, b) (an ellipse):
  // x × dx = c × U dw + det U dt, so ½∫(x dy − y dx) = ½[c × (target − source) + det U · Δt].
  const auto term = [](const auto& arc, double det) {
    return 0.5 * (cross(Vec2(arc.center), Vec2(arc.target - arc.source)) + det * arc.sweep);
  };
  if (const auto* a = std::get_if<Arc>(&p)) return term(*a, a->radius * a->radius);
  const auto& e = std::get<EllipticArc>(p);
  return term(e, e.semi_axes.x() * e.semi_axes.y());
}

/// Parameter extent of the arc as an increasing interval [lo, lo + |sweep|].
template <class A>
std::pair<double, double> angle_interval(const A& a) {
  return a.sweep >= 0 ? std::pair{a.start, a.start + a.sweep}
                      : std::pair{a.start + a.sweep, a.start};
}

void extend_bbox(Vec2& lo, Vec2& hi, const Vec2& p) {
  lo = lo.cwiseMin(p);
  hi = hi.cwiseMax(p);
}

/// Calls f(t) for every t = base + kπ in [t0, t1].
template <class F>
void for_each_half_turn(double base, double t0, double t1, F f) {
  for (double k = std::ceil((t0 - base) / pi); base + k * pi <= t1; ++k) f(base + k * pi);
}

}  // namespace

std::pair<Vec2, Vec2> bounding_box(const Piece& p) {
  Vec2 lo = source_of(p), hi = lo;
  extend_bbox(lo, hi, target_of(p));
  const auto extend_at = [&](const auto& arc, double base) {
    const auto [t0, t1] = angle_interval(arc);
    for_each_half_turn(base, t0, t1, [&](double t) { extend_bbox(lo, hi, arc.point_at(t)); });
  };
  if (const auto* a = std::get_if<Arc>(&p)) {
    // Axis-extreme points of the circle whose angle k·π/2 falls inside the arc.
    extend_at(*a, 0);
    extend_at(*a, pi / 2);
  } else if (const auto* e = std::get_if<EllipticArc>(&p)) {
    // x(φ) = cₓ + a cosθ cos φ − b sinθ sin φ is extreme where tan φ = −(b sinθ)/(a cosθ), and
    // y(φ) where tan φ = (b cosθ)/(a sinθ).
    const double a = e->semi_axes.x(), b = e->semi_axes.y(), c = std::cos(e->angle), s = std::sin(e->angle);
    extend_at(*e, std::atan2(-b * s, a * c));
    extend_at(*e, std::atan2(b * c, a * s));
  }
  return {lo, hi};
}

namespace {

/// ∫ n nᵀ ds over an elliptic arc.  With a ≥ b the outward normal is R(angle)·m/|m|, m =
/// (b cos φ, a sin φ), |m| = a Δ(ψ), Δ(ψ) = √(1 − k² sin²ψ), ψ = φ − π/2, k² = 1 − b²/a², so
/// (Legendre's F and D = (F − E)/k², both stable as k → 0):
///   ∫ b² cos²φ/|m| dφ = (b²/a) D,   ∫ a² sin²φ/|m| dφ = a (F − D),
///   ∫ ab cos φ sin φ/|m| dφ = −b ∫ sin ψ cos ψ/Δ dψ = −b (sin²ψ₁ − sin²ψ₀)/(Δ₁ + Δ₀).
Eigen::Matrix2d elliptic_boundary_tensor(const EllipticArc& arc) {
  const EllipticArc e = arc.major_first();
  const double a = e.semi_axes.x(), b = e.semi_axes.y();
  const double k = std::sqrt((a - b) * (a + b)) / a;
  const auto [phi0, phi1] = angle_interval(e);
  const double psi0 = phi0 - pi / 2, psi1 = phi1 - pi / 2;
  const auto delta = [&](double psi) { return std::sqrt(1 - k * k * std::sin(psi) * std::sin(psi)); };
  const double F = boost::math::ellint_1(k, psi1) - boost::math::ellint_1(k, psi0);
  const double D = boost::math::ellint_d(k, psi1) - boost::math::ellint_d(k, psi0);
  const double off = -b * std::sin(psi1 - psi0) * std::sin(psi1 + psi0) / (delta(psi1) + delta(psi0));
  Eigen::Matrix2d body;
  body << b * b / a * D, off, off, a * (F - D);
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(e.angle).toRotationMatrix();
  return R * body * R.transpose();
}

}  // namespace

Eigen::Matrix2d boundary_tensor_of(const Piece& p) {
  if (const auto* s = std::get_if<Segment>(&p)) {
    const Vec2 n = outward_normal(p, s->a);
    return (s->b - s->a).norm() * n * n.transpose();
  }
  if (const auto* e = std::get_if<EllipticArc>(&p)) return elliptic_boundary_tensor(*e);
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
