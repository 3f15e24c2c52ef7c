// The exact geometry of a 3-D shape as JSON: what `billiard info --json` prints and the Python
// module's `info` returns.
#include "billiards/geometry3/shape3_info.hpp"

#include "billiards/geometry/shape_info.hpp"

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
  auto info = geometry::common_info(shape.region.name, shape.region.origin.file, measures_of(shape.region),
                                    shape.parameters);
  info["holes"] = shape.region.holes.size();
  info["boundary"] = boundary_json(shape.region.outer);
  return info;
}

}  // namespace billiards::geometry3
