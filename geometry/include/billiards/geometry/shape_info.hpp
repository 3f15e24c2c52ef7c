// The exact geometry of a 2-D shape as JSON; its keys are listed in README.md ("billiard info
// --json keys").
#pragma once

#include "billiards/geometry/shape_file.hpp"

#include <nlohmann/json_fwd.hpp>

namespace billiards::geometry {

/// name, file, dimension, V, S, mean_free_path, boundary_tensor, bbox, parameters, holes, pieces.
nlohmann::json shape_info(const Shape& shape);

}  // namespace billiards::geometry
