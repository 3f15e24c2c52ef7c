// Shape files: YAML → Region2.  See docs/shapes.md for the format.
#include "billiards/geometry/shape_file.hpp"

#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/validate.hpp"
#include "billiards/geometry/yaml_reader.hpp"
#include "conic_intersection.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

namespace billiards::geometry {

namespace {

/// Relative tolerance for "this point lies on that curve" and "these curves are tangent": far
/// above rounding of expressions like 2/sqrt(3), far below any deliberate gap.
constexpr double on_curve_tolerance = 1e-9;

using Reader = YamlReader;

/// The curve of a `circle:`/`arc:` (semi-axes (r, r), angle 0) or of an `ellipse:`/
/// `elliptic_arc:`, and the side of it the region lies on.
struct Curve {
  EllipticArc ellipse;  // center, semi_axes, angle
  bool circle;
  bool region_inside;
  SourceRef where;

  double radius() const { return ellipse.semi_axes.x(); }
  double scale() const { return std::max(ellipse.semi_axes.maxCoeff(), ellipse.center.norm()); }
  std::string noun() const { return circle ? "arc" : "elliptic arc"; }
  /// A vector from the centre whose polar angle is the curve's parameter at p (the polar angle,
  /// the eccentric anomaly).
  Vec2 preimage(const Vec2& p) const {
    const Vec2 d = p - ellipse.center;
    if (circle) return d;
    return {ellipse.semi_axes.y() * (std::cos(ellipse.angle) * d.x() + std::sin(ellipse.angle) * d.y()),
            ellipse.semi_axes.x() * (-std::sin(ellipse.angle) * d.x() + std::cos(ellipse.angle) * d.y())};
  }
};

/// One element of a `pieces:` list: a joint point, or the curve of an arc or elliptic arc.
struct Element {
  std::optional<Vec2> point;  // explicit joint
  std::optional<Vec2> near;   // joint = intersection of the neighbouring curves nearest this
  std::optional<Curve> arc;
  SourceRef where;
};

std::string pair_name(const Curve& a, const Curve& b) {
  if (a.circle && b.circle)
    return "the arcs at lines " + std::to_string(a.where.line) + " and " + std::to_string(b.where.line);
  return "the " + a.noun() + " at line " + std::to_string(a.where.line) + " and the " + b.noun() + " at line " +
         std::to_string(b.where.line);
}

/// Meeting point of two consecutive circles: their tangency point, or the intersection
/// nearest `near` when given.
Vec2 circles_joint(const Curve& a, const Curve& b, const std::optional<Vec2>& near) {
  const Vec2 u = b.ellipse.center - a.ellipse.center;
  const double d = u.norm(), ra = a.radius(), rb = b.radius();
  const double tol = on_curve_tolerance * std::max(a.scale(), b.scale());
  const std::string pair = pair_name(a, b);
  if (d <= tol) throw InputError(a.where.file, a.where.line, pair + " are concentric");
  const double outer_gap = d - (ra + rb);          // > 0: apart
  const double inner_gap = std::abs(ra - rb) - d;  // > 0: one inside the other
  if (!near && std::abs(outer_gap) <= tol) return a.ellipse.center + ra * u / d;
  if (!near && std::abs(inner_gap) <= tol)
    return ra > rb ? Vec2(a.ellipse.center + ra * u / d) : Vec2(b.ellipse.center - rb * u / d);
  if (outer_gap > tol || inner_gap > tol)
    throw InputError(a.where.file, b.where.line,
                     pair + " do not meet (gap " + std::to_string(std::max(outer_gap, inner_gap)) +
                         "): the loop is not closed");
  if (!near)
    throw InputError(a.where.file, b.where.line,
                     pair + " cross at two points: put '- point: {near: [x, y]}' between them");
  // Two intersections: foot of the radical line plus/minus h along its normal.
  const double along = (d * d + ra * ra - rb * rb) / (2 * d);
  const double h = std::sqrt(std::max(0.0, ra * ra - along * along));
  const Vec2 foot = a.ellipse.center + along * u / d, perp(-u.y() / d, u.x() / d);
  const Vec2 p = foot + h * perp, q = foot - h * perp;
  return (p - *near).norm() <= (q - *near).norm() ? p : q;
}

/// Meeting point of two consecutive curves, one of them at least an ellipse: their only common
/// point, a tangency; or the common point nearest `near` when given.
Vec2 conics_joint(const Curve& a, const Curve& b, const std::optional<Vec2>& near) {
  const double tol = on_curve_tolerance * std::max(a.scale(), b.scale());
  const Meetings m = meetings(a.ellipse, b.ellipse, tol);
  const std::string pair = pair_name(a, b);
  std::vector<Vec2> all = m.touching;
  all.insert(all.end(), m.crossing.begin(), m.crossing.end());
  if (all.empty()) throw InputError(a.where.file, b.where.line, pair + " do not meet: the loop is not closed");
  if (near)
    return *std::min_element(all.begin(), all.end(),
                             [&](const Vec2& p, const Vec2& q) { return (p - *near).norm() < (q - *near).norm(); });
  if (all.size() == 1 && m.crossing.empty()) return all[0];
  throw InputError(a.where.file, b.where.line,
                   pair + (m.crossing.empty() ? " touch" : " cross or touch") + " at " + std::to_string(all.size()) +
                       " points, not at one tangency point: put '- point: {near: [x, y]}' between them");
}

Vec2 joint_of(const Curve& a, const Curve& b, const std::optional<Vec2>& near) {
  return a.circle && b.circle ? circles_joint(a, b, near) : conics_joint(a, b, near);
}

void require_on_curve(const Vec2& p, const Curve& c, const SourceRef& point_ref) {
  const double off = c.circle ? std::abs((p - c.ellipse.center).norm() - c.radius()) : distance_estimate(c.ellipse, p);
  if (off > on_curve_tolerance * c.scale())
    throw InputError(point_ref.file, point_ref.line,
                     std::string("point is not on the ") + (c.circle ? "circle" : "ellipse") + " of the " + c.noun() +
                         " at line " + std::to_string(c.where.line) + " (off by " + std::to_string(off) + ")");
}

/// The arc of `c`'s curve from `from` to `to` (both on it), counter-clockwise when the region is
/// inside, clockwise otherwise; the whole curve when from == to.
Piece make_arc(const Curve& c, const Vec2& from, const Vec2& to) {
  const Vec2 u0 = c.preimage(from), u1 = c.preimage(to);
  double ccw = std::atan2(cross(u0, u1), u0.dot(u1));  // (−π, π]
  if (ccw <= 0) ccw += 2 * pi;
  if (from == to) ccw = 2 * pi;
  const double start = std::atan2(u0.y(), u0.x());
  const double sweep = c.region_inside ? ccw : -(ccw == 2 * pi ? 2 * pi : 2 * pi - ccw);
  if (c.circle) return Arc{c.ellipse.center, c.radius(), start, sweep, from, to};
  EllipticArc e = c.ellipse;
  e.start = start;
  e.sweep = sweep;
  e.source = from;
  e.target = to;
  return e;
}

Loop full_curve(const Curve& c, bool hole) {
  Piece p = c.circle ? Piece(Arc{c.ellipse.center, c.radius(), 0, 0, {}, {}}) : Piece(c.ellipse);
  std::visit(overloaded{[](Segment&) {},
                        [&](auto& arc) {
                          arc.start = 0;
                          arc.sweep = hole ? -2 * pi : 2 * pi;
                          arc.source = arc.target = arc.point_at(0);
                        }},
             p);
  return Loop{{p}, {c.where}, c.where};
}

class LoopReader {
 public:
  explicit LoopReader(const Reader& r) : r_(r) {}

