// The exact geometry of a shape as JSON: what `billiard info --json` prints and the Python
// module's `info` returns.
#include "billiards/geometry/shape_info.hpp"

#include "billiards/geometry/measures.hpp"

#include <nlohmann/json.hpp>

namespace billiards::geometry {

namespace {

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
                          {"curvature", curvature_of(p)},
                          {"from", {source_of(p).x(), source_of(p).y()}},
                          {"to", {target_of(p).x(), target_of(p).y()}}};
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
