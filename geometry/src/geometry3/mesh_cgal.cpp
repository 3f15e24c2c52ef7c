// Triangle meshes through CGAL: reading OFF/OBJ/STL, validation with Polygon_mesh_processing,
// point location and distances with an AABB tree, volume and area.  The only translation unit
// of geometry3 that sees CGAL (it needs -frounding-math and compiles slowly).
#include "billiards/geometry3/region3.hpp"

#include "billiards/geometry/expression.hpp"
#include "billiards/geometry/input_error.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/OFF/File_header_extended_OFF.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/boost/graph/helpers.h>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <queue>
#include <set>
#include <string_view>
#include <variant>

namespace billiards::geometry3 {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Polygons = std::vector<std::vector<std::size_t>>;
namespace PMP = CGAL::Polygon_mesh_processing;

/// Why a polygon soup is not an oriented manifold surface, naming the faces (0-based, as in
/// the file).
std::string why_not_manifold(const Polygons& polygons) {
  std::map<std::pair<std::size_t, std::size_t>, std::vector<std::size_t>> directed;
  std::map<std::pair<std::size_t, std::size_t>, int> undirected;
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    const auto& p = polygons[f];
    for (std::size_t k = 0; k < p.size(); ++k) {
      const std::size_t a = p[k], b = p[(k + 1) % p.size()];
      directed[{a, b}].push_back(f);
      ++undirected[{std::min(a, b), std::max(a, b)}];
    }
  }
  for (const auto& [e, n] : undirected)
    if (n > 2)
      return "not manifold: the edge between vertices " + std::to_string(e.first) + " and " +
             std::to_string(e.second) + " is shared by " + std::to_string(n) + " faces";
  for (const auto& [e, faces] : directed)
    if (faces.size() > 1)
      return "faces " + std::to_string(faces[0]) + " and " + std::to_string(faces[1]) +
             " are inconsistently oriented (both run from vertex " + std::to_string(e.first) +
             " to " + std::to_string(e.second) + ")";
  return "not manifold: a vertex joins two sheets of the surface";
}

/// A polygon's vertices seen along the axis nearest its normal (Newell's): dropping a
/// coordinate is exact, so what the exact predicates decide of the projection holds of the
/// file's numbers.
CGAL::Polygon_2<K> projected(const std::vector<Point>& points, const std::vector<std::size_t>& face) {
  Vec3 normal = Vec3::Zero();
  for (std::size_t k = 0; k < face.size(); ++k) {
    const Point &a = points[face[k]], &b = points[face[(k + 1) % face.size()]];
    normal += Vec3((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()), (a.x() - b.x()) * (a.y() + b.y()));
  }
  int drop = 0;
  normal.cwiseAbs().maxCoeff(&drop);
  CGAL::Polygon_2<K> out;
  for (const std::size_t v : face) {
    const Point& p = points[v];
    out.push_back(K::Point_2(p[(drop + 1) % 3], p[(drop + 2) % 3]));
  }
  return out;
}

/// The triangles of a face of more than three vertices, each turning as the face does: the
/// constrained Delaunay triangulation of its projection (`projected`) with its edges as
/// constraints, the triangles inside them; nothing when the projection is not a simple
/// polygon (the face crosses itself, repeats a vertex, or is flat seen along its normal).
/// (Not CGAL's triangulate_faces: given a face that crosses itself, it dereferences a null
/// pointer.)
std::optional<Polygons> triangles_of(const std::vector<Point>& points, const std::vector<std::size_t>& face) {
  const CGAL::Polygon_2<K> polygon = projected(points, face);
  if (!polygon.is_simple()) return std::nullopt;
  using Vertex = CGAL::Triangulation_vertex_base_with_info_2<std::size_t, K>;
  using Tds = CGAL::Triangulation_data_structure_2<Vertex, CGAL::Constrained_triangulation_face_base_2<K>>;
  using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::No_constraint_intersection_tag>;
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> corner;
  for (std::size_t k = 0; k < face.size(); ++k) {
    corner.push_back(cdt.insert(polygon[int(k)]));
    corner.back()->info() = face[k];
  }
  for (std::size_t k = 0; k < face.size(); ++k) cdt.insert_constraint(corner[k], corner[(k + 1) % face.size()]);
  // Outside: the faces reached from the infinite one without crossing a constraint.
  std::set<Cdt::Face_handle> outside{cdt.infinite_face()};
  std::queue<Cdt::Face_handle> reached;
  reached.push(cdt.infinite_face());
  for (; !reached.empty(); reached.pop())
    for (int i = 0; i < 3; ++i) {
      const Cdt::Face_handle next = reached.front()->neighbor(i);
      if (!cdt.is_constrained({reached.front(), i}) && outside.insert(next).second) reached.push(next);
    }
  const bool reversed = polygon.orientation() == CGAL::CLOCKWISE;  // (the triangulation's faces turn counter-clockwise)
  Polygons out;
  for (const Cdt::Face_handle f : cdt.finite_face_handles())
    if (!outside.count(f)) {
      out.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
      if (reversed) std::swap(out.back()[1], out.back()[2]);
    }
  return out;
}