  Loop read(const YAML::Node& n, bool hole) const {
    const std::string what = hole ? "a hole" : "the boundary";
    r_.expect_keys(n, {"polygon", "circle", "ellipse", "pieces"}, what);
    if (n.size() != 1) r_.fail(n, what + " must be exactly one of: polygon, circle, ellipse, pieces");
    Loop loop = n["polygon"]   ? polygon(n["polygon"], hole)
                : n["circle"]  ? full_curve(circle(n["circle"], !hole), hole)
                : n["ellipse"] ? full_curve(ellipse(n["ellipse"], !hole), hole)
                               : pieces(n["pieces"]);
    loop.origin = r_.ref(n);
    return loop;
  }

 private:
  Curve circle(const YAML::Node& n, bool region_inside, std::initializer_list<const char*> keys = {"center", "radius"},
               const char* what = "a circle") const {
    r_.expect_keys(n, keys, what);
    EllipticArc e;
    e.center = r_.point(r_.required(n, "center", what));
    const double r = r_.positive(r_.required(n, "radius", what), "radius");
    e.semi_axes = {r, r};
    return {e, true, region_inside, r_.ref(n)};
  }

  Curve ellipse(const YAML::Node& n, bool region_inside,
                std::initializer_list<const char*> keys = {"center", "semi_axes", "angle"},
                const char* what = "an ellipse") const {
    r_.expect_keys(n, keys, what);
    EllipticArc e;
    e.center = r_.point(r_.required(n, "center", what));
    const YAML::Node axes = r_.required(n, "semi_axes", what);
    e.semi_axes = r_.point(axes);
    if (!(e.semi_axes.minCoeff() > 0))
      r_.fail(axes, "semi_axes must be positive, got [" + std::to_string(e.semi_axes.x()) + ", " +
                        std::to_string(e.semi_axes.y()) + "]");
    e.angle = n["angle"] ? r_.number(n["angle"]) : 0.0;
    return {e, false, region_inside, r_.ref(n)};
  }

