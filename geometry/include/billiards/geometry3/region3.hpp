// 3-D billiard regions: a convex polyhedron (half-spaces), a closed triangle mesh or a sphere,
// minus disjoint balls (scatterers).
//
// Convention: every normal is the OUTWARD normal of the region (pointing into the wall), and
// mesh triangles are listed counter-clockwise seen from outside.
#pragma once

#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/pieces.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

#include <array>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace billiards::geometry3 {

using Vec3 = Eigen::Vector3d;
using geometry::Measures;
using geometry::SourceRef;

/// The half-space n·x ≤ offset, with |n| = 1 (n is the outward normal of the face it bounds).
struct Plane {
  Vec3 normal;
  double offset = 0;
  SourceRef where;
  double beyond(const Vec3& x) const { return normal.dot(x) - offset; }
};

/// A bounded intersection of half-spaces.  `faces[i]` is the convex polygon the region has
/// on `planes[i]` (counter-clockwise seen from outside), computed when the file is read.
struct ConvexPolyhedron {
  std::vector<Plane> planes;
  std::vector<std::vector<Vec3>> faces;
};

class MeshLocator;

/// A closed, manifold, outward-oriented triangle mesh without self-intersections.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::string file;  // the mesh file it was read from
  std::shared_ptr<const MeshLocator> locator;
};

/// A ball; as the outer wall the region is inside it, as a hole the region is outside it.
struct Ball {
  Vec3 center;
  double radius = 0;
  SourceRef where;
};

using Boundary3 = std::variant<ConvexPolyhedron, TriangleMesh, Ball>;

struct Region3 {
  std::string name;
  SourceRef origin;
  Boundary3 outer;
  std::vector<Ball> holes;
};

/// V, S, ∫ n nᵀ dS (3×3) and the bounding box: closed forms for planes and balls (V of a
/// polyhedron as ⅓ Σ offset·area), CGAL's PMP volume and area for meshes.
Measures measures_of(const Region3& region);
/// Is x in the closed region?  (Meshes: CGAL's Side_of_triangle_mesh, exact predicates.)
bool contains(const Region3& region, const Vec3& x);
/// The faces of the bounded intersection of the half-spaces; throws InputError (at the
/// plane's line) for a plane that does not bound the region, and when it is unbounded or empty.
std::vector<std::vector<Vec3>> convex_faces(const std::vector<Plane>& planes, const SourceRef& where);

/// CGAL's view of a validated mesh: point location and distance (AABB tree), and PMP's
/// volume and area.
class MeshLocator {
 public:
  explicit MeshLocator(const TriangleMesh& mesh);
  ~MeshLocator();
  bool inside(const Vec3& x) const;  // closed: points on the surface count as inside
  double distance(const Vec3& x) const;
  double volume() const;
  double area() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Reads an OFF/OBJ/STL file (by extension) and validates it: triangles (polygons are
/// triangulated), no degenerate face, manifold, closed, free of self-intersections, outward
/// oriented.  Errors are InputErrors at `where` (the shape file's `mesh:` line) naming the file.
TriangleMesh read_mesh(const std::string& path, const SourceRef& where);

}  // namespace billiards::geometry3
