// Shape files: YAML → Region2.  See docs/shapes.md for the format.
#include "billiards/geometry/shape_file.hpp"

#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/validate.hpp"
#include "billiards/geometry/yaml_reader.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <optional>

namespace billiards::geometry {

namespace {

/// Relative tolerance for "this point lies on that circle" and "these circles are tangent":
/// far above rounding of expressions like 2/sqrt(3), far below any deliberate gap.
constexpr double on_curve_tolerance = 1e-9;

using Reader = YamlReader;

struct Circle {
  Vec2 center;
  double radius;
  bool region_inside;
  SourceRef where;
};

/// One element of a `pieces:` list: a joint point, or an arc's circle.
struct Element {
  std::optional<Vec2> point;  // explicit joint
  std::optional<Vec2> near;   // joint = intersection of the neighbouring circles nearest this
  std::optional<Circle> arc;
  SourceRef where;
};

double scale_of(const Circle& a, const Circle& b) {
  return std::max({a.radius, b.radius, a.center.norm(), b.center.norm()});
}

/// Meeting point of two consecutive circles: their tangency point, or the intersection
/// nearest `near` when given.
Vec2 joint_of(const Circle& a, const Circle& b, const std::optional<Vec2>& near) {
  const Vec2 u = b.center - a.center;
  const double d = u.norm();
  const double tol = on_curve_tolerance * scale_of(a, b);
  const std::string pair = "the arcs at lines " + std::to_string(a.where.line) + " and " +
                           std::to_string(b.where.line);
  if (d <= tol) throw InputError(a.where.file, a.where.line, pair + " are concentric");
  const double outer_gap = d - (a.radius + b.radius);        // > 0: apart
  const double inner_gap = std::abs(a.radius - b.radius) - d;  // > 0: one inside the other
  if (!near && std::abs(outer_gap) <= tol) return a.center + a.radius * u / d;
  if (!near && std::abs(inner_gap) <= tol)
    return a.radius > b.radius ? Vec2(a.center + a.radius * u / d) : Vec2(b.center - b.radius * u / d);
  if (outer_gap > tol || inner_gap > tol)
    throw InputError(a.where.file, b.where.line,
                     pair + " do not meet (gap " + std::to_string(std::max(outer_gap, inner_gap)) +
                         "): the loop is not closed");
  if (!near)
    throw InputError(a.where.file, b.where.line,
                     pair + " cross at two points: put '- point: {near: [x, y]}' between them");
  // Two intersections: foot of the radical line plus/minus h along its normal.
  const double along = (d * d + a.radius * a.radius - b.radius * b.radius) / (2 * d);
  const double h = std::sqrt(std::max(0.0, a.radius * a.radius - along * along));
  const Vec2 foot = a.center + along * u / d, perp(-u.y() / d, u.x() / d);
  const Vec2 p = foot + h * perp, q = foot - h * perp;
  return (p - *near).norm() <= (q - *near).norm() ? p : q;
}

void require_on_circle(const Vec2& p, const Circle& c, const SourceRef& point_ref) {
  const double off = std::abs((p - c.center).norm() - c.radius);
  if (off > on_curve_tolerance * std::max(c.radius, c.center.norm()))
    throw InputError(point_ref.file, point_ref.line,
                     "point is not on the circle of the arc at line " + std::to_string(c.where.line) +
                         " (off by " + std::to_string(off) + ")");
}

Arc make_arc(const Circle& c, const Vec2& from, const Vec2& to) {
  const Vec2 u0 = from - c.center, u1 = to - c.center;
  double ccw = std::atan2(cross(u0, u1), u0.dot(u1));  // (−π, π]
  if (ccw <= 0) ccw += 2 * pi;
  if (from == to) ccw = 2 * pi;
  Arc a;
  a.center = c.center;
  a.radius = c.radius;
  a.start = std::atan2(u0.y(), u0.x());
  a.sweep = c.region_inside ? ccw : -(ccw == 2 * pi ? 2 * pi : 2 * pi - ccw);
  a.source = from;
  a.target = to;
  return a;
}

Loop full_circle(const Circle& c, bool hole) {
  Arc a;
  a.center = c.center;
  a.radius = c.radius;
  a.start = 0;
  a.sweep = hole ? -2 * pi : 2 * pi;
  a.source = a.target = a.point_at(0);
  return Loop{{a}, {c.where}, c.where};
}

class LoopReader {
 public:
  explicit LoopReader(const Reader& r) : r_(r) {}