  /// The region's side of an arc's curve.
  bool region_inside(const YAML::Node& n, const std::string& what, const char* curve) const {
    const YAML::Node side = r_.required(n, "side", what);
    const std::string s = side.IsScalar() ? side.Scalar() : "";
    if (s != "inside" && s != "outside")
      r_.fail(side, std::string("side must be 'inside' (region inside the ") + curve + ") or 'outside'");
    return s == "inside";
  }

  Curve arc(const YAML::Node& n) const {
    Curve c = circle(n, true, {"center", "radius", "side"}, "an arc");
    c.region_inside = region_inside(n, "an arc", "circle");
    return c;
  }

  Curve elliptic_arc(const YAML::Node& n) const {
    Curve c = ellipse(n, true, {"center", "semi_axes", "angle", "side"}, "an elliptic arc");
    c.region_inside = region_inside(n, "an elliptic arc", "ellipse");
    return c;
  }

  Loop polygon(const YAML::Node& n, bool hole) const {
    if (!n.IsSequence() || n.size() < 3) r_.fail(n, "a polygon needs at least 3 vertices");
    std::vector<Vec2> v;
    std::vector<SourceRef> where;
    for (const auto& p : n) {
      v.push_back(r_.point(p));
      where.push_back(r_.ref(p));
    }
    Loop loop;
    loop.origin = r_.ref(n);
    for (std::size_t i = 0; i < v.size(); ++i) add_segment(loop, v[i], v[(i + 1) % v.size()], where[i]);
    // Polygons are oriented for the user: region on the left.
    if ((signed_area(loop) < 0) != hole) reverse(loop);
    return loop;
  }

  void add_segment(Loop& loop, const Vec2& a, const Vec2& b, const SourceRef& where) const {
    if (a == b) throw InputError(where.file, where.line, "zero-length segment: repeated point");
    loop.pieces.push_back(Segment{a, b});
    loop.where.push_back(where);
  }

  static void reverse(Loop& loop) {
    std::reverse(loop.pieces.begin(), loop.pieces.end());
    std::reverse(loop.where.begin(), loop.where.end());
    for (Piece& p : loop.pieces) {
      auto& s = std::get<Segment>(p);  // polygons are made of segments only
      std::swap(s.a, s.b);
    }
  }