/// The faces as triangles (`triangles_of`), or the number of the first that cannot be.
std::variant<Polygons, std::size_t> triangulated(const std::vector<Point>& points, const Polygons& faces) {
  Polygons out;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (faces[f].size() == 3) {
      out.push_back(faces[f]);
      continue;
    }
    const auto triangles = triangles_of(points, faces[f]);
    if (!triangles) return f;
    out.insert(out.end(), triangles->begin(), triangles->end());
  }
  return out;
}

Mesh to_cgal(const TriangleMesh& m) {
  Mesh mesh;
  std::vector<Mesh::Vertex_index> v;
  for (const Vec3& p : m.vertices) v.push_back(mesh.add_vertex(Point(p.x(), p.y(), p.z())));
  for (const auto& t : m.triangles) mesh.add_face(v[t[0]], v[t[1]], v[t[2]]);
  return mesh;
}

TriangleMesh from_cgal(const Mesh& mesh) {
  TriangleMesh out;
  std::map<Mesh::Vertex_index, int> index;
  for (auto v : mesh.vertices()) {
    index[v] = int(out.vertices.size());
    const Point& p = mesh.point(v);
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : mesh.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) t[k++] = index[v];
    out.triangles.push_back(t);
  }
  return out;
}

}  // namespace

struct MeshLocator::Impl {
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_face_graph_triangle_primitive<Mesh>>>;
  Mesh mesh;
  Tree tree;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh, K>> side;

  explicit Impl(Mesh m) : mesh(std::move(m)), tree(faces(mesh).first, faces(mesh).second, mesh) {
    tree.accelerate_distance_queries();
    side = std::make_unique<CGAL::Side_of_triangle_mesh<Mesh, K>>(tree);
  }
};

MeshLocator::MeshLocator(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>(to_cgal(mesh))) {}
MeshLocator::~MeshLocator() = default;

bool MeshLocator::inside(const Vec3& x) const {
  return (*impl_->side)(Point(x.x(), x.y(), x.z())) != CGAL::ON_UNBOUNDED_SIDE;
}
double MeshLocator::distance(const Vec3& x) const {
  return std::sqrt(impl_->tree.squared_distance(Point(x.x(), x.y(), x.z())));
}
double MeshLocator::volume() const { return PMP::volume(impl_->mesh); }
double MeshLocator::area() const { return PMP::area(impl_->mesh); }

