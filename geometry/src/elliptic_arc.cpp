#include "billiards/geometry/elliptic_arc.hpp"

#include <boost/math/special_functions/ellint_2.hpp>
#include <boost/math/tools/roots.hpp>

#include <limits>
#include <numbers>
#include <utility>

namespace billiards::geometry {

Eigen::Vector2d EllipticArc::tangent_at(double phi) const {
  const double c = std::cos(angle), s = std::sin(angle);
  const double u = -semi_axes.x() * std::sin(phi), w = semi_axes.y() * std::cos(phi);
  return {c * u - s * w, s * u + c * w};
}

double EllipticArc::speed_at(double phi) const { return std::hypot(semi_axes.x() * std::sin(phi), semi_axes.y() * std::cos(phi)); }

double EllipticArc::anomaly_of(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d d = p - center;
  const double c = std::cos(angle), s = std::sin(angle);
  return std::atan2((-s * d.x() + c * d.y()) / semi_axes.y(), (c * d.x() + s * d.y()) / semi_axes.x());
}

double EllipticArc::curvature_at(double phi) const {
  const double v = speed_at(phi);
  return (focusing() ? 1.0 : -1.0) * semi_axes.x() * semi_axes.y() / (v * v * v);
}

EllipticArc EllipticArc::major_first() const {
  if (semi_axes.x() >= semi_axes.y()) return *this;
  EllipticArc e = *this;
  e.semi_axes = {semi_axes.y(), semi_axes.x()};
  e.angle = angle + std::numbers::pi / 2;
  e.start = start - std::numbers::pi / 2;
  return e;
}

double EllipticArc::length_to(double phi) const {
  // With a ≥ b, |dx/dφ| = a √(1 − k² cos²φ), k² = 1 − b²/a²; cos φ = −sin(φ − π/2) turns it
  // into Legendre's form: a·E(φ − π/2, k).
  if (semi_axes.x() < semi_axes.y()) return major_first().length_to(phi - std::numbers::pi / 2);
  const double a = semi_axes.x(), b = semi_axes.y();
  const double k = std::sqrt((a - b) * (a + b)) / a;
  return a * boost::math::ellint_2(k, phi - std::numbers::pi / 2);
}

double EllipticArc::anomaly_at_length(double s, double lo, double hi) const {
  // length_to is smooth and strictly increasing (its derivative is the speed, ≥ min(a, b)):
  // Newton's method from the linear interpolant converges in a few steps.
  const double s_lo = length_to(lo), s_hi = length_to(hi);
  const double guess = s_hi > s_lo ? lo + (hi - lo) * (s - s_lo) / (s_hi - s_lo) : lo;
  std::uintmax_t iterations = 50;
  return boost::math::tools::newton_raphson_iterate(
      [&](double phi) { return std::pair{length_to(phi) - s, speed_at(phi)}; }, std::clamp(guess, lo, hi), lo, hi,
      std::numeric_limits<double>::digits - 2, iterations);
}

}  // namespace billiards::geometry