  Element element(const YAML::Node& n) const {
    r_.expect_keys(n, {"point", "arc", "elliptic_arc"}, "a loop element");
    if (n.size() != 1) r_.fail(n, "a loop element is either '- point: ...', '- arc: ...' or '- elliptic_arc: ...'");
    Element e;
    e.where = r_.ref(n);
    if (n["arc"]) {
      e.arc = arc(n["arc"]);
    } else if (n["elliptic_arc"]) {
      e.arc = elliptic_arc(n["elliptic_arc"]);
    } else if (n["point"].IsMap()) {
      r_.expect_keys(n["point"], {"near"}, "a point");
      e.near = r_.point(r_.required(n["point"], "near", "a point"));
    } else {
      e.point = r_.point(n["point"]);
    }
    return e;
  }

  Loop pieces(const YAML::Node& n) const {
    if (!n.IsSequence() || n.size() == 0) r_.fail(n, "'pieces' must be a non-empty list");
    std::vector<Element> e;
    for (const auto& item : n) e.push_back(element(item));
    Loop loop;
    loop.origin = r_.ref(n);
    const std::size_t m = e.size();
    if (m == 1 && e[0].arc) return full_curve(*e[0].arc, !e[0].arc->region_inside);
    // Resolve every joint: an explicit point, or the meeting point of two consecutive curves.
    std::vector<std::optional<Vec2>> joint_after(m);  // joint between e[i] and e[i+1]
    for (std::size_t i = 0; i < m; ++i) {
      const Element& a = e[i];
      const Element& b = e[(i + 1) % m];
      if (a.arc && b.arc) joint_after[i] = joint_of(*a.arc, *b.arc, std::nullopt);
    }
    std::vector<Vec2> at(m);  // position of each point element
    for (std::size_t i = 0; i < m; ++i) {
      if (e[i].arc) continue;
      if (e[i].point) { at[i] = *e[i].point; continue; }
      const Element& prev = e[(i + m - 1) % m];
      const Element& next = e[(i + 1) % m];
      if (!prev.arc || !next.arc) r_.fail(n[i], "'near' points must stand between two arcs or elliptic arcs");
      at[i] = joint_of(*prev.arc, *next.arc, e[i].near);
    }
    // Walk the cycle; every arc runs from the joint before it to the joint after it, and
    // two consecutive points make a segment.
    for (std::size_t i = 0; i < m; ++i) {
      const std::size_t j = (i + 1) % m, h = (i + m - 1) % m;
      if (e[i].arc) {
        const Vec2 from = e[h].arc ? *joint_after[h] : at[h];
        const Vec2 to = e[j].arc ? *joint_after[i] : at[j];
        if (!e[h].arc) require_on_curve(from, *e[i].arc, e[h].where);
        if (!e[j].arc) require_on_curve(to, *e[i].arc, e[j].where);
        loop.pieces.push_back(make_arc(*e[i].arc, from, to));
        loop.where.push_back(e[i].where);
      } else if (!e[j].arc) {
        add_segment(loop, at[i], at[j], e[i].where);
      }
    }
    if (loop.pieces.size() < 2 && !(loop.pieces.size() == 1 && is_closed_curve(loop.pieces[0])))
      r_.fail(n, "a loop needs at least two pieces");
    return loop;
  }

  const Reader& r_;
};

}  // namespace

Shape parse_shape(const std::string& yaml_text, const std::string& name, const Overrides& overrides) {
  const YAML::Node doc = load_yaml(yaml_text, name);
  Expressions expr;
  Reader r(name, expr);
  Shape shape;
  Region2& region = shape.region;
  region.name = r.shape_header(doc, 2, overrides);
  region.origin = {name, 1};
  shape.parameters = expr.values();
  shape.description = leading_comment(yaml_text);
  const LoopReader loops(r);
  region.outer = loops.read(r.required(doc, "boundary", "a shape file"), false);
  if (const YAML::Node holes = doc["holes"]) {
    if (!holes.IsSequence()) r.fail(holes, "'holes' must be a list");
    for (const auto& h : holes) region.holes.push_back(loops.read(h, true));
  }
  validate(region);
  return shape;
}

Shape load_shape(const std::string& path, const Overrides& overrides) {
  return parse_shape(read_input_file(path, "shape file"), path, overrides);
}

}  // namespace billiards::geometry