/// The polygon soup as a closed, outward-oriented, non-self-intersecting triangle mesh, or
/// `fail`'s error.
template <class Fail>
TriangleMesh checked_mesh(const std::string& path, const std::vector<Point>& points, const Polygons& polygons,
                          const Fail& fail) {
  const auto soup = triangulated(points, polygons);
  if (const auto* f = std::get_if<std::size_t>(&soup))
    return fail("face " + std::to_string(*f) +
                " (counting from 0) cannot be triangulated: seen along its normal, it crosses itself, repeats a vertex or is flat");
  const Polygons& triangles = std::get<Polygons>(soup);
  // A diagonal of a face may be an edge the surface has already (with no face cut, the soup
  // is the one read_mesh has checked).
  if (triangles.size() != polygons.size() && !PMP::is_polygon_soup_a_polygon_mesh(triangles))
    return fail("with its faces triangulated, " + why_not_manifold(triangles));
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, triangles, mesh);
  if (!CGAL::is_valid_polygon_mesh(mesh)) return fail("not a valid surface: its faces do not join into one");
  if (!CGAL::is_closed(mesh)) return fail("not closed (it has boundary edges): it does not bound a region");
  for (auto f : mesh.faces())
    if (PMP::is_degenerate_triangle_face(f, mesh))
      return fail("face " + std::to_string(std::size_t(f)) + " is degenerate (zero area)");
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> crossing;
  PMP::self_intersections(mesh, std::back_inserter(crossing));
  if (!crossing.empty())
    return fail("self-intersecting: faces " + std::to_string(std::size_t(crossing[0].first)) + " and " +
                std::to_string(std::size_t(crossing[0].second)) + " intersect (" +
                std::to_string(crossing.size()) + " pairs)");
  if (!PMP::is_outward_oriented(mesh))
    return fail("inward oriented: list each face counter-clockwise seen from outside");
  // is_outward_oriented looks at the outermost component only; a cavity must face inward.
  if (!PMP::does_bound_a_volume(mesh))
    return fail("a nested component is oriented like its enclosing one (a cavity's faces must point into the cavity)");
  TriangleMesh out = from_cgal(mesh);
  out.file = path;
  out.locator = std::make_shared<const MeshLocator>(out);
  return out;
}

/// Why an OFF file cannot be read safely, if it cannot: vertex colours (COFF), binary OFF, or
/// counts beyond what its `size` bytes can hold, in its header (vertices and faces: ≥ 5 bytes a
/// vertex and 7 a face as text, "0 0 0" and "3 0 1 2" with separators; edges: ≥ 2 bytes each,
/// an index in a face) or in a face (≥ 2 bytes an index).  The header is read as CGAL's scanner
/// reads it (File_header_OFF's operator>>: its comment skipping, its keyword with the prefixes
/// ST, C, N, 4, n, then `int`s from the stream), so that the counts checked are the ones it
/// takes (fuzz findings: counts after a comment, or followed by a control character, went
/// unchecked when the header was read otherwise); a header it refuses is left to it.
std::optional<std::string> off_problem(std::istream& in, double size) {
  char c;
  // A keyword as CGAL scans it: c, then the letters and digits that follow (41 characters at
  // most), the character after them consumed.
  const auto word_from = [&](char first) {
    std::string word(1, first);
    while (word.size() < 41 && in.get(c) && std::isalnum(static_cast<unsigned char>(c))) word += c;
    return word;
  };
  while ((in >> c) && c == '#') in >> CGAL::skip_until_EOL;
  if (!in) return std::nullopt;
  const std::string keyword = word_from(c);
  const auto off = keyword.find("OFF");
  if (off == std::string::npos) return std::nullopt;
  const std::string prefix = keyword.substr(0, off);
  // CGAL's scanner of vertex colours (COFF) reads past its buffer on malformed colours (a fuzz
  // finding); a billiard has no use for colours.
  if (prefix.find('C') != std::string::npos)
    return "coloured OFF (" + keyword + ") is not read: list the vertices without colours (OFF)";
  in >> CGAL::skip_comment_OFF >> c;
  if (!in) return std::nullopt;
  if (!std::isdigit(static_cast<unsigned char>(c))) {
    // Binary OFF: CGAL's reader computes with its counts unchecked (twice the edges overflow an
    // int: a fuzz finding); a mesh is as well written as text.
    if (word_from(c) == "BINARY") return "binary OFF is not read: write the mesh as text (OFF or OBJ), or as STL";
    return std::nullopt;
  }
  in.putback(c);
  int vertices = 0, faces = 0, edges = 0;
  in >> vertices;
  if (prefix.find('n') != std::string::npos) in >> vertices;  // nOFF: that was the dimension
  in >> faces >> edges;
  if (!in) return std::nullopt;
  if (!(vertices >= 0 && faces >= 0 && 5.0 * vertices + 7.0 * faces <= size))
    return fmt::format("its header announces {:g} vertices and {:g} faces, more than its {:g} bytes can hold",
                       double(vertices), double(faces), size);
  // (CGAL doubles the edges in an int.)
  if (!(edges >= 0 && edges <= std::numeric_limits<int>::max() / 2 && 2.0 * edges <= size))
    return fmt::format("its header announces {:g} edges, more than its {:g} bytes can hold", double(edges), size);
  std::string token;
  const auto next = [&]() -> bool {  // (a '#' starts a comment to the end of the line)
    while (in >> token) {
      const auto hash = token.find('#');
      if (hash == std::string::npos) return true;
      in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
      token.resize(hash);
      if (!token.empty()) return true;
    }
    return false;
  };
  std::string line;
  for (double v = 0; v < vertices && std::getline(in >> std::ws, line);)
    if (line[0] != '#') ++v;
  for (double f = 0; f < faces && next(); ++f) {
    in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    const double corners = std::strtod(token.c_str(), nullptr);
    if (!(2 * corners <= size))
      return fmt::format("face {:g} announces {} vertices, more than its {:g} bytes can hold", f, token, size);
  }
  return std::nullopt;
}

