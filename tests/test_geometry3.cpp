// 3-D shapes: exact measures of every bundled shape against closed forms (or Monte Carlo and
// independent sums for the 1e5-triangle mesh), and every kind of invalid input rejected with
// its file, line and reason.
#include "cli_helpers.hpp"

#include "billiards/dynamics/random.hpp"
#include "billiards/geometry/input_error.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

using namespace billiards;
using namespace billiards::geometry3;
using geometry::pi;

namespace {

const std::string shapes3 = BILLIARDS_SOURCE_DIR "/shapes/3d/";

Measures measures(const std::string& name, const Overrides& set = {}) {
  return measures_of(load_shape3(shapes3 + name + ".yaml", set).region);
}

bool close(double a, double b, double rel = 1e-14) { return std::abs(a - b) <= rel * std::abs(b); }

void check(const Measures& m, double V, double S, const Eigen::Matrix3d& T, double rel = 1e-14) {
  CHECK(m.dimension == 3);
  CHECK(close(m.volume, V, rel));
  CHECK(close(m.surface, S, rel));
  CHECK((m.boundary_tensor - T).norm() <= rel * T.norm());
  CHECK(close(geometry::mean_free_path(m), 4 * V / S, rel));
}

const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();

}  // namespace

TEST_CASE("closed forms of the bundled 3-D shapes") {
  check(measures("cube"), 1, 6, 2 * I);
  check(measures("cube", {{"L", "3"}}), 27, 54, 18 * I);
  check(measures("ball"), 4 * pi / 3, 4 * pi, 4 * pi / 3 * I);
  const double R = 0.25;
  check(measures("sinai3"), 1 - 4 * pi * R * R * R / 3, 6 + 4 * pi * R * R, (2 + 4 * pi * R * R / 3) * I);
  // Octahedron |x|+|y|+|z| ≤ 1 from its 8 half-spaces: the faces are computed by clipping.
  check(measures("octahedron"), 4.0 / 3, 4 * std::sqrt(3.0), 4 * std::sqrt(3.0) / 3 * I);
  // L-prism from an OFF file with non-convex hexagonal faces (triangulated when read).
  check(measures("l-prism"), 6, 22, Eigen::Vector3d(8, 8, 6).asDiagonal().toDenseMatrix());
  const auto b = measures("l-prism");
  CHECK(b.bbox_lo == Eigen::Vector3d(0, 0, 0));
  CHECK(b.bbox_hi == Eigen::Vector3d(2, 2, 2));
}

TEST_CASE("the 1e5-triangle mesh: CGAL's V and S against independent sums and Monte Carlo") {
  const auto shape = load_shape3(shapes3 + "bumpy-100k.yaml");
  const auto& mesh = std::get<TriangleMesh>(shape.region.outer);
  REQUIRE(mesh.triangles.size() == 100820);
  const auto m = measures_of(shape.region);
  // Divergence theorem (V = Σ a·(b×c)/6) and Σ |(b−a)×(c−a)|/2, computed here.
  double V = 0, S = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    V += a.dot(b.cross(c)) / 6;
    S += (b - a).cross(c - a).norm() / 2;
  }
  CHECK(close(m.volume, V, 1e-12));
  CHECK(close(m.surface, S, 1e-12));
  CHECK(close(m.boundary_tensor.trace(), S, 1e-12));
  CHECK(m.boundary_tensor == m.boundary_tensor.transpose());
  // Monte Carlo volume with CGAL's exact point location (independent of the volume sum).
  dynamics::ParticleRng rng(7, 0);
  const Vec3 size = m.bbox_hi - m.bbox_lo;
  const int n = 200000;
  int inside = 0;
  for (int i = 0; i < n; ++i)
    inside += contains(shape.region, m.bbox_lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()).cwiseProduct(size));
  const double p = double(inside) / n, box = size.prod();
  const double se = box * std::sqrt(p * (1 - p) / n);
  INFO("Monte Carlo V = " << p * box << " ± " << se << ", mesh V = " << m.volume);
  CHECK(std::abs(p * box - m.volume) < 4 * se);
  // The smooth surface's volume ∫ r³/3 dΩ, which the fine mesh approximates to O(h²).
  CHECK(std::abs(m.volume / (4 * pi / 3) - 1) < 0.1);
}

// ---------------------------------------------------------------- invalid input

