#include "billiards/geometry/pieces.hpp"

#include <algorithm>
#include <cmath>

namespace billiards::geometry {

std::string SourceRef::describe() const {
  if (file.empty()) return "<built in code>";
  return line > 0 ? file + ":" + std::to_string(line) : file;
}

Vec2 Arc::point_at(double angle) const {
  return center + radius * Vec2(std::cos(angle), std::sin(angle));
}

Vec2 source_of(const Piece& p) {
  return std::visit(overloaded{[](const Segment& s) { return s.a; }, [](const auto& arc) { return Vec2(arc.source); }},
                    p);
}

Vec2 target_of(const Piece& p) {
  return std::visit(overloaded{[](const Segment& s) { return s.b; }, [](const auto& arc) { return Vec2(arc.target); }},
                    p);
}

double length_of(const Piece& p) {
  return std::visit(overloaded{[](const Segment& s) { return (s.b - s.a).norm(); },
                               [](const Arc& a) { return a.radius * std::abs(a.sweep); },
                               [](const EllipticArc& e) {
                                 return std::abs(e.length_to(e.start + e.sweep) - e.length_to(e.start));
                               }},
                    p);
}

double curvature_at(const Piece& p, const Vec2& on_piece) {
  return std::visit(overloaded{[](const Segment&) { return 0.0; },
                               [](const Arc& a) { return a.curvature(); },
                               [&](const EllipticArc& e) { return e.curvature_at(e.anomaly_of(on_piece)); }},
                    p);
}

Vec2 outward_normal(const Piece& p, const Vec2& on_piece) {
  // The right normal of the direction of travel; a counter-clockwise arc's is the curve's
  // own outward normal.
  const auto right = [](const Vec2& d) { return Vec2(d.y(), -d.x()); };
  return std::visit(overloaded{[&](const Segment& s) { return right((s.b - s.a).normalized()); },
                               [&](const Arc& a) {
                                 const Vec2 u = (on_piece - a.center).normalized();
                                 return a.focusing() ? u : Vec2(-u);
                               },
                               [&](const EllipticArc& e) {
                                 const Vec2 n = right(e.tangent_at(e.anomaly_of(on_piece)).normalized());
                                 return e.focusing() ? n : Vec2(-n);
                               }},
                    p);
}

Vec2 point_along(const Piece& p, double u) {
  return std::visit(overloaded{[&](const Segment& s) { return Vec2(s.a + u * (s.b - s.a)); },
                               [&](const Arc& a) { return a.point_at(a.start + u * a.sweep); },
                               [&](const EllipticArc& e) {
                                 const double end = e.start + e.sweep;
                                 const double s = e.length_to(e.start) + u * (e.length_to(end) - e.length_to(e.start));
                                 return Vec2(e.point_at(e.anomaly_at_length(s, std::min(e.start, end), std::max(e.start, end))));
                               }},
                    p);
}

const char* kind_of(const Piece& p) {
  return std::visit(overloaded{[](const Segment&) { return "segment"; }, [](const Arc&) { return "arc"; },
                               [](const EllipticArc&) { return "elliptic_arc"; }},
                    p);
}

bool is_closed_curve(const Piece& p) {
  return std::visit(overloaded{[](const Segment&) { return false; },
                               [](const auto& arc) { return std::abs(arc.sweep) >= 2 * pi; }},
                    p);
}

std::vector<const Loop*> Region2::loops() const {
  std::vector<const Loop*> all{&outer};
  for (const Loop& h : holes) all.push_back(&h);
  return all;
}

std::size_t Region2::piece_count() const {
  std::size_t n = 0;
  for (const Loop* l : loops()) n += l->pieces.size();
  return n;
}

std::vector<Vec2> outline_of(const Loop& loop, double arc_step) {
  std::vector<Vec2> pts;
  // Vertices equally spaced in the curve's parameter (the angle, the eccentric anomaly).
  const auto add = [&](const auto& arc) {
    const int n = std::max(4, int(std::ceil(std::abs(arc.sweep) / arc_step)));
    for (int i = 0; i < n; ++i) pts.push_back(arc.point_at(arc.start + arc.sweep * i / n));
  };
  for (const auto& p : loop.pieces)
    std::visit(overloaded{[&](const Segment& s) { pts.push_back(s.a); }, add}, p);
  return pts;
}

}  // namespace billiards::geometry
