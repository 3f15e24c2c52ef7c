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

nlohmann::json shape_info(const Shape& shape) {
  const auto m = measures_of(shape.region);
  const auto& T = m.boundary_tensor;
  return {{"name", shape.region.name},
          {"file", shape.region.origin.file},
          {"dimension", m.dimension},
          {"V", m.volume},
          {"S", m.surface},
          {"mean_free_path", mean_free_path(m)},
          {"boundary_tensor", {{T(0, 0), T(0, 1)}, {T(1, 0), T(1, 1)}}},
          {"bbox", {{m.bbox_lo(0), m.bbox_lo(1)}, {m.bbox_hi(0), m.bbox_hi(1)}}},
          {"parameters", shape.parameters},
          {"holes", shape.region.holes.size()},
          {"pieces", pieces_json(shape.region)}};
}

}  // namespace billiards::geometry
