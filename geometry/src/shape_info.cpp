// The exact geometry of a shape as JSON: what `billiard info --json` prints and the Python
// module's `info` returns.
#include "billiards/geometry/shape_info.hpp"

#include "billiards/geometry/measures.hpp"

#include <nlohmann/json.hpp>

#include <array>

namespace billiards::geometry {

namespace {

/// [least, greatest] signed curvature along an elliptic arc: |κ| is extreme at its ends and
/// where it passes an end of an axis (φ a multiple of π/2).
std::array<double, 2> curvature_range(const EllipticArc& e) {
  const double end = e.start + e.sweep;
  std::array<double, 2> range{e.curvature_at(e.start), e.curvature_at(e.start)};
  const auto include = [&](double phi) {
    range[0] = std::min(range[0], e.curvature_at(phi));
    range[1] = std::max(range[1], e.curvature_at(phi));
  };
  include(end);
  const double lo = std::min(e.start, end), hi = std::max(e.start, end);
  for (double k = std::ceil(lo / (pi / 2)); k * (pi / 2) <= hi; ++k) include(k * (pi / 2));
  return range;
}

/// Every piece of every loop, with its source line.
nlohmann::json pieces_json(const Region2& region) {
  nlohmann::json out = nlohmann::json::array();
  for (const Loop* loop : region.loops()) {
    for (std::size_t i = 0; i < loop->pieces.size(); ++i) {
      const auto& p = loop->pieces[i];
      nlohmann::json j = {{"kind", kind_of(p)},
                          {"line", loop->where[i].line},
                          {"loop", loop == &region.outer ? "boundary" : "hole"},
                          {"length", length_of(p)},
                          {"from", {source_of(p).x(), source_of(p).y()}},
                          {"to", {target_of(p).x(), target_of(p).y()}}};
      if (const auto* e = std::get_if<EllipticArc>(&p)) {
        j["center"] = {e->center.x(), e->center.y()};
        j["semi_axes"] = {e->semi_axes.x(), e->semi_axes.y()};
        j["angle"] = e->angle;
        j["sweep"] = e->sweep;  // in eccentric anomaly
        j["curvature"] = curvature_range(*e);
      } else {
        j["curvature"] = curvature_at(p, source_of(p));  // constant along segments and arcs
      }
      if (const auto* a = std::get_if<Arc>(&p)) {
        j["center"] = {a->center.x(), a->center.y()};
        j["radius"] = a->radius;
        j["sweep"] = a->sweep;
      }
      out.push_back(j);
    }
  }
  return out;
}

}  // namespace

nlohmann::json common_info(const std::string& name, const std::string& file, const Measures& m,
                           const std::map<std::string, double>& parameters) {
  const auto vector = [](const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  nlohmann::json tensor = nlohmann::json::array();
  for (int i = 0; i < m.dimension; ++i) tensor.push_back(vector(m.boundary_tensor.row(i).transpose()));
  return {{"name", name},
          {"file", file},
          {"dimension", m.dimension},
          {"V", m.volume},
          {"S", m.surface},
          {"mean_free_path", mean_free_path(m)},
          {"boundary_tensor", tensor},
          {"bbox", {vector(m.bbox_lo), vector(m.bbox_hi)}},
          {"parameters", parameters}};
}

nlohmann::json shape_info(const Shape& shape) {
  auto info = common_info(shape.region.name, shape.region.origin.file, measures_of(shape.region), shape.parameters);
  info["holes"] = shape.region.holes.size();
  info["pieces"] = pieces_json(shape.region);
  return info;
}

}  // namespace billiards::geometry
