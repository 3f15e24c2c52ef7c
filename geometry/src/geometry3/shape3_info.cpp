// The exact geometry of a 3-D shape as JSON: what `billiard info --json` prints and the Python
// module's `info` returns.
#include "billiards/geometry3/shape3_info.hpp"

#include <nlohmann/json.hpp>

namespace billiards::geometry3 {

namespace {

template <class V>
nlohmann::json vector_json(const V& p) {
  return {p(0), p(1), p(2)};
}

/// The outer wall: its kind and size.
nlohmann::json boundary_json(const Boundary3& outer) {
  return std::visit(
      [](const auto& b) -> nlohmann::json {
        using B = std::decay_t<decltype(b)>;
        if constexpr (std::is_same_v<B, ConvexPolyhedron>) return {{"kind", "polyhedron"}, {"faces", b.planes.size()}};
        else if constexpr (std::is_same_v<B, TriangleMesh>)
          return {{"kind", "mesh"}, {"mesh_file", b.file}, {"triangles", b.triangles.size()}, {"vertices", b.vertices.size()}};
        else return {{"kind", "sphere"}, {"center", vector_json(b.center)}, {"radius", b.radius}};
      },
      outer);
}

}  // namespace

nlohmann::json shape_info(const Shape3& shape) {
  const auto m = measures_of(shape.region);
  const auto& T = m.boundary_tensor;
  return {{"name", shape.region.name},
          {"file", shape.region.origin.file},
          {"dimension", 3},
          {"V", m.volume},
          {"S", m.surface},
          {"mean_free_path", geometry::mean_free_path(m)},
          {"boundary_tensor", {{T(0, 0), T(0, 1), T(0, 2)}, {T(1, 0), T(1, 1), T(1, 2)}, {T(2, 0), T(2, 1), T(2, 2)}}},
          {"bbox", {vector_json(m.bbox_lo), vector_json(m.bbox_hi)}},
          {"parameters", shape.parameters},
          {"holes", shape.region.holes.size()},
          {"boundary", boundary_json(shape.region.outer)}};
}

}  // namespace billiards::geometry3
