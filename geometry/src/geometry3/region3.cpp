// Measures and point location of 3-D regions, and the faces of a convex polyhedron given by
// its half-spaces.
#include "billiards/geometry3/region3.hpp"

#include "billiards/geometry/input_error.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace billiards::geometry3 {

namespace {

/// A face polygon under construction: vertex k is the meeting point of the face's plane with
/// the planes of the edges before and after it; `edge_after[k]` indexes `planes`.
struct Polygon {
  std::vector<Vec3> at;
  std::vector<int> edge_after;
};

/// The point common to three planes (Cramer's rule on n·x = offset, in long double).
Vec3 meet(const Plane& a, const Plane& b, const Plane& c) {
  using V = Eigen::Matrix<long double, 3, 1>;
  const V na = a.normal.cast<long double>(), nb = b.normal.cast<long double>(),
          nc = c.normal.cast<long double>();
  const V bc = nb.cross(nc), ca = nc.cross(na), ab = na.cross(nb);
  return ((a.offset * bc + b.offset * ca + c.offset * ab) / na.dot(bc)).cast<double>();
}

/// Sutherland–Hodgman step: keeps the part of the face (on `planes[face]`) with n·x ≤ offset
/// of `planes[cut]`.  New vertices are recomputed from their three planes, never interpolated,
/// so that faces sharing an edge agree on its ends to rounding.
Polygon clip(const Polygon& p, const std::vector<Plane>& planes, int face, int cut) {
  Polygon out;
  const std::size_t n = p.at.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t next = (k + 1) % n;
    const bool in = planes[cut].beyond(p.at[k]) <= 0, next_in = planes[cut].beyond(p.at[next]) <= 0;
    const int edge = p.edge_after[k];
    if (in) out.at.push_back(p.at[k]), out.edge_after.push_back(edge);
    if (in && !next_in) {  // leaving: the cut becomes the next edge
      out.at.push_back(meet(planes[face], planes[edge], planes[cut]));
      out.edge_after.push_back(cut);
    } else if (!in && next_in) {  // entering: back on the old edge
      out.at.push_back(meet(planes[face], planes[edge], planes[cut]));
      out.edge_after.push_back(edge);
    }
  }
  return out;
}

double polygon_area(const std::vector<Vec3>& f, const Vec3& normal) {
  Vec3 twice = Vec3::Zero();
  for (std::size_t k = 0; k < f.size(); ++k) twice += f[k].cross(f[(k + 1) % f.size()]);
  return 0.5 * twice.dot(normal);
}

struct Accumulator {
  Measures m;
  Accumulator() {
    m.dimension = 3;
    m.boundary_tensor = Eigen::Matrix3d::Zero();
    m.bbox_lo = Vec3::Constant(INFINITY);
    m.bbox_hi = Vec3::Constant(-INFINITY);
  }
  /// A flat piece of wall of area `area` and outward unit normal `n`: its part of ∫ n nᵀ dS.
  void tensor(double area, const Vec3& n) {
    const Eigen::Matrix3d nn = n * n.transpose();  // evaluated first, so exactly symmetric
    m.boundary_tensor += area * nn;
  }
  void extend(const Vec3& p) {
    m.bbox_lo = m.bbox_lo.cwiseMin(p);
    m.bbox_hi = m.bbox_hi.cwiseMax(p);
  }
  /// A sphere: ∫ n nᵀ dS = (4πr²/3) I by symmetry; `sign` is +1 for the outer wall, −1 for a hole.
  void sphere(const Ball& b, int sign) {
    const double r = b.radius, pi = geometry::pi;
    m.volume += sign * 4 * pi * r * r * r / 3;
    m.surface += 4 * pi * r * r;
    m.boundary_tensor += (4 * pi * r * r / 3) * Eigen::Matrix3d::Identity();
  }
};

