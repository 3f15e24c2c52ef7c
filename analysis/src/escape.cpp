#include "billiards/analysis/escape.hpp"

#include "billiards/analysis/statistics.hpp"
#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/yaml_reader.hpp"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>

namespace billiards::analysis {

Exits::Exits(const BoundaryCoordinates& coordinates, std::vector<ExitInterval> exits)
    : coordinates_(&coordinates), exits_(std::move(exits)) {
  for (const auto& e : exits_) {
    const auto [first, end] = coordinates.loop_range(e.loop);
    lengths_.push_back(e.to > e.from ? e.to - e.from : (end - e.from) + (e.to - first));
    length_ += lengths_.back();
  }
}

bool Exits::contains(double s) const {
  for (const auto& e : exits_) {
    if (e.to > e.from ? (s >= e.from && s <= e.to) : ((s >= e.from || s <= e.to) && coordinates_->loop_at(s) == e.loop))
      return true;
  }
  return false;
}

double Exits::at_fraction(double u) const {
  double left = u * length_;
  for (std::size_t i = 0; i < exits_.size(); ++i) {
    if (left < lengths_[i] || i + 1 == exits_.size()) {
      const auto& e = exits_[i];
      const auto [first, end] = coordinates_->loop_range(e.loop);
      const double s = e.from + left;
      return s < end ? s : first + (s - end);
    }
    left -= lengths_[i];
  }
  return 0;
}

namespace {

/// A shape file's `exits:` list (read again from the file), with a reader of expressions in the
/// shape's parameters.
struct ExitList {
  YAML::Node list;
  Expressions expressions;
  YamlReader reader;
  ExitList(const std::string& file, const std::map<std::string, double>& parameters, const char* syntax)
      : list(load_yaml(read_input_file(file, "shape file"), file)["exits"]), reader(file, expressions) {
    for (const auto& [name, value] : parameters) expressions.define(name, fmt::format("{:.17g}", value), file, 0);
    if (list && !list.IsSequence()) reader.fail(list, fmt::format("'exits' must be a list of {}", syntax));
  }
};

}  // namespace

std::vector<ExitInterval> read_exits(const geometry::Shape& shape, const BoundaryCoordinates& coordinates) {
  const ExitList exit_list(shape.region.origin.file, shape.parameters, "{from: [x, y], to: [x, y]}");
  const YAML::Node& list = exit_list.list;
  if (!list) return {};
  const YamlReader& r = exit_list.reader;
  const auto m = geometry::measures_of(shape.region);
  const double tolerance = 1e-9 * (m.bbox_hi - m.bbox_lo).maxCoeff();
  std::vector<ExitInterval> exits;
  for (const auto& n : list) {
    r.expect_keys(n, {"from", "to"}, "an exit");
    const auto on_boundary = [&](const char* key) {
      const YAML::Node p = r.required(n, key, "an exit");
      const Vec2 x = r.point(p);
      const auto s = coordinates.locate(x, tolerance);
      if (!s) r.fail(p, fmt::format("the exit's '{}' point ({:.9g}, {:.9g}) is not on the boundary", key, x.x(), x.y()));
      return *s;
    };
    ExitInterval e{0, on_boundary("from"), on_boundary("to"), r.ref(n)};
    e.loop = coordinates.loop_at(e.from);
    if (coordinates.loop_at(e.to) != e.loop) r.fail(n, "an exit's 'from' and 'to' points must lie on the same loop");
    if (std::abs(e.to - e.from) <= tolerance)
      r.fail(n, "the exit is empty: its 'from' and 'to' points coincide");
    exits.push_back(e);
  }
  return exits;
}

dynamics::State entering_state(const BoundaryCoordinates& coordinates, const Exits& exits, double speed,
                               dynamics::ParticleRng& rng) {
  const double s = exits.at_fraction(rng.uniform());
  const double p = 2 * rng.uniform() - 1;
  const Vec2 n = coordinates.normal_at(s), t(-n.y(), n.x());  // outward normal, tangent of travel
  dynamics::State state;
  state.x = coordinates.point_at(s);
  state.v = speed * (p * t - std::sqrt(1 - p * p) * n);
  return state;
}

bool Exits3::contains(const dynamics::WallId& wall, const geometry3::Vec3& x) const {
  if (wall.kind != dynamics::wall_kind3::plane) return false;
  for (const auto& d : discs_)
    if (wall.index == d.face && (x - d.center).squaredNorm() <= d.radius * d.radius) return true;
  return false;
}

double Exits3::area() const {
  double a = 0;
  for (const auto& d : discs_) a += geometry::pi * d.radius * d.radius;
  return a;
}

dynamics::State3 Exits3::entering_state(double speed, dynamics::ParticleRng& rng) const {
  // A disc with probability ∝ its area, a point uniform on it, cos² θ uniform, azimuth uniform.
  double pick = rng.uniform() * area();
  const DiscExit* d = &discs_.back();
  for (const auto& disc : discs_) {
    const double a = geometry::pi * disc.radius * disc.radius;
    if (pick < a) {
      d = &disc;
      break;
    }
    pick -= a;
  }
  const double rho = d->radius * std::sqrt(rng.uniform()), phi = 2 * geometry::pi * rng.uniform();
  const double cos2 = rng.uniform(), psi = 2 * geometry::pi * rng.uniform();
  dynamics::State3 s;
  s.x = d->center + rho * (std::cos(phi) * d->e1 + std::sin(phi) * d->e2);
  s.v = speed * (-std::sqrt(cos2) * d->normal + std::sqrt(1 - cos2) * (std::cos(psi) * d->e1 + std::sin(psi) * d->e2));
  return s;
}

namespace {

/// The disc's face: the face whose plane holds its centre and which holds the whole disc.
DiscExit place_disc(const geometry3::ConvexPolyhedron& p, const geometry3::Vec3& c, double r, double tolerance,
                    const YamlReader& reader, const YAML::Node& n) {
  for (std::size_t i = 0; i < p.planes.size(); ++i) {
    const auto& plane = p.planes[i];
    if (std::abs(plane.beyond(c)) > tolerance) continue;
    const auto& face = p.faces[i];
    for (std::size_t k = 0; k < face.size(); ++k) {  // (counter-clockwise from outside: inward = n × edge)
      const geometry3::Vec3 edge = face[(k + 1) % face.size()] - face[k];
      const geometry3::Vec3 inward = plane.normal.cross(edge).normalized();
      if (inward.dot(c - face[k]) < r - tolerance)
        reader.fail(n, fmt::format("the exit's disc (radius {:.9g}) reaches beyond the face of the plane at line {}",
                                   r, plane.where.line));
    }
    DiscExit d{int(i), c, plane.normal, {}, {}, r, reader.ref(n)};
    d.e1 = (face[1] - face[0]).normalized();
    d.e2 = plane.normal.cross(d.e1);
    return d;
  }
  reader.fail(n, fmt::format("the exit's centre ({:.9g}, {:.9g}, {:.9g}) is not on a face of the polyhedron", c.x(),
                             c.y(), c.z()));
}

}  // namespace

std::vector<DiscExit> read_exits3(const geometry3::Shape3& shape) {
  const ExitList exit_list(shape.region.origin.file, shape.parameters, "{disc: {center: [x, y, z], radius: r}}");
  const YAML::Node& list = exit_list.list;
  if (!list) return {};
  const YamlReader& r = exit_list.reader;
  const auto* polyhedron = std::get_if<geometry3::ConvexPolyhedron>(&shape.region.outer);
  const auto m = geometry3::measures_of(shape.region);
  const double tolerance = 1e-9 * (m.bbox_hi - m.bbox_lo).maxCoeff();
  std::vector<DiscExit> exits;
  for (const auto& n : list) {
    r.expect_keys(n, {"disc"}, "a 3-D exit");
    const YAML::Node disc = r.required(n, "disc", "a 3-D exit");
    r.expect_keys(disc, {"center", "radius"}, "an exit's disc");
    if (!polyhedron) r.fail(n, "exits in 3-D are discs on the faces of a box or polyhedron, and this boundary has no faces");
    const geometry3::Vec3 c = r.vector(r.required(disc, "center", "an exit's disc"), 3);
    const double radius = r.positive(r.required(disc, "radius", "an exit's disc"), "radius");
    exits.push_back(place_disc(*polyhedron, c, radius, tolerance, r, disc));
  }
  return exits;
}

double kac_mean_escape_time(double volume, double exit_measure, double speed, int dimension) {
  return (dimension == 3 ? 4.0 : geometry::pi) * volume / (exit_measure * speed);
}

EscapeSummary summarize(const std::vector<EscapeRecord>& records) {
  EscapeSummary out;
  for (const auto& r : records) {
    out.lost += r.lost;
    if (r.escaped) out.times.push_back(r.time);
  }
  if (out.times.size() >= 2) {
    const auto m = sample_moments(out.times);
    out.mean = m.mean, out.se = m.se_mean;
  }
  return out;
}

Survival survival(std::vector<double> times, std::size_t particles, int points) {
  std::sort(times.begin(), times.end());
  const double end = times.empty() ? 0 : times.back();
  Survival out;
  for (int k = 0; k <= points; ++k) {
    const double t = end * k / points;
    const auto later = std::size_t(times.end() - std::upper_bound(times.begin(), times.end(), t));
    out.t.push_back(t);
    out.P.push_back(double(particles - times.size() + later) / double(particles));
  }
  return out;
}

}  // namespace billiards::analysis