namespace {

/// A fresh temporary folder with files (the test process's scratch directory).
struct Folder {
  std::filesystem::path dir = scratch("geometry3");
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
};

const std::string cube_vertices = "8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n";
const std::string cube_faces =  // counter-clockwise seen from outside
    "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n"
    "3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";

std::string reversed(const std::string& faces) {
  std::istringstream in(faces);
  std::string out;
  int n, a, b, c;
  while (in >> n >> a >> b >> c) out += "3 " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(b) + "\n";
  return out;
}

/// Loads a mesh shape whose `mesh:` key is on line 3, expecting an error containing `what`.
void mesh_rejected(const std::string& off, const std::string& what) {
  Folder f;
  f.write("m.off", off);
  const std::string yaml = "dimension: 3\nboundary:\n  mesh: m.off\n";
  INFO(what);
  CHECK_THROWS_WITH(parse_shape3(yaml, (f.dir / "s.yaml").string()),
                    Catch::Contains("s.yaml:3: mesh ") && Catch::Contains(what));
}

void rejected(const std::string& yaml, const std::string& where_what) {
  INFO(yaml);
  CHECK_THROWS_WITH(parse_shape3(yaml, "s.yaml"), Catch::Contains(where_what));
}

}  // namespace

TEST_CASE("a valid cube mesh loads, and its measures are exact") {
  Folder f;
  f.write("m.off", "OFF\n" + cube_vertices + cube_faces);
  const auto s = parse_shape3("dimension: 3\nboundary:\n  mesh: m.off\nholes:\n  - ball: {center: [0.5, 0.5, 0.5], radius: 0.4}\n",
                              (f.dir / "s.yaml").string());
  check(measures_of(s.region), 1 - 4 * pi * 0.064 / 3, 6 + 4 * pi * 0.16, (2 + 4 * pi * 0.16 / 3) * I);
}

TEST_CASE("the same cube read from OFF, OBJ and STL") {
  const double v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  std::istringstream in(cube_faces);
  std::string obj, stl = "solid cube\n";
  for (const auto& p : v) obj += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  int n, a, b, c;
  while (in >> n >> a >> b >> c) {
    obj += "f " + std::to_string(a + 1) + " " + std::to_string(b + 1) + " " + std::to_string(c + 1) + "\n";
    stl += "facet normal 0 0 0\nouter loop\n";  // STL repeats the vertices of every facet
    for (int k : {a, b, c})
      stl += "vertex " + std::to_string(v[k][0]) + " " + std::to_string(v[k][1]) + " " + std::to_string(v[k][2]) + "\n";
    stl += "endloop\nendfacet\n";
  }
  stl += "endsolid cube\n";
  Folder f;
  f.write("m.off", "OFF\n" + cube_vertices + cube_faces);
  f.write("m.obj", obj);
  f.write("m.stl", stl);
  for (const char* file : {"m.off", "m.obj", "m.stl"}) {
    INFO(file);
    const auto s = parse_shape3(std::string("dimension: 3\nboundary:\n  mesh: ") + file + "\n", (f.dir / "s.yaml").string());
    CHECK(std::get<TriangleMesh>(s.region.outer).vertices.size() == 8);
    check(measures_of(s.region), 1, 6, 2 * I);
  }
}

/// A prism of height h over a star of 2n corners (radii 1 and r, alternating) whose axis is
/// coordinate `axis`, as OFF: two non-convex 2n-gons and 2n quadrilaterals, counter-clockwise
/// seen from outside.
std::string star_prism(int n, double r, double h, int axis) {
  std::string off = fmt::format("OFF\n{} {} 0\n", 4 * n, 2 * n + 2);
  for (const double z : {0.0, h})
    for (int k = 0; k < 2 * n; ++k) {
      const double rho = k % 2 ? r : 1, x = rho * std::cos(pi * k / n), y = rho * std::sin(pi * k / n);
      Vec3 q;
      q[axis] = z, q[(axis + 1) % 3] = x, q[(axis + 2) % 3] = y;  // (a cyclic permutation: turns kept)
      off += fmt::format("{:.17g} {:.17g} {:.17g}\n", q.x(), q.y(), q.z());
    }
  std::string bottom = std::to_string(2 * n), top = bottom;
  for (int k = 0; k < 2 * n; ++k) bottom += " " + std::to_string(2 * n - 1 - k), top += " " + std::to_string(2 * n + k);
  off += bottom + "\n" + top + "\n";
  for (int k = 0; k < 2 * n; ++k) {
    const int next = (k + 1) % (2 * n);
    off += fmt::format("4 {} {} {} {}\n", k, next, next + 2 * n, k + 2 * n);
  }
  return off;
}

