// 3-D shape files: YAML → Region3.  See docs/3d.md for the format.
#include "billiards/geometry3/shape3_file.hpp"

#include "billiards/geometry/yaml_reader.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>

namespace billiards::geometry3 {

namespace {

class Reader3 {
 public:
  Reader3(const YamlReader& r, std::filesystem::path folder) : r_(r), folder_(std::move(folder)) {}

  Boundary3 boundary(const YAML::Node& n) const {
    r_.expect_keys(n, {"box", "polyhedron", "sphere", "mesh"}, "the boundary");
    if (n.size() != 1) r_.fail(n, "the boundary must be exactly one of: box, polyhedron, sphere, mesh");
    if (n["sphere"]) return ball(n["sphere"]);
    if (n["mesh"]) return mesh(n["mesh"]);
    ConvexPolyhedron p;
    p.planes = n["box"] ? box(n["box"]) : half_spaces(n["polyhedron"]);
    p.faces = convex_faces(p.planes, r_.ref(n));
    return p;
  }

  Ball ball(const YAML::Node& n) const {
    r_.expect_keys(n, {"center", "radius"}, "a sphere");
    return {vec(r_.required(n, "center", "a sphere")),
            r_.positive(r_.required(n, "radius", "a sphere"), "radius"), r_.ref(n)};
  }

 private:
  Vec3 vec(const YAML::Node& n) const { return r_.vector(n, 3); }

  std::vector<Plane> box(const YAML::Node& n) const {
    r_.expect_keys(n, {"min", "max"}, "a box");
    const Vec3 lo = vec(r_.required(n, "min", "a box")), hi = vec(r_.required(n, "max", "a box"));
    if (!(lo.array() < hi.array()).all()) r_.fail(n, "a box needs min < max in every coordinate");
    std::vector<Plane> planes;
    for (int k = 0; k < 3; ++k) {
      planes.push_back({Vec3::Unit(k), hi[k], r_.ref(n)});
      planes.push_back({-Vec3::Unit(k), -lo[k], r_.ref(n)});
    }
    return planes;
  }

  std::vector<Plane> half_spaces(const YAML::Node& n) const {
    if (!n.IsSequence() || n.size() < 4) r_.fail(n, "a polyhedron needs at least 4 half-spaces");
    std::vector<Plane> planes;
    for (const auto& h : n) {
      r_.expect_keys(h, {"normal", "offset"}, "a half-space (normal . x <= offset)");
      const Vec3 normal = vec(r_.required(h, "normal", "a half-space"));
      if (!(normal.norm() > 0)) r_.fail(h, "the normal must not be zero");
      const double scale = normal.norm();
      planes.push_back({normal / scale, r_.number(r_.required(h, "offset", "a half-space")) / scale, r_.ref(h)});
    }
    return planes;
  }

  TriangleMesh mesh(const YAML::Node& n) const {
    if (!n.IsScalar()) r_.fail(n, "'mesh' is the path of an OFF, OBJ or STL file");
    return read_mesh((folder_ / n.Scalar()).lexically_normal().string(), r_.ref(n));
  }

  const YamlReader& r_;
  std::filesystem::path folder_;
};

/// Why ball `b` does not lie strictly inside the outer wall, or "" if it does.
std::string outside_wall(const Ball& b, const Boundary3& outer) {
  if (const auto* p = std::get_if<ConvexPolyhedron>(&outer)) {
    for (const Plane& pl : p->planes)
      if (!(pl.beyond(b.center) + b.radius < 0))
        return "crosses or touches the plane at line " + std::to_string(pl.where.line);
    return "";
  }
  if (const auto* s = std::get_if<Ball>(&outer))
    return (b.center - s->center).norm() + b.radius < s->radius ? "" : "crosses or touches the outer sphere";
  const auto& locator = *std::get<TriangleMesh>(outer).locator;
  return locator.inside(b.center) && locator.distance(b.center) > b.radius ? ""
                                                                         : "is not strictly inside the mesh";
}

void validate_holes(const Region3& region) {
  for (std::size_t i = 0; i < region.holes.size(); ++i) {
    const Ball& b = region.holes[i];
    if (const auto why = outside_wall(b, region.outer); !why.empty())
      throw InputError(b.where.file, b.where.line, "this ball " + why);
    for (std::size_t j = 0; j < i; ++j)
      if (!((b.center - region.holes[j].center).norm() > b.radius + region.holes[j].radius))
        throw InputError(b.where.file, b.where.line,
                         "this ball overlaps or touches the ball at line " + std::to_string(region.holes[j].where.line));
  }
}

}  // namespace

Shape3 parse_shape3(const std::string& yaml_text, const std::string& name, const Overrides& overrides,
                    const std::string& mesh_dir) {
  const YAML::Node doc = load_yaml(yaml_text, name);
  Expressions expr;
  YamlReader r(name, expr);
  Shape3 shape;
  Region3& region = shape.region;
  region.name = r.shape_header(doc, 3, overrides);
  region.origin = {name, 1};
  shape.parameters = expr.values();
  shape.description = leading_comment(yaml_text);
  const Reader3 reader(r, mesh_dir.empty() ? std::filesystem::path(name).parent_path() : std::filesystem::path(mesh_dir));
  region.outer = reader.boundary(r.required(doc, "boundary", "a shape file"));
  if (const YAML::Node holes = doc["holes"]) {
    if (!holes.IsSequence()) r.fail(holes, "'holes' must be a list");
    for (const auto& h : holes) {
      r.expect_keys(h, {"ball"}, "a hole");
      region.holes.push_back(reader.ball(r.required(h, "ball", "a hole")));
    }
  }
  validate_holes(region);
  return shape;
}

Shape3 load_shape3(const std::string& path, const Overrides& overrides) {
  return parse_shape3(read_input_file(path, "shape file"), path, overrides);
}

int shape_dimension(const std::string& path) { return parse_shape_dimension(read_input_file(path, "shape file"), path); }

int parse_shape_dimension(const std::string& yaml_text, const std::string& name) {
  const YAML::Node doc = load_yaml(yaml_text, name);
  if (!doc.IsMap() || !doc["dimension"]) return 2;
  const YAML::Node d = doc["dimension"];
  if (d.IsScalar() && (d.Scalar() == "2" || d.Scalar() == "3")) return std::stoi(d.Scalar());
  throw InputError(name, d.Mark().line + 1, "'dimension' must be 2 or 3");
}

}  // namespace billiards::geometry3
