#include "billiards/analysis/escape.hpp"

#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/yaml_reader.hpp"

#include <fmt/core.h>

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

std::vector<ExitInterval> read_exits(const geometry::Shape& shape, const BoundaryCoordinates& coordinates) {
  const std::string& file = shape.region.origin.file;
  const YAML::Node doc = load_yaml(read_input_file(file, "shape file"), file);
  const YAML::Node list = doc["exits"];
  if (!list) return {};
  Expressions expressions;
  for (const auto& [name, value] : shape.parameters) expressions.define(name, fmt::format("{:.17g}", value), file, 0);
  const YamlReader r(file, expressions);
  if (!list.IsSequence()) r.fail(list, "'exits' must be a list of {from: [x, y], to: [x, y]}");
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

}  // namespace billiards::analysis