/// Refuses a file CGAL's readers would mishandle: counts announcing more vertices, faces or
/// triangles than its size can hold (OFF: above; binary STL: 50 bytes a triangle), which they
/// reserve before reading, and OFF's vertex colours and binary form.
std::optional<std::string> unreadable_safely(const std::string& path, const std::string& ext) {
  const double size = double(std::filesystem::file_size(path));
  std::ifstream in(path, std::ios::binary);
  if (ext == ".off") return off_problem(in, size);
  if (ext == ".stl" && size >= 84) {
    char head[84];
    in.read(head, 84);
    if (std::string_view(head, 5) != "solid") {  // binary: a count of triangles at byte 80
      std::uint32_t n;
      std::memcpy(&n, head + 80, 4);
      if (84 + 50 * double(n) > size)
        return fmt::format("its binary header announces {} triangles, more than its {:g} bytes can hold", n, size);
    }
  }
  return std::nullopt;
}

TriangleMesh read_mesh(const std::string& path, const SourceRef& where) {
  const auto fail = [&](const std::string& msg) -> TriangleMesh {
    throw InputError(where.file, where.line, "mesh " + path + ": " + msg);
  };
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext != ".off" && ext != ".obj" && ext != ".stl") return fail("expected a .off, .obj or .stl file");
  if (!std::filesystem::is_regular_file(path)) return fail("cannot open the file");
  if (const auto why = unreadable_safely(path, ext)) return fail(*why);
  std::vector<Point> points;
  Polygons polygons;
  bool read = false;
  try {  // CGAL's readers size their lists by the counts in the file, however absurd
    read = CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false));
  } catch (const std::length_error&) {
  } catch (const std::bad_alloc&) {
  }
  if (!read || polygons.empty()) return fail("cannot read it as " + ext.substr(1) + " (or it has no faces)");
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    if (polygons[f].size() < 3) return fail("a face has fewer than 3 vertices");
    for (const std::size_t v : polygons[f])
      if (v >= points.size())
        return fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(v) + " (counting from 0), but there are " +
                    std::to_string(points.size()) + " vertices");
  }
  for (const Point& p : points)
    for (int k = 0; k < 3; ++k)
      if (!(std::abs(p[k]) <= Expressions::max_magnitude))
        return fail("a vertex coordinate is not a number within ±1e30");
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) return fail(why_not_manifold(polygons));
  // CGAL checks its preconditions by throwing: on a surface it cannot process (a degenerate
  // face, an invalid connectivity) that is this file's fault, reported as such.
  try {
    return checked_mesh(path, points, polygons, fail);
  } catch (const CGAL::Failure_exception&) {
    return fail("not a valid surface: a face is degenerate (repeated or collinear vertices) or faces meet badly");
  }
}

}  // namespace billiards::geometry3
