// The exact geometry of a 2-D shape as JSON; its keys are listed in docs/commands.md
// (`billiard info`).
#pragma once

#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <map>
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace billiards::geometry {

/// name, file, dimension, V, S, mean_free_path, boundary_tensor, bbox, parameters, holes, pieces.
nlohmann::json shape_info(const Shape& shape);

/// The keys shared by 2-D and 3-D shapes: name, file, dimension, V, S, mean_free_path,
/// boundary_tensor (d×d), bbox ([lo, hi]), parameters.
nlohmann::json common_info(const std::string& name, const std::string& file, const Measures& m,
                           const std::map<std::string, double>& parameters);

}  // namespace billiards::geometry
