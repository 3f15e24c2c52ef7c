// Elliptic walls in the geometry layer: measures against series and quadratures written here,
// computed joints, shape-file errors, and `billiard info` on the bundled elliptic shapes.
#include "billiards/analysis/potential.hpp"
#include "billiards/analysis/wall.hpp"
#include "billiards/geometry.hpp"
#include "cli_helpers.hpp"

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <cmath>

using namespace billiards;
using geometry::EllipticArc;
using geometry::pi;
using geometry::Vec2;

namespace {

bool close(double a, double b, double rel) { return std::abs(a - b) <= rel * std::abs(b); }

EllipticArc ellipse(Vec2 c, double a, double b, double angle, double start, double sweep) {
  EllipticArc e;
  e.center = c;
  e.semi_axes = {a, b};
  e.angle = angle;
  e.start = start;
  e.sweep = sweep;
  e.source = e.point_at(start);
  e.target = e.point_at(start + sweep);
  return e;
}

geometry::Region2 region_of(const geometry::Piece& full) {
  geometry::Region2 r;
  r.outer.pieces = {full};
  r.outer.where = {{}};
  return r;
}

/// Perimeter of an ellipse by the Gauss–Kummer series π(a + b) Σ C(1/2, n)² hⁿ, h =
/// ((a − b)/(a + b))², summed smallest term first.
double gauss_kummer_perimeter(double a, double b) {
  const double h = std::pow((a - b) / (a + b), 2);
  std::vector<double> terms{1};
  double binomial = 1, power = 1;  // C(1/2, n), hⁿ
  for (int n = 1; n < 5000; ++n) {
    binomial *= (0.5 - (n - 1)) / n;
    power *= h;
    terms.push_back(binomial * binomial * power);
    if (terms.back() < 1e-20) break;
  }
  double sum = 0;
  for (auto t = terms.rbegin(); t != terms.rend(); ++t) sum += *t;
  return pi * (a + b) * sum;
}

/// ∫ f(φ) dφ over [lo, hi] by adaptive Gauss–Kronrod (61 points), to 1e-15 relative.
template <class F>
double integral(F f, double lo, double hi) {
  return boost::math::quadrature::gauss_kronrod<double, 61>::integrate(f, lo, hi, 15, 1e-15);
}

/// The unit tangent and the right normal at anomaly φ, from the parametrisation written here.
struct Frame {
  Vec2 dx;  // dx/dφ
  Vec2 normal;
};
Frame frame(const EllipticArc& e, double phi) {
  const double c = std::cos(e.angle), s = std::sin(e.angle);
  const Vec2 d(-e.semi_axes.x() * std::sin(phi), e.semi_axes.y() * std::cos(phi));
  const Vec2 dx(c * d.x() - s * d.y(), s * d.x() + c * d.y());
  return {dx, Vec2(dx.y(), -dx.x()).normalized()};
}

/// |M(x − c)|² − 1 for the ellipse: zero on it.
double implicit(const EllipticArc& e, const Vec2& x) {
  const Vec2 d = x - e.center;
  const double c = std::cos(e.angle), s = std::sin(e.angle);
  const double u = (c * d.x() + s * d.y()) / e.semi_axes.x(), w = (-s * d.x() + c * d.y()) / e.semi_axes.y();
  return u * u + w * w - 1;
}

std::string yaml_point(const Vec2& p) { return fmt::format("[{:.17g}, {:.17g}]", p.x(), p.y()); }

std::string error_of(const std::string& yaml) {
  try {
    geometry::parse_shape(yaml, "bad.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("a full ellipse: V = pi a b, S by the Gauss-Kummer series, lambda = pi V / S") {
  for (const auto& [a, b, angle] : {std::tuple{2.0, 1.0, 0.0}, {1.0, 2.0, 0.3}, {5.0, 0.5, -1.2}, {1.0, 0.999, 2.0},
                                    {1e-3, 3e-3, 0.7}, {10.0, 1.0, pi / 2}}) {
    for (double sweep : {2 * pi, -2 * pi}) {
      INFO("a = " << a << ", b = " << b << ", angle = " << angle << ", sweep = " << sweep);
      const auto m = geometry::measures_of(region_of(ellipse({0.3, -0.4}, a, b, angle, 0, sweep)));
      CHECK(close(std::abs(m.volume), pi * a * b, 1e-14));
      CHECK(close(m.surface, gauss_kummer_perimeter(a, b), 1e-13));
      CHECK(close(geometry::mean_free_path(m), pi * m.volume / m.surface, 1e-15));
      CHECK(close(m.boundary_tensor.trace(), m.surface, 1e-13));
    }
  }
}

TEST_CASE("an ellipse with a = b has the circle's measures") {
  for (double r : {0.25, 1.0, 3.0}) {
    const Vec2 c(1.5, -0.5);
    const auto e = geometry::measures_of(region_of(ellipse(c, r, r, 0.8, 0.3, 2 * pi)));
    geometry::Arc arc{c, r, 0.3, 2 * pi, {}, {}};
    arc.source = arc.target = arc.point_at(0.3);
    const auto k = geometry::measures_of(region_of(arc));
    CHECK(close(e.volume, k.volume, 1e-15));
    CHECK(close(e.surface, k.surface, 1e-15));
    CHECK((e.boundary_tensor - k.boundary_tensor).norm() <= 1e-15 * k.surface);
    CHECK((e.bbox_lo - k.bbox_lo).norm() <= 1e-15 * r);
    CHECK((e.bbox_hi - k.bbox_hi).norm() <= 1e-15 * r);
  }
}

TEST_CASE("elliptic arcs: sector area, length, int n n^T dS, bounding box against quadrature") {
  const Vec2 c(0.7, -1.1);
  for (const auto& [a, b, angle, start, sweep] :
       {std::tuple{2.0, 1.0, 0.4, 0.3, 1.9}, {1.0, 3.0, -0.9, -2.0, -4.1}, {2.0, 1.999, 0.1, 1.0, 6.0},
        {0.5, 0.2, 2.5, 4.0, 0.01}, {4.0, 1.0, 0.0, -pi / 2, pi}}) {
    INFO("a = " << a << ", b = " << b << ", angle = " << angle << ", start = " << start << ", sweep = " << sweep);
    const EllipticArc e = ellipse(c, a, b, angle, start, sweep);
    // The sector: centre → source, the arc, target → centre.
    geometry::Loop sector;
    sector.pieces = {geometry::Segment{c, e.source}, e, geometry::Segment{e.target, c}};
    const double lo = std::min(start, start + sweep), hi = std::max(start, start + sweep);
    const double sign = sweep > 0 ? 1 : -1;
    const double arc_area = 0.5 * sign * integral([&](double t) { return geometry::cross(e.point_at(t), frame(e, t).dx); }, lo, hi);
    // Incomplete elliptic integrals at |φ| up to ~2π carry an absolute error of a few ulps of
    // the ellipse's size: short arcs are checked against that scale.
    const double size = std::max(a, b), area_scale = size * (size + c.norm());
    CHECK(std::abs(geometry::signed_area(sector) - (0.5 * geometry::cross(c, e.source) + arc_area +
                                                    0.5 * geometry::cross(e.target, c))) <= 1e-14 * area_scale);
    const double length = integral([&](double t) { return frame(e, t).dx.norm(); }, lo, hi);
    CHECK(std::abs(geometry::length_of(e) - length) <= 1e-14 * (length + size));
    Eigen::Matrix2d T = Eigen::Matrix2d::Zero();
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        T(i, j) = integral([&](double t) { const auto f = frame(e, t); return f.normal[i] * f.normal[j] * f.dx.norm(); }, lo, hi);
    CHECK((geometry::boundary_tensor_of(e) - T).norm() <= 1e-14 * (length + size));
    // The bounding box against 20001 points of the arc (their box is inside, and close).
    const auto [box_lo, box_hi] = geometry::bounding_box(e);
    Vec2 p_lo = e.source, p_hi = e.source;
    for (int k = 0; k <= 20000; ++k) {
      const Vec2 p = e.point_at(start + sweep * k / 20000);
      p_lo = p_lo.cwiseMin(p);
      p_hi = p_hi.cwiseMax(p);
    }
    CHECK((box_lo - p_lo).maxCoeff() <= 1e-14 * a);
    CHECK((p_hi - box_hi).maxCoeff() <= 1e-14 * a);
    CHECK((p_lo - box_lo).norm() + (box_hi - p_hi).norm() <= std::pow(sweep / 20000, 2) * std::max(a, b));
    // point_along is by arc length: the length up to u is u times the whole.
    for (double u : {0.1, 0.5, 0.77}) {
      double phi = std::fmod(e.anomaly_of(geometry::point_along(e, u)) - lo, 2 * pi);  // into [lo, lo + 2π)
      phi = lo + (phi < 0 ? phi + 2 * pi : phi);
      const double to = integral([&](double t) { return frame(e, t).dx.norm(); }, std::min(start, phi), std::max(start, phi));
      CHECK(std::abs(to - u * length) <= 1e-12 * u * length + 1e-14 * size);
    }
  }
}

TEST_CASE("normals and curvature of an elliptic arc") {
  const EllipticArc e = ellipse({0, 0}, 3, 1, 0.5, 0, 2 * pi);
  for (double phi : {0.0, 0.4, pi / 2, 2.5, 4.0}) {
    const Vec2 x = e.point_at(phi);
    // The outward normal is the gradient of the implicit function.
    const double h = 1e-6;
    const Vec2 grad((implicit(e, x + Vec2(h, 0)) - implicit(e, x - Vec2(h, 0))) / (2 * h),
                    (implicit(e, x + Vec2(0, h)) - implicit(e, x - Vec2(0, h))) / (2 * h));
    CHECK((geometry::outward_normal(e, x) - grad.normalized()).norm() <= 1e-8);
    // κ = |x′ × x″| / |x′|³ with x″ = −(x − c).
    const Vec2 d = frame(e, phi).dx;
    CHECK(close(geometry::curvature_at(e, x), std::abs(geometry::cross(d, Vec2(-x))) / std::pow(d.norm(), 3), 1e-14));
  }
  EllipticArc scatterer = e;
  scatterer.sweep = -2 * pi;
  CHECK(geometry::curvature_at(scatterer, e.point_at(1)) == -geometry::curvature_at(e, e.point_at(1)));
  CHECK((geometry::outward_normal(scatterer, e.point_at(1)) + geometry::outward_normal(e, e.point_at(1))).norm() == 0);
}

TEST_CASE("the bundled elliptic shapes: V, S, lambda in closed form; validation accepts them") {
  const auto load = [](const std::string& name, const Overrides& set = {}) {
    return geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + name + ".yaml", set);
  };
  auto m = geometry::measures_of(load("ellipse").region);
  CHECK(close(m.volume, 2 * pi, 1e-15));
  CHECK(close(m.surface, gauss_kummer_perimeter(2, 1), 1e-13));
  m = geometry::measures_of(load("ellipse", {{"a", "1"}, {"b", "3"}, {"angle", "pi/5"}}).region);
  CHECK(close(m.volume, 3 * pi, 1e-15));
  CHECK(close(m.surface, gauss_kummer_perimeter(1, 3), 1e-13));
  m = geometry::measures_of(load("elliptic-stadium").region);
  CHECK(close(m.volume, 4 + pi / 2, 1e-15));
  CHECK(close(m.surface, 4 + gauss_kummer_perimeter(0.5, 1), 1e-13));
  m = geometry::measures_of(load("sinai-ellipse").region);
  CHECK(close(m.volume, 1 - pi * 0.3 * 0.15, 1e-15));
  CHECK(close(m.surface, 4 + gauss_kummer_perimeter(0.3, 0.15), 1e-13));
}

TEST_CASE("analysis on elliptic tables: allowed area with U = 0 is V, the uniform-force wall integral is F^T T F") {
  const analysis::Potential flat = [](const Vec2&) { return 0.0; };
  for (const char* name : {"ellipse", "elliptic-stadium", "sinai-ellipse"}) {
    INFO(name);
    const auto region = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/" + std::string(name) + ".yaml").region;
    const auto m = geometry::measures_of(region);
    const auto area = analysis::allowed_area(region, flat, 1.0);
    CHECK(std::abs(area.value - m.volume) <= 1e-9 * m.volume);
    const Vec2 F(0.6, -1.3);
    const auto wall = analysis::wall_integral(region, [&](const Vec2&) { return F; });
    CHECK(std::abs(wall.value - F.dot(m.boundary_tensor * F)) <= 1e-9 * wall.value);
  }
}

TEST_CASE("joints computed by tangency lie on both curves") {
  const EllipticArc outer = ellipse({0.3, -0.2}, 2, 1, 0.4, 0, 2 * pi);
  const double phi0 = 0.7;
  const Vec2 P = outer.point_at(phi0), n = frame(outer, phi0).normal;
  const std::string ellipse_yaml =
      "    - elliptic_arc: {center: [0.3, -0.2], semi_axes: [2, 1], angle: 0.4, side: inside}\n";
  const auto check_joint = [&](const geometry::Region2& r, auto on_inner) {
    const Vec2 J = geometry::target_of(r.outer.pieces[0]);
    CHECK((J - P).norm() <= 1e-12);
    CHECK(std::abs(implicit(outer, J)) <= 1e-15);
    CHECK(on_inner(J) <= 1e-15);
  };
  SECTION("a circle inside the ellipse, tangent at P (radius below the least radius of curvature)") {
    const double rho = 0.3;
    const Vec2 C = P - rho * n;
    const double t1 = std::atan2(n.y(), n.x()) + 1.5;
    const std::string yaml = "boundary:\n  pieces:\n    - point: " + yaml_point(outer.point_at(phi0 - 1.5)) + "\n" +
                             ellipse_yaml + "    - arc: {center: " + yaml_point(C) +
                             fmt::format(", radius: {}, side: inside}}\n", rho) +
                             "    - point: " + yaml_point(C + rho * Vec2(std::cos(t1), std::sin(t1))) + "\n";
    const auto shape = geometry::parse_shape(yaml, "tangent.yaml");
    check_joint(shape.region, [&](const Vec2& J) { return std::abs((J - C).norm() - rho) / rho; });
  }
  SECTION("a smaller homothetic ellipse inside, tangent at P") {
    const EllipticArc inner = ellipse(P + 0.5 * (outer.center - P), 1, 0.5, 0.4, 0, 2 * pi);
    const std::string yaml = "boundary:\n  pieces:\n    - point: " + yaml_point(outer.point_at(phi0 - 1.5)) + "\n" +
                             ellipse_yaml + "    - elliptic_arc: {center: " + yaml_point(inner.center) +
                             ", semi_axes: [1, 0.5], angle: 0.4, side: inside}\n" +
                             "    - point: " + yaml_point(inner.point_at(phi0 + 1.5)) + "\n";
    const auto shape = geometry::parse_shape(yaml, "tangent.yaml");
    check_joint(shape.region, [&](const Vec2& J) { return std::abs(implicit(inner, J)); });
  }
}

TEST_CASE("elliptic shape-file errors name file, line and problem") {
  CHECK_THAT(error_of("boundary:\n  ellipse: {center: [0, 0], semi_axes: [1, -2]}\n"),
             Catch::Contains("bad.yaml:2: semi_axes must be positive"));
  CHECK_THAT(error_of("boundary:\n  ellipse: {center: [0, 0], semi_axes: [0, 2]}\n"),
             Catch::Contains("bad.yaml:2: semi_axes must be positive"));
  CHECK_THAT(error_of("boundary:\n  ellipse: {center: [0, 0], semi_axes: [1, 2], tilt: 1}\n"),
             Catch::Contains("bad.yaml:2: unknown key 'tilt' in an ellipse"));
  // A joint off the ellipse.
  CHECK_THAT(error_of("boundary:\n  pieces:\n    - point: [-1, -1]\n    - point: [1, -1]\n"
                      "    - elliptic_arc: {center: [1, 0], semi_axes: [0.5, 1], side: inside}\n"
                      "    - point: [1, 1.001]\n"),
             Catch::Contains("bad.yaml:6: point is not on the ellipse of the elliptic arc at line 5"));
  // Tangency requested, but the curves cross at two points, or miss.
  CHECK_THAT(error_of("boundary:\n  pieces:\n    - elliptic_arc: {center: [0, 0], semi_axes: [2, 1], side: inside}\n"
                      "    - arc: {center: [2, 0], radius: 1, side: inside}\n"),
             Catch::Contains("bad.yaml:4: the elliptic arc at line 3 and the arc at line 4 cross or touch at 2 points"));
  CHECK_THAT(error_of("boundary:\n  pieces:\n    - elliptic_arc: {center: [0, 0], semi_axes: [2, 1], side: inside}\n"
                      "    - elliptic_arc: {center: [5, 0], semi_axes: [2, 1], side: inside}\n"),
             Catch::Contains("bad.yaml:4: the elliptic arc at line 3 and the elliptic arc at line 4 do not meet"));
  // An elliptic hole crossing the outer boundary.
  CHECK_THAT(error_of("boundary:\n  polygon: [[-1, -1], [1, -1], [1, 1], [-1, 1]]\nholes:\n"
                      "  - ellipse: {center: [0, 0], semi_axes: [1.5, 0.5]}\n"),
             Catch::Contains("bad.yaml:4: the hole at line 4 is not strictly inside the outer boundary"));
  // Two elliptic holes overlapping.
  CHECK_THAT(error_of("boundary:\n  polygon: [[-3, -3], [3, -3], [3, 3], [-3, 3]]\nholes:\n"
                      "  - ellipse: {center: [0, 0], semi_axes: [1.5, 0.5]}\n"
                      "  - ellipse: {center: [0, 0], semi_axes: [1.5, 0.5], angle: pi/2}\n"),
             Catch::Contains("bad.yaml:5: the holes at lines 4 and 5 overlap or touch"));
  // Wrong orientation: the region outside an elliptic outer boundary.
  CHECK_THAT(error_of("boundary:\n  pieces:\n    - point: [-1, -1]\n    - point: [-1, 1]\n"
                      "    - elliptic_arc: {center: [-1, 0], semi_axes: [0.5, 1], side: outside}\n"),
             Catch::Contains("bad.yaml:2: the outer boundary runs clockwise"));
}

TEST_CASE("billiard info on elliptic shapes: JSON kind, V, S, lambda; errors with FILE:LINE and no output") {
  const auto r = billiard("info --json shapes/ellipse.yaml --set a=3 --set b=1.5");
  REQUIRE(r.status == 0);
  const auto info = nlohmann::json::parse(r.output);
  CHECK(info["pieces"][0]["kind"] == "elliptic_arc");
  CHECK(info["pieces"][0]["semi_axes"] == nlohmann::json({3.0, 1.5}));
  CHECK(close(info["V"].get<double>(), 4.5 * pi, 1e-15));
  CHECK(close(info["S"].get<double>(), gauss_kummer_perimeter(3, 1.5), 1e-13));
  CHECK(close(info["mean_free_path"].get<double>(), pi * 4.5 * pi / gauss_kummer_perimeter(3, 1.5), 1e-13));
  const auto stadium = nlohmann::json::parse(billiard("info --json shapes/elliptic-stadium.yaml").output);
  CHECK(stadium["pieces"][1]["kind"] == "elliptic_arc");
  CHECK(close(stadium["mean_free_path"].get<double>(), pi * (4 + pi / 2) / (4 + gauss_kummer_perimeter(0.5, 1)), 1e-13));
  CHECK(billiard("info shapes/sinai-ellipse.yaml").status == 0);

  const auto dir = scratch_root() / "ellipse";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "bad.yaml") << "boundary:\n  ellipse: {center: [0, 0], semi_axes: [1, -2]}\n";
  const auto bad = billiard("info " + (dir / "bad.yaml").string());
  CHECK(bad.status != 0);
  CHECK(bad.output == "billiard: error: " + (dir / "bad.yaml").string() + ":2: semi_axes must be positive, got [1.000000, -2.000000]\n");
}
