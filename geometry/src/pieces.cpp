#include "billiards/geometry/pieces.hpp"

#include <algorithm>
#include <cmath>

namespace billiards::geometry {

namespace {
template <class... F>
struct overloaded : F... { using F::operator()...; };
template <class... F>
overloaded(F...) -> overloaded<F...>;
}  // namespace

std::string SourceRef::describe() const {
  if (file.empty()) return "<built in code>";
  return line > 0 ? file + ":" + std::to_string(line) : file;
}

Vec2 Arc::point_at(double angle) const {
  return center + radius * Vec2(std::cos(angle), std::sin(angle));
}

Vec2 source_of(const Piece& p) {
  return std::visit(overloaded{[](const Segment& s) { return s.a; },
                               [](const Arc& a) { return a.source; }},
                    p);
}

Vec2 target_of(const Piece& p) {
  return std::visit(overloaded{[](const Segment& s) { return s.b; },
                               [](const Arc& a) { return a.target; }},
                    p);
}

double length_of(const Piece& p) {
  return std::visit(overloaded{[](const Segment& s) { return (s.b - s.a).norm(); },
                               [](const Arc& a) { return a.radius * std::abs(a.sweep); }},
                    p);
}

double curvature_of(const Piece& p) {
  return std::visit(overloaded{[](const Segment&) { return 0.0; },
                               [](const Arc& a) { return a.curvature(); }},
                    p);
}

Vec2 outward_normal(const Piece& p, const Vec2& on_piece) {
  return std::visit(overloaded{[](const Segment& s) {
                                 const Vec2 d = (s.b - s.a).normalized();
                                 return Vec2(d.y(), -d.x());  // right of travel
                               },
                               [&](const Arc& a) {
                                 const Vec2 u = (on_piece - a.center).normalized();
                                 return a.focusing() ? u : Vec2(-u);
                               }},
                    p);
}

Vec2 point_along(const Piece& p, double u) {
  return std::visit(overloaded{[&](const Segment& s) { return Vec2(s.a + u * (s.b - s.a)); },
                               [&](const Arc& a) { return a.point_at(a.start + u * a.sweep); }},
                    p);
}

const char* kind_of(const Piece& p) { return std::holds_alternative<Segment>(p) ? "segment" : "arc"; }

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
  for (const auto& p : loop.pieces) {
    const auto* arc = std::get_if<Arc>(&p);
    const int n = arc ? std::max(4, int(std::ceil(std::abs(arc->sweep) / arc_step))) : 1;
    for (int i = 0; i < n; ++i) pts.push_back(point_along(p, double(i) / n));
  }
  return pts;
}

}  // namespace billiards::geometry
