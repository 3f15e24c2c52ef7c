// libFuzzer target: the 2-D shape reader (YAML, expressions, pieces, CGAL validation).
// Any input must either give a shape or an InputError; anything else is a finding.
#include "billiards/geometry/shape_file.hpp"

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    billiards::geometry::parse_shape(std::string(reinterpret_cast<const char*>(data), size), "fuzz.yaml");
  } catch (const billiards::InputError&) {
  }
  return 0;
}
