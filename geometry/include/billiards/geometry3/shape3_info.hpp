// The exact geometry of a 3-D shape as JSON; its keys are listed in docs/commands.md
// (`billiard info`).
#pragma once

#include "billiards/geometry3/shape3_file.hpp"

#include <nlohmann/json_fwd.hpp>

namespace billiards::geometry3 {

/// name, file, dimension, V, S, mean_free_path, boundary_tensor (3×3), bbox, parameters, holes,
/// boundary (kind polyhedron with faces, mesh with mesh_file, triangles, vertices, or sphere
/// with center, radius).
nlohmann::json shape_info(const Shape3& shape);

}  // namespace billiards::geometry3
