#include "billiards/analysis/boundary_map.hpp"

#include "billiards/geometry/expression.hpp"
#include "billiards/geometry/input_error.hpp"

#include <fmt/core.h>

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

template <int D>
BasicSection<D> parse_section(const std::string& text, const std::string& option) {
  using V = Eigen::Matrix<double, D, 1>;
  const char* names[] = {"x", "y", "z"};
  const auto eq = text.find('=');
  const auto fail = [&](const std::string& why) { return InputError(option + " '" + text + "'", 0, why); };
  if (eq == std::string::npos || text.find('=', eq + 1) != std::string::npos)
    throw fail(D == 2 ? "a section is one equation of a line in x and y, such as \"y = 0\" or \"x + 2*y = 1\""
                      : "a 3-D section is one equation of a plane in x, y and z, such as \"z = 0\" or \"x + y = 0.2\"");
  const std::string difference = fmt::format("({}) - ({})", text.substr(0, eq), text.substr(eq + 1));
  const auto f = [&](const V& x) {
    Expressions e;
    for (int k = 0; k < D; ++k) e.define(names[k], fmt::format("{:.17g}", x[k]), option, 0);
    return e.evaluate(difference, option, 0);
  };
  const double c = -f(V::Zero());
  V a;
  for (int k = 0; k < D; ++k) a[k] = f(V::Unit(k)) + c;
  const double norm = a.norm();
  for (const double scale : {1.0, -2.3, 1e3}) {
    V x;
    for (int k = 0; k < D; ++k) x[k] = scale * std::sin(1.7 + 2.9 * k);
    const double linear = a.dot(x) - c;
    if (!(std::abs(f(x) - linear) <= 1e-9 * (std::abs(linear) + norm * x.cwiseAbs().sum() + std::abs(c))))
      throw fail(D == 2 ? "the equation is not linear in x and y: a section is a straight line"
                        : "the equation is not linear in x, y and z: a 3-D section is a plane");
  }
  if (!(norm > 0)) throw fail(D == 2 ? "the equation does not depend on x or y: it is no line"
                                     : "the equation does not depend on x, y or z: it is no plane");
  return {a / norm, c / norm};
}
template BasicSection<2> parse_section<2>(const std::string&, const std::string&);
template BasicSection<3> parse_section<3>(const std::string&, const std::string&);

}  // namespace billiards::analysis
