// Reading 2-D shape files (YAML).  The format is documented in docs/shapes.md.
#pragma once

#include "billiards/geometry/expression.hpp"
#include "billiards/geometry/pieces.hpp"

#include <map>
#include <string>

namespace billiards::geometry {

struct Shape {
  Region2 region;
  std::map<std::string, double> parameters;  // after overrides
  std::string description;                   // the file's leading comment block
};

/// Reads, builds and validates a shape file.  Throws InputError naming file and line.
Shape load_shape(const std::string& path, const Overrides& overrides = {});
/// Same, from text in memory; `name` stands for the file in error messages.
Shape parse_shape(const std::string& yaml_text, const std::string& name,
                  const Overrides& overrides = {});

}  // namespace billiards::geometry