TEST_CASE("polygon faces are triangulated: star prisms along each axis have the closed-form V and S") {
  const int n = 7;
  const double r = 0.4, h = 1.5;
  // The star: 2n triangles (centre, corner, next corner) of sides 1 and r at angle π/n.
  const double area = 2 * n * 0.5 * r * std::sin(pi / n);
  const double perimeter = 2 * n * std::sqrt(1 + r * r - 2 * r * std::cos(pi / n));
  for (int axis = 0; axis < 3; ++axis) {
    INFO("axis " << axis);
    Folder f;
    f.write("m.off", star_prism(n, r, h, axis));
    const auto s = parse_shape3("dimension: 3\nboundary:\n  mesh: m.off\n", (f.dir / "s.yaml").string());
    // Each 2n-gon in 2n − 2 triangles, each quadrilateral in 2.
    CHECK(std::get<TriangleMesh>(s.region.outer).triangles.size() == std::size_t(2 * (2 * n - 2) + 4 * n));
    const auto m = measures_of(s.region);
    CHECK(close(m.volume, area * h, 1e-13));
    CHECK(close(m.surface, 2 * area + perimeter * h, 1e-13));
  }
}

/// The unit cube's OFF with a cube [1/4, 3/4]³ inside it, its faces reversed or not.
std::string cube_with_cavity(bool cavity_reversed) {
  std::string off = "OFF\n16 24 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                    ".25 .25 .25\n.75 .25 .25\n.75 .75 .25\n.25 .75 .25\n.25 .25 .75\n.75 .25 .75\n.75 .75 .75\n.25 .75 .75\n" +
                    cube_faces;
  std::istringstream in(cube_faces);
  int n, a, b, c;
  while (in >> n >> a >> b >> c) {
    if (cavity_reversed) std::swap(b, c);
    off += "3 " + std::to_string(a + 8) + " " + std::to_string(b + 8) + " " + std::to_string(c + 8) + "\n";
  }
  return off;
}

TEST_CASE("a mesh with a cavity: inward-facing cavity accepted, outward-facing rejected") {
  Folder f;
  f.write("m.off", cube_with_cavity(true));
  const auto s = parse_shape3("dimension: 3\nboundary:\n  mesh: m.off\n", (f.dir / "s.yaml").string());
  check(measures_of(s.region), 1 - 0.125, 6 + 1.5, 2.5 * I);
  CHECK(contains(s.region, Vec3(0.1, 0.1, 0.1)));
  CHECK(!contains(s.region, Vec3(0.5, 0.5, 0.5)));
  mesh_rejected(cube_with_cavity(false), "a nested component is oriented like its enclosing one");
}