void add_outer(Accumulator& acc, const ConvexPolyhedron& p) {
  for (std::size_t i = 0; i < p.planes.size(); ++i) {
    const double area = polygon_area(p.faces[i], p.planes[i].normal);
    acc.m.surface += area;
    acc.tensor(area, p.planes[i].normal);
    acc.m.volume += p.planes[i].offset * area / 3;  // cone from the origin over the face
    for (const Vec3& v : p.faces[i]) acc.extend(v);
  }
}

void add_outer(Accumulator& acc, const TriangleMesh& mesh) {
  acc.m.volume += mesh.locator->volume();
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Vec3 twice = (b - a).cross(c - a);
    acc.tensor(0.5 * twice.norm(), twice.normalized());
  }
  acc.m.surface += mesh.locator->area();
  for (const Vec3& v : mesh.vertices) acc.extend(v);
}

void add_outer(Accumulator& acc, const Ball& b) {
  acc.sphere(b, +1);
  acc.extend(b.center - Vec3::Constant(b.radius));
  acc.extend(b.center + Vec3::Constant(b.radius));
}

}  // namespace

std::vector<std::vector<Vec3>> convex_faces(const std::vector<Plane>& given, const SourceRef& where) {
  double scale = 1;
  for (const Plane& p : given) scale = std::max(scale, std::abs(p.offset));
  const double far = 1e6 * scale;  // "infinitely" far for any sensible polyhedron
  for (std::size_t i = 0; i < given.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if ((given[i].normal - given[j].normal).norm() <= 1e-12 && std::abs(given[i].offset - given[j].offset) <= 1e-12 * scale)
        throw InputError(given[i].where.file, given[i].where.line,
                         "this plane repeats the plane at line " + std::to_string(given[j].where.line));
  std::vector<std::vector<Vec3>> faces;
  for (int i = 0; i < int(given.size()); ++i) {
    // Start from a huge square on plane i, bounded by four extra planes, and clip.
    std::vector<Plane> planes = given;
    const Vec3 n = given[i].normal;
    const Vec3 u = n.unitOrthogonal(), w = n.cross(u);
    const int box = int(planes.size());
    for (const Vec3& d : {u, w, Vec3(-u), Vec3(-w)}) planes.push_back({d, far, where});
    Polygon poly;
    for (int k = 0; k < 4; ++k) {
      poly.at.push_back(meet(planes[i], planes[box + k], planes[box + (k + 1) % 4]));
      poly.edge_after.push_back(box + (k + 1) % 4);
    }
    for (int j = 0; j < int(given.size()) && poly.at.size() >= 3; ++j)
      if (j != i) poly = clip(poly, planes, i, j);
    const auto& ref = given[i].where;
    if (poly.at.size() < 3 || polygon_area(poly.at, n) <= 1e-12 * scale * scale)
      throw InputError(ref.file, ref.line, "this plane does not bound the polyhedron (redundant, or the region is empty)");
    for (int e : poly.edge_after)
      if (e >= box) throw InputError(ref.file, ref.line, "the polyhedron is unbounded beyond this plane's face");
    faces.push_back(poly.at);
  }
  return faces;
}

Measures measures_of(const Region3& region) {
  Accumulator acc;
  std::visit([&](const auto& outer) { add_outer(acc, outer); }, region.outer);
  for (const Ball& b : region.holes) acc.sphere(b, -1);
  return acc.m;
}

bool contains(const Region3& region, const Vec3& x) {
  for (const Ball& b : region.holes)
    if ((x - b.center).squaredNorm() < b.radius * b.radius) return false;
  if (const auto* p = std::get_if<ConvexPolyhedron>(&region.outer)) {
    for (const Plane& pl : p->planes)
      if (pl.beyond(x) > 0) return false;
    return true;
  }
  if (const auto* b = std::get_if<Ball>(&region.outer))
    return (x - b->center).squaredNorm() <= b->radius * b->radius;
  return std::get<TriangleMesh>(region.outer).locator->inside(x);
}

}  // namespace billiards::geometry3