  Loop read(const YAML::Node& n, bool hole) const {
    const std::string what = hole ? "a hole" : "the boundary";
    r_.expect_keys(n, {"polygon", "circle", "pieces"}, what);
    if (n.size() != 1) r_.fail(n, what + " must be exactly one of: polygon, circle, pieces");
    Loop loop = n["polygon"]  ? polygon(n["polygon"], hole)
                : n["circle"] ? full_circle(circle(n["circle"], !hole), hole)
                              : pieces(n["pieces"]);
    loop.origin = r_.ref(n);
    return loop;
  }

 private:
  Circle circle(const YAML::Node& n, bool region_inside) const {
    r_.expect_keys(n, {"center", "radius"}, "a circle");
    return {r_.point(r_.required(n, "center", "a circle")),
            r_.positive(r_.required(n, "radius", "a circle"), "radius"), region_inside, r_.ref(n)};
  }

  Circle arc(const YAML::Node& n) const {
    r_.expect_keys(n, {"center", "radius", "side"}, "an arc");
    Circle c{r_.point(r_.required(n, "center", "an arc")),
             r_.positive(r_.required(n, "radius", "an arc"), "radius"), true, r_.ref(n)};
    const YAML::Node side = r_.required(n, "side", "an arc");
    const std::string s = side.IsScalar() ? side.Scalar() : "";
    if (s != "inside" && s != "outside")
      r_.fail(side, "side must be 'inside' (region inside the circle) or 'outside'");
    c.region_inside = s == "inside";
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
    r_.expect_keys(n, {"point", "arc"}, "a loop element");
    if (n.size() != 1) r_.fail(n, "a loop element is either '- point: ...' or '- arc: ...'");
    Element e;
    e.where = r_.ref(n);
    if (n["arc"]) {
      e.arc = arc(n["arc"]);
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
    if (m == 1 && e[0].arc) return full_circle(*e[0].arc, !e[0].arc->region_inside);
    // Resolve every joint: an explicit point, or the meeting point of two consecutive arcs.
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
      if (!prev.arc || !next.arc) r_.fail(n[i], "'near' points must stand between two arcs");
      at[i] = joint_of(*prev.arc, *next.arc, e[i].near);
    }
    // Walk the cycle; every arc runs from the joint before it to the joint after it, and
    // two consecutive points make a segment.
    for (std::size_t i = 0; i < m; ++i) {
      const std::size_t j = (i + 1) % m, h = (i + m - 1) % m;
      if (e[i].arc) {
        const Vec2 from = e[h].arc ? *joint_after[h] : at[h];
        const Vec2 to = e[j].arc ? *joint_after[i] : at[j];
        if (!e[h].arc) require_on_circle(from, *e[i].arc, e[h].where);
        if (!e[j].arc) require_on_circle(to, *e[i].arc, e[j].where);
        loop.pieces.push_back(make_arc(*e[i].arc, from, to));
        loop.where.push_back(e[i].where);
      } else if (!e[j].arc) {
        add_segment(loop, at[i], at[j], e[i].where);
      }
    }
    if (loop.pieces.size() < 2 && !(loop.pieces.size() == 1 && std::holds_alternative<Arc>(loop.pieces[0])))
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
  if (!doc.IsMap()) throw InputError(name, 1, "a shape file is a YAML mapping");
  r.expect_keys(doc, {"name", "dimension", "parameters", "boundary", "holes"}, "a shape file");
  if (doc["dimension"] && doc["dimension"].as<std::string>() != "2")
    r.fail(doc["dimension"], "only dimension 2 is supported so far");
  if (const YAML::Node params = doc["parameters"]) r.define_parameters(params, overrides);
  if (const auto unknown = expr.unused(overrides); !unknown.empty())
    throw InputError(name, 0, "--set names '" + unknown.front() + "', which is not a parameter of this shape");

  Shape shape;
  shape.parameters = expr.values();
  shape.description = leading_comment(yaml_text);
  Region2& region = shape.region;
  region.origin = {name, 1};
  region.name = doc["name"] ? doc["name"].as<std::string>()
                            : std::filesystem::path(name).stem().string();
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