TEST_CASE("invalid meshes are rejected with the reason") {
  mesh_rejected("OFF\n8 10 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n" +
                    cube_faces.substr(0, cube_faces.rfind("3 3 0 4")),
                "not closed");
  mesh_rejected("OFF\n" + cube_vertices + reversed(cube_faces), "inward oriented");
  // Two faces flipped: the orientation is inconsistent along their shared edges.
  mesh_rejected("OFF\n" + cube_vertices + reversed(cube_faces.substr(0, 16)) + cube_faces.substr(16),
                "inconsistently oriented");
  // Two cubes interpenetrating, in one file.
  std::string two = "OFF\n16 24 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                    ".5 .5 .5\n1.5 .5 .5\n1.5 1.5 .5\n.5 1.5 .5\n.5 .5 1.5\n1.5 .5 1.5\n1.5 1.5 1.5\n.5 1.5 1.5\n" + cube_faces;
  std::istringstream in(cube_faces);
  int n, a, b, c;
  while (in >> n >> a >> b >> c) two += "3 " + std::to_string(a + 8) + " " + std::to_string(b + 8) + " " + std::to_string(c + 8) + "\n";
  mesh_rejected(two, "self-intersecting");
  // A third face on the edge 0–1 (a fin): not manifold.
  mesh_rejected("OFF\n9 13 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n0.5 -1 -1\n" + cube_faces + "3 0 1 8\n",
                "not manifold");
  mesh_rejected("OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n", "not closed");
  // The L-prism's top hexagon with two corners moved so that its edges cross (a fuzz finding:
  // CGAL's triangulation of it dereferenced a null pointer).
  std::string crossing = read_file(shapes3 + "l-prism.off");
  for (const auto& [from, to] : {std::pair{"\n2 1 2\n", "\n0 -1 2\n"}, std::pair{"\n1 2 2\n", "\n1 -2 2\n"}}) {
    REQUIRE(crossing.find(from) != std::string::npos);
    crossing.replace(crossing.find(from), std::strlen(from), to);
  }
  mesh_rejected(crossing, "face 1 (counting from 0) cannot be triangulated: seen along its normal, it crosses itself");
  // Two copies of a quadrilateral, back to back: each is cut along its short diagonal, which
  // four triangles then share.
  mesh_rejected("OFF\n4 2 0\n0 0 0\n1 -0.3 0\n2 0 0\n1 0.3 0\n4 0 1 2 3\n4 3 2 1 0\n",
                "with its faces triangulated, not manifold: the edge between vertices 1 and 3 is shared by 4 faces");
  mesh_rejected("garbage", "cannot read");
  // Headers announcing more than the file holds are refused before anything is allocated for them.
  mesh_rejected("OFF\n1000000000 2000000000 0\n0 0 0\n", "its header announces 1e+09 vertices and 2e+09 faces, more than its");
  mesh_rejected("# a comment\nOFF 12 4 0\n0 0 0\n", "its header announces 12 vertices and 4 faces");
  mesh_rejected("OFF)# a comment after the keyword, no space before it\n4 42222222 9\n",
                "its header announces 4 vertices and 4.22222e+07 faces");
  mesh_rejected("COFF\n" + cube_vertices + cube_faces, "coloured OFF (COFF) is not read");
  // Counts CGAL's reader computes with: twice the edges (2e9 would overflow an int; a count
  // CGAL reads up to a control character too), and those of binary OFF, whose header may
  // follow a comment (fuzz findings).
  mesh_rejected("OFF\n3 1 2000000000\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "its header announces 2e+09 edges, more than its");
  mesh_rejected("OFF\n3 1 2000000000\x04" "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "its header announces 2e+09 edges");
  mesh_rejected("OFF\n# a comment\nBINARY\n" + std::string("\0\0\0\3\0\0\0\1\x70\0\0\0", 12), "binary OFF is not read");
  mesh_rejected("OFF BINARY\n" + std::string(12, '\x7f'), "binary OFF is not read");
  mesh_rejected("OFF\n" + cube_vertices + "3 0 1 2\n200000000000 0 1 2\n" + cube_faces.substr(16),
                "face 1 announces 200000000000 vertices, more than its");
  {
    Folder stl;
    std::string binary(84, '\0');
    const std::uint32_t triangles = 1u << 30;
    std::memcpy(binary.data() + 80, &triangles, 4);
    stl.write("m.stl", binary + std::string(50, '\0'));
    CHECK_THROWS_WITH(parse_shape3("dimension: 3\nboundary:\n  mesh: m.stl\n", (stl.dir / "s.yaml").string()),
                      Catch::Contains("s.yaml:3: mesh ") && Catch::Contains("announces 1073741824 triangles, more than its 134 bytes"));
  }
  Folder f;
  CHECK_THROWS_WITH(parse_shape3("dimension: 3\nboundary:\n  mesh: missing.off\n", (f.dir / "s.yaml").string()),
                    Catch::Contains("s.yaml:3: mesh ") && Catch::Contains("missing.off: cannot open"));
  CHECK_THROWS_WITH(parse_shape3("dimension: 3\nboundary:\n  mesh: m.ply\n", (f.dir / "s.yaml").string()),
                    Catch::Contains("expected a .off, .obj or .stl file"));
}

TEST_CASE("invalid 3-D shape files name the line and the problem") {
  const std::string box = "dimension: 3\nboundary:\n  box: {min: [0, 0, 0], max: [1, 1, 1]}\n";
  rejected(box + "holes:\n  - ball: {center: [0.5, 0.5, 0.5], radius: 0.6}\n",
           "s.yaml:5: this ball crosses or touches the plane at line 3");
  rejected(box + "holes:\n  - ball: {center: [0.3, 0.5, 0.5], radius: 0.2}\n  - ball: {center: [0.7, 0.5, 0.5], radius: 0.2}\n",
           "s.yaml:6: this ball overlaps or touches the ball at line 5");
  rejected("dimension: 3\nboundary:\n  sphere: {center: [0, 0, 0], radius: 1}\nholes:\n  - ball: {center: [0.5, 0, 0], radius: 0.5}\n",
           "s.yaml:5: this ball crosses or touches the outer sphere");
  rejected("dimension: 3\nboundary:\n  box: {min: [0, 0, 0], max: [1, -1, 1]}\n", "s.yaml:3: a box needs min < max");
  rejected("dimension: 3\nboundary:\n  sphere: {center: [0, 0], radius: 1}\n", "s.yaml:3: expected a vector [x, y, z]");
  rejected("dimension: 3\nboundary:\n  sphere: {center: [0, 0, 0], radius: -1}\n", "s.yaml:3: radius must be positive");
  rejected("dimension: 3\nboundary:\n  cone: {}\n", "s.yaml:3: unknown key 'cone'");
  rejected("dimension: 2\nboundary:\n  box: {}\n", "s.yaml:1: a 3-D shape file has 'dimension: 3'");
  rejected("dimension: 3\nboundary:\n  sphere: {center: [0, 0, 0], radius: R}\n", "s.yaml:3");
  // Half-spaces: unbounded (no face below), redundant (x ≤ 2 behind x ≤ 1).
  const std::string three = "    - {normal: [1, 0, 0], offset: 1}\n    - {normal: [0, 1, 0], offset: 1}\n"
                            "    - {normal: [0, 0, 1], offset: 1}\n";
  rejected("dimension: 3\nboundary:\n  polyhedron:\n" + three + "    - {normal: [-1, -1, 0], offset: 1}\n",
           "the polyhedron is unbounded beyond this plane's face");
  rejected("dimension: 3\nboundary:\n  polyhedron:\n" + three + "    - {normal: [-1, -1, -1], offset: 1}\n"
           "    - {normal: [2, 0, 0], offset: 4}\n",
           "s.yaml:8: this plane does not bound the polyhedron");
  rejected("dimension: 3\nboundary:\n  polyhedron:\n" + three + "    - {normal: [-1, -1, -1], offset: 1}\n"
           "    - {normal: [2, 0, 0], offset: 2}\n",
           "s.yaml:8: this plane repeats the plane at line 4");
  rejected("dimension: 3\nboundary:\n  polyhedron:\n" + three +
               "    - {normal: [-1, 0, 0], offset: -1}\n    - {normal: [0, -1, 0], offset: 1}\n"
               "    - {normal: [0, 0, -1], offset: 1}\n",
           "s.yaml:5: this plane does not bound the polyhedron");  // a slab of zero thickness
  rejected("dimension: 3\nboundary:\n  polyhedron:\n" + three + "    - {normal: [0, 0, 0], offset: 1}\n",
           "s.yaml:7: the normal must not be zero");
  CHECK_THROWS_WITH(load_shape3(shapes3 + "cube.yaml", {{"M", "2"}}), Catch::Contains("'M', which is not a parameter"));
}

TEST_CASE("shape_dimension tells 2-D from 3-D files") {
  CHECK(shape_dimension(shapes3 + "sinai3.yaml") == 3);
  CHECK(shape_dimension(BILLIARDS_SOURCE_DIR "/shapes/sinai.yaml") == 2);
}

TEST_CASE("billiard info reads 3-D shape files") {
  const auto r = billiard("info shapes/3d/sinai3.yaml --json --set L=2");
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.output);
  CHECK(j["dimension"] == 3);
  CHECK(close(j["V"].get<double>(), 8 - 4 * pi / 64 / 3));
  CHECK(close(j["S"].get<double>(), 24 + 4 * pi / 16));
  CHECK(j["boundary_tensor"].size() == 3);
  CHECK(j["bbox"][1][2] == 1.0);
  CHECK(j["boundary"]["kind"] == "polyhedron");
  const auto text = billiard("info shapes/3d/l-prism.yaml");
  CHECK(text.status == 0);
  CHECK_THAT(text.output, Catch::Contains("mean free path   1.09090909090909"));
  const auto dir = scratch("info3");
  write_file(dir / "bad.yaml", "# open\ndimension: 3\nboundary:\n  mesh: open.off\n");
  write_file(dir / "open.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const auto bad = billiard("info " + (dir / "bad.yaml").string());
  CHECK(bad.status != 0);
  CHECK_THAT(bad.output, Catch::StartsWith("billiard: error: " + (dir / "bad.yaml").string() + ":4: mesh ") &&
                             Catch::Contains("open.off: not closed"));
  std::filesystem::remove_all(dir);
}
