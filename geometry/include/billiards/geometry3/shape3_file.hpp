// Reading 3-D shape files (YAML with `dimension: 3`).  The format is documented in docs/3d.md.
#pragma once

#include "billiards/geometry/expression.hpp"
#include "billiards/geometry3/region3.hpp"

#include <map>
#include <string>

namespace billiards::geometry3 {

struct Shape3 {
  Region3 region;
  std::map<std::string, double> parameters;  // after overrides
  std::string description;                   // the file's leading comment block
};

/// Reads, builds and validates a 3-D shape file.  Throws InputError naming file and line.
Shape3 load_shape3(const std::string& path, const Overrides& overrides = {});
/// Same, from text in memory; `name` stands for the file in error messages and mesh files
/// are found relative to `mesh_dir`, by default the folder of `name`.
Shape3 parse_shape3(const std::string& yaml_text, const std::string& name,
                    const Overrides& overrides = {}, const std::string& mesh_dir = {});
/// The `dimension` a shape file declares (2 when absent); throws InputError if unreadable.
int shape_dimension(const std::string& path);
/// The same for a shape file's text; `name` stands for the file in error messages.
int parse_shape_dimension(const std::string& yaml_text, const std::string& name);

}  // namespace billiards::geometry3
